// The CPU kernels instantiated once per instruction set; cpu/CMakeLists.txt compiles this
// file and cpu/isa_lane_kernels.cpp several times with OBSCURA_ISA, OBSCURA_LANES and the
// matching -march. Nothing here may have external linkage but the `kernels` table and the
// lane kernels' entry points (see cpu/isa.h), all in the ISA's own namespace.
#include "cpu/blur_tile_impl.h"
#include "cpu/depth_normal_tile_impl.h"
#include "cpu/discs_tile_impl.h"
#include "cpu/pack_tile_impl.h"
#include "cpu/ssdo_tile_impl.h"

namespace obscura::cpu::OBSCURA_ISA {
// Defined in cpu/isa_lane_kernels.cpp for the same ISA (the table's types check them).
void hbaoTile(const KernelParams& p, ConstPlane depth, ConstPlane normal, ConstPlane edges, MutablePlane ao,
              const Box2i& tile);
void ssaoTile(const KernelParams& p, ConstPlane depth, ConstPlane normal, MutablePlane ao, const Box2i& tile);
void hbaoDeepTile(const KernelParams& p, ConstPlane depth, ConstPlane normal, ConstPlane deep, ConstPlane edges,
                  MutablePlane ao, const Box2i& tile);
void hbaoGiTile(const KernelParams& p, ConstPlane depth, ConstPlane normal, ConstPlane deep, ConstPlane radiance,
                ConstPlane facing, ConstPlane edges, MutablePlane ao, MutablePlane gi, const Box2i& tile);

const IsaKernels kernels{&hbaoTile,      &ssaoTile,  &ssdoTile,        &blurTile,     &discsBaseTile,
                         &discsTile,     &depthNormalTile, &hbaoDeepTile, &hbaoGiTile,  &packSourceTile};
} // namespace obscura::cpu::OBSCURA_ISA
