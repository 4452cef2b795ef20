// The CPU kernels instantiated once per instruction set; cpu/CMakeLists.txt compiles this
// file several times with OBSCURA_ISA, OBSCURA_LANES and the matching -march.
// Nothing here may have external linkage but the `kernels` table (see cpu/isa.h).
#include "cpu/blur_tile_impl.h"
#include "cpu/discs_tile_impl.h"
#include "cpu/lane_tile_impl.h"
#include "cpu/ssdo_tile_impl.h"

namespace obscura::cpu::OBSCURA_ISA {
const IsaKernels kernels{&hbaoTile, &ssaoTile, &ssdoTile, &blurTile, &discsBaseTile, &discsTile, &hbaoDeepTile, &hbaoBorderTile};
} // namespace obscura::cpu::OBSCURA_ISA
