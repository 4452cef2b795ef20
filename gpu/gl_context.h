// Offscreen OpenGL contexts with no display: an EGL device (a headless GPU, or
// Mesa's software device) or OSMesa. Both are opened with dlopen, so nothing
// here is a link-time dependency.
#pragma once
#include "gpu/device_info.h"
#include "gpu/gl_api.h"

#include <memory>
#include <string>

namespace obscura::gpu {

enum class ContextKind { EglDevice, OSMesa };

class GlContext {
public:
    // Throws obscura::Error with one line saying why the context cannot be made.
    // preferHardware: with EGL, skip software devices (for --device auto).
    static std::unique_ptr<GlContext> create(ContextKind kind, bool hardwareOnly = false);
    virtual ~GlContext() = default;

    virtual void makeCurrent() = 0;
    const GlApi& gl() const { return gl_; }
    const ContextInfo& info() const { return info_; }

protected:
    void loadApi(void* (*getProc)(const char*), const char* backend);
    GlApi gl_;
    ContextInfo info_;
};

} // namespace obscura::gpu
