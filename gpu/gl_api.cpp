#include "gl_api.h"

namespace obscura::gpu {

const char* GlApi::load(void* (*getProc)(const char*)) {
#define OBSCURA_LOAD_GL(type, name)                                  \
    name = reinterpret_cast<type>(getProc("gl" #name));              \
    if (!name) return "gl" #name;
    OBSCURA_GL_FUNCTIONS(OBSCURA_LOAD_GL)
#undef OBSCURA_LOAD_GL
    return nullptr;
}

} // namespace obscura::gpu
