// The OpenGL 4.3 core entry points the GPU backend uses, loaded through the
// context's getProcAddress. Nothing links libGL: a machine without OpenGL still
// runs the CPU path, and OSMesa and EGL can coexist in one process.
#pragma once
#include <GL/glcorearb.h>

namespace obscura::gpu {

#define OBSCURA_GL_FUNCTIONS(X)                                                              \
    X(PFNGLGETSTRINGPROC, GetString)                                                         \
    X(PFNGLGETINTEGERVPROC, GetIntegerv)                                                     \
    X(PFNGLGETINTEGERI_VPROC, GetIntegeri_v)                                                 \
    X(PFNGLGETINTEGER64VPROC, GetInteger64v)                                                 \
    X(PFNGLGETERRORPROC, GetError)                                                           \
    X(PFNGLFINISHPROC, Finish)                                                               \
    X(PFNGLCREATESHADERPROC, CreateShader)                                                   \
    X(PFNGLSHADERSOURCEPROC, ShaderSource)                                                   \
    X(PFNGLCOMPILESHADERPROC, CompileShader)                                                 \
    X(PFNGLGETSHADERIVPROC, GetShaderiv)                                                     \
    X(PFNGLGETSHADERINFOLOGPROC, GetShaderInfoLog)                                           \
    X(PFNGLDELETESHADERPROC, DeleteShader)                                                   \
    X(PFNGLCREATEPROGRAMPROC, CreateProgram)                                                 \
    X(PFNGLATTACHSHADERPROC, AttachShader)                                                   \
    X(PFNGLLINKPROGRAMPROC, LinkProgram)                                                     \
    X(PFNGLGETPROGRAMIVPROC, GetProgramiv)                                                   \
    X(PFNGLGETPROGRAMINFOLOGPROC, GetProgramInfoLog)                                         \
    X(PFNGLDELETEPROGRAMPROC, DeleteProgram)                                                 \
    X(PFNGLUSEPROGRAMPROC, UseProgram)                                                       \
    X(PFNGLGENBUFFERSPROC, GenBuffers)                                                       \
    X(PFNGLDELETEBUFFERSPROC, DeleteBuffers)                                                 \
    X(PFNGLBINDBUFFERPROC, BindBuffer)                                                       \
    X(PFNGLBINDBUFFERBASEPROC, BindBufferBase)                                               \
    X(PFNGLBUFFERDATAPROC, BufferData)                                                       \
    X(PFNGLBUFFERSUBDATAPROC, BufferSubData)                                                 \
    X(PFNGLGETBUFFERSUBDATAPROC, GetBufferSubData)                                           \
    X(PFNGLDISPATCHCOMPUTEPROC, DispatchCompute)                                             \
    X(PFNGLMEMORYBARRIERPROC, MemoryBarrier)                                                 \
    X(PFNGLGETUNIFORMLOCATIONPROC, GetUniformLocation)                                       \
    X(PFNGLUNIFORM1IPROC, Uniform1i)                                                         \
    X(PFNGLUNIFORM2IPROC, Uniform2i)

struct GlApi {
#define OBSCURA_DECLARE_GL(type, name) type name = nullptr;
    OBSCURA_GL_FUNCTIONS(OBSCURA_DECLARE_GL)
#undef OBSCURA_DECLARE_GL

    // Loads every entry point; returns the name of the first one missing, or nullptr.
    const char* load(void* (*getProc)(const char*));
};

} // namespace obscura::gpu
