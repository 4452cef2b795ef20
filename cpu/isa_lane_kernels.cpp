// The lane kernels (HBAO, its border and deep input, SSAO) for one instruction set, compiled
// apart from the other kernels (cpu/isa_kernels.cpp, same OBSCURA_ISA and -march) so that a
// change to one family rebuilds only its own objects. Only the entry points have external
// linkage, in the ISA's namespace.
#include "cpu/lane_tile_impl.h"
