#include "gpu/gl_context.h"

#include "gpu/gl_backend.h"

#include "base/error.h"

#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/osmesa.h>
#include <dlfcn.h>

#include <cstring>
#include <mutex>
#include <vector>

namespace obscura::gpu {

namespace {

// dlopen a library, trying each soname; throws with the reason when none loads.
void* openLibrary(std::initializer_list<const char*> names, const char* what) {
    std::string why;
    for (const char* n : names) {
        if (void* h = dlopen(n, RTLD_NOW | RTLD_LOCAL)) return h;
        why = dlerror();
    }
    throw Error(std::string(what) + " is not available (" + why + ")");
}

template <class F>
F symbol(void* lib, const char* name) {
    return reinterpret_cast<F>(dlsym(lib, name));
}

bool hasExtension(const char* list, const char* ext) {
    if (!list) return false;
    const size_t n = std::strlen(ext);
    for (const char* p = std::strstr(list, ext); p; p = std::strstr(p + 1, ext))
        if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
    return false;
}

// ---- EGL on a device (EGL_EXT_device_enumeration + EGL_EXT_platform_device), surfaceless ----
PFNEGLGETPROCADDRESSPROC g_eglGetProcAddress = nullptr;
void* eglProc(const char* name) { return reinterpret_cast<void*>(g_eglGetProcAddress(name)); }

class EglContext : public GlContext {
public:
    explicit EglContext(bool hardwareOnly) {
        lib_ = openLibrary({"libEGL.so.1", "libEGL.so"}, "EGL");
        g_eglGetProcAddress = symbol<PFNEGLGETPROCADDRESSPROC>(lib_, "eglGetProcAddress");
        if (!g_eglGetProcAddress) throw Error("EGL: eglGetProcAddress missing");
        auto queryString = reinterpret_cast<PFNEGLQUERYSTRINGPROC>(eglProc("eglQueryString"));
        auto queryDevices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglProc("eglQueryDevicesEXT"));
        auto queryDeviceString = reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(eglProc("eglQueryDeviceStringEXT"));
        auto getPlatformDisplay = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglProc("eglGetPlatformDisplayEXT"));
        initialize_ = reinterpret_cast<PFNEGLINITIALIZEPROC>(eglProc("eglInitialize"));
        auto bindApi = reinterpret_cast<PFNEGLBINDAPIPROC>(eglProc("eglBindAPI"));
        auto createContext = reinterpret_cast<PFNEGLCREATECONTEXTPROC>(eglProc("eglCreateContext"));
        makeCurrent_ = reinterpret_cast<PFNEGLMAKECURRENTPROC>(eglProc("eglMakeCurrent"));
        const char* clientExt = queryString ? queryString(EGL_NO_DISPLAY, EGL_EXTENSIONS) : nullptr;
        if (!queryDevices || !getPlatformDisplay || !hasExtension(clientExt, "EGL_EXT_platform_device"))
            throw Error("EGL: no device platform (EGL_EXT_device_enumeration / EGL_EXT_platform_device)");

        EGLint count = 0;
        std::vector<EGLDeviceEXT> devices(16);
        if (!queryDevices((EGLint)devices.size(), devices.data(), &count) || count == 0)
            throw Error("EGL: no devices found");
        devices.resize(count);
        // Hardware devices first; Mesa's software device only when hardware is not required.
        std::string why = "EGL: no usable device";
        for (int pass = 0; pass < 2 && display_ == EGL_NO_DISPLAY; ++pass) {
            for (EGLDeviceEXT dev : devices) {
                const char* devExt = queryDeviceString ? queryDeviceString(dev, EGL_EXTENSIONS) : nullptr;
                const bool software = hasExtension(devExt, "EGL_MESA_device_software");
                if (software != (pass == 1)) continue;
                if (software && hardwareOnly) {
                    why = "EGL: only a software device is present";
                    continue;
                }
                EGLDisplay dpy = getPlatformDisplay(EGL_PLATFORM_DEVICE_EXT, dev, nullptr);
                EGLint major = 0, minor = 0;
                if (dpy == EGL_NO_DISPLAY || !initialize_(dpy, &major, &minor)) continue;
                const char* dpyExt = queryString(dpy, EGL_EXTENSIONS);
                if (!hasExtension(dpyExt, "EGL_KHR_surfaceless_context") || !hasExtension(dpyExt, "EGL_KHR_no_config_context")) {
                    why = "EGL: device lacks surfaceless / no-config contexts";
                    continue;
                }
                if (!bindApi(EGL_OPENGL_API)) continue;
                const EGLint attribs[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 3,
                                          EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
                EGLContext ctx = createContext(dpy, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attribs);
                if (ctx == EGL_NO_CONTEXT) {
                    why = "EGL: the device cannot create an OpenGL 4.3 core context";
                    continue;
                }
                display_ = dpy;
                context_ = ctx;
                info_.software = software;
            }
        }
        if (display_ == EGL_NO_DISPLAY) throw Error(why);
        bindApi_ = bindApi;
        makeCurrent();
        loadApi(&eglProc, "gl-egl");
    }
    void makeCurrent() override {
        // The thread's bound API may have been put back to its owner's since (ThreadGlState).
        if (!bindApi_(EGL_OPENGL_API) || !makeCurrent_(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_))
            throw Error("EGL: eglMakeCurrent failed");
    }

private:
    void* lib_ = nullptr;  // kept loaded for the process lifetime: drivers do not unload cleanly
    PFNEGLINITIALIZEPROC initialize_ = nullptr;
    PFNEGLBINDAPIPROC bindApi_ = nullptr;
    PFNEGLMAKECURRENTPROC makeCurrent_ = nullptr;
    EGLDisplay display_ = EGL_NO_DISPLAY;
    EGLContext context_ = EGL_NO_CONTEXT;
};

// ---- OSMesa: Mesa's software renderer (llvmpipe), OpenGL 4.5 core, no display at all ----
using OSMesaGetProcAddressFn = OSMESAproc (*)(const char*);
OSMesaGetProcAddressFn g_osmesaGetProcAddress = nullptr;
void* osmesaProc(const char* name) { return reinterpret_cast<void*>(g_osmesaGetProcAddress(name)); }

class OsMesaContext : public GlContext {
public:
    OsMesaContext() {
        lib_ = openLibrary({"libOSMesa.so.8", "libOSMesa.so.6", "libOSMesa.so"}, "OSMesa");
        auto create = symbol<OSMesaContext (*)(const int*, OSMesaContext)>(lib_, "OSMesaCreateContextAttribs");
        makeCurrent_ = symbol<GLboolean (*)(OSMesaContext, void*, GLenum, GLsizei, GLsizei)>(lib_, "OSMesaMakeCurrent");
        g_osmesaGetProcAddress = symbol<OSMesaGetProcAddressFn>(lib_, "OSMesaGetProcAddress");
        if (!create || !makeCurrent_ || !g_osmesaGetProcAddress) throw Error("OSMesa: entry points missing");
        const int attribs[] = {OSMESA_FORMAT, OSMESA_RGBA, OSMESA_DEPTH_BITS, 0, OSMESA_PROFILE, OSMESA_CORE_PROFILE,
                               OSMESA_CONTEXT_MAJOR_VERSION, 4, OSMESA_CONTEXT_MINOR_VERSION, 5, 0};
        context_ = create(attribs, nullptr);
        if (!context_) throw Error("OSMesa: cannot create an OpenGL 4.5 core context");
        makeCurrent();
        loadApi(&osmesaProc, "gl-osmesa");
        info_.software = true;
    }
    void makeCurrent() override {
        // OSMesa needs a colour buffer to make a context current; compute never touches it.
        if (!makeCurrent_(context_, pixel_, GL_UNSIGNED_BYTE, 1, 1)) throw Error("OSMesa: OSMesaMakeCurrent failed");
    }

private:
    void* lib_ = nullptr;
    GLboolean (*makeCurrent_)(OSMesaContext, void*, GLenum, GLsizei, GLsizei) = nullptr;
    OSMesaContext context_ = nullptr;
    unsigned char pixel_[4] = {0, 0, 0, 0};
};

// libEGL's entry points the thread's state is read and put back with, when the process has it.
struct EglState {
    PFNEGLGETCURRENTDISPLAYPROC display = nullptr;
    PFNEGLGETCURRENTSURFACEPROC surface = nullptr;
    PFNEGLGETCURRENTCONTEXTPROC context = nullptr;
    PFNEGLQUERYAPIPROC queryApi = nullptr;
    PFNEGLBINDAPIPROC bindApi = nullptr;
    PFNEGLMAKECURRENTPROC makeCurrent = nullptr;
};

// Null where libEGL is not loaded: then no EGL context can be current. Once found, the library
// is held open (never closed), so the entry points kept stay valid whatever the host unloads.
const EglState* eglState() {
    static void* held = nullptr;
    static std::mutex holding;
    void* lib = nullptr;
    {
        std::lock_guard<std::mutex> lock(holding);
        if (!held) held = dlopen("libEGL.so.1", RTLD_NOW | RTLD_NOLOAD);
        lib = held;
    }
    if (!lib) return nullptr;
    static const EglState state = [lib] {
        EglState s;
        s.display = symbol<PFNEGLGETCURRENTDISPLAYPROC>(lib, "eglGetCurrentDisplay");
        s.surface = symbol<PFNEGLGETCURRENTSURFACEPROC>(lib, "eglGetCurrentSurface");
        s.context = symbol<PFNEGLGETCURRENTCONTEXTPROC>(lib, "eglGetCurrentContext");
        s.queryApi = symbol<PFNEGLQUERYAPIPROC>(lib, "eglQueryAPI");
        s.bindApi = symbol<PFNEGLBINDAPIPROC>(lib, "eglBindAPI");
        s.makeCurrent = symbol<PFNEGLMAKECURRENTPROC>(lib, "eglMakeCurrent");
        return s;
    }();
    const EglState* s = &state;
    return s->display && s->surface && s->context && s->queryApi && s->bindApi && s->makeCurrent ? s : nullptr;
}

} // namespace

ThreadGlState::ThreadGlState() {
    const EglState* egl = eglState();
    eglLoaded_ = egl != nullptr;
    if (!egl) return;
    api_ = egl->queryApi();
    display_ = egl->display();
    draw_ = egl->surface(EGL_DRAW);
    read_ = egl->surface(EGL_READ);
    context_ = egl->context();
}

ThreadGlState::~ThreadGlState() {
    const EglState* egl = eglState();
    if (!egl || (eglLoaded_ && egl->queryApi() == api_ && egl->context() == context_)) return;  // untouched
    // Release whatever obscura made current for its API, then put the owner's back.
    if (egl->bindApi(EGL_OPENGL_API) && egl->context() != EGL_NO_CONTEXT && egl->context() != context_)
        egl->makeCurrent(egl->display(), EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    egl->bindApi(eglLoaded_ && api_ != 0 ? api_ : EGL_OPENGL_ES_API);  // EGL's default API
    if (eglLoaded_ && context_ != EGL_NO_CONTEXT) egl->makeCurrent(display_, draw_, read_, context_);
}

void GlContext::loadApi(void* (*getProc)(const char*), const char* backend) {
    if (const char* missing = gl_.load(getProc)) throw Error(std::string(backend) + ": OpenGL entry point " + missing + " missing");
    info_.backend = backend;
    auto str = [&](GLenum e) {
        const GLubyte* s = gl_.GetString(e);
        return s ? std::string(reinterpret_cast<const char*>(s)) : std::string();
    };
    info_.renderer = str(GL_RENDERER);
    info_.version = str(GL_VERSION);
    info_.vendor = str(GL_VENDOR);
    GLint64 block = 0;
    gl_.GetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &block);
    info_.maxStorageBlockBytes = block;
    gl_.GetIntegerv(GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS, &info_.maxStorageBindings);
    gl_.GetIntegeri_v(GL_MAX_COMPUTE_WORK_GROUP_COUNT, 0, &info_.maxWorkGroups[0]);
    gl_.GetIntegeri_v(GL_MAX_COMPUTE_WORK_GROUP_COUNT, 1, &info_.maxWorkGroups[1]);
    if (info_.renderer.find("llvmpipe") != std::string::npos || info_.renderer.find("softpipe") != std::string::npos)
        info_.software = true;
}

std::unique_ptr<GlContext> GlContext::create(ContextKind kind, bool hardwareOnly) {
    if (kind == ContextKind::EglDevice) return std::make_unique<EglContext>(hardwareOnly);
    return std::make_unique<OsMesaContext>();
}

} // namespace obscura::gpu
