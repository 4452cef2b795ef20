// The lane kernels instantiated once per instruction set; cpu/CMakeLists.txt compiles this
// file several times with OBSCURA_ISA, OBSCURA_LANES and the matching -march.
// Nothing here may have external linkage but the entry points (see lane_tile_impl.h).
#include "cpu/lane_tile_impl.h"
