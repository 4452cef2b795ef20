// The HBAO kernel instantiated for x86-64-v3 (AVX2, FMA, BMI2): CMakeLists.txt compiles
// this file alone with -march=x86-64-v3; runHbao() calls it only on CPUs that have those.
// Nothing here may have external linkage but the entry point (see hbao_tile_impl.h).
#if defined(OBSCURA_HAVE_X86_64_V3)
#define OBSCURA_ISA x86_64_v3
#include "cpu/hbao_tile_impl.h"
#endif
