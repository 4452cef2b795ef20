// Built instead of the OpenGL backend when its headers are missing: every GL device fails clearly.
#include "gpu/gl_backend.h"

#include "base/error.h"

namespace obscura::gpu {

class GlContext {
public:
    virtual ~GlContext() = default;
};
enum class ContextKind { EglDevice, OSMesa };

const ContextInfo& GlBackend::info() const {
    static const ContextInfo none;
    return none;
}
GlBackend::GlBackend(ContextKind, bool) { throw Error("this build of obscura has no OpenGL backend"); }
GlBackend::~GlBackend() = default;
void GlBackend::runAo(const char*, const glsl::KernelParams&, ConstPlane, ConstPlane, MutablePlane, int, GlTimings*,
                      long long) {}
void GlBackend::runSsdo(const glsl::KernelParams&, const SsdoInputs&, MutablePlane, MutablePlane, MutablePlane, int,
                        GlTimings*) {}
void GlBackend::runDiscs(const glsl::KernelParams&, const float*, size_t, ConstPlane, ConstPlane, MutablePlane, int,
                         GlTimings*) {}
void GlBackend::runDepthNormals(const glsl::KernelParams&, ConstPlane, MutablePlane, GlTimings*) {}
ThreadGlState::ThreadGlState() = default;
ThreadGlState::~ThreadGlState() = default;
GlBackend& glBackendFor(const std::string&) { throw Error("this build of obscura has no OpenGL backend"); }

} // namespace obscura::gpu
