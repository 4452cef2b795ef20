// A GL run leaves the calling thread's EGL state as it found it. An OpenFX host lends its own
// threads to a render and may draw on them with its own GL: under libglvnd a thread with an EGL
// context current cannot make a GLX one current, and the host's bound client API is its own.
#include "core/devices.h"
#include "core/operator.h"
#include "support/gl_devices.h"
#include "support/scenes.h"

#include <gtest/gtest.h>

#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <dlfcn.h>

#include <algorithm>
#include <string>

using namespace obscura;
using namespace obscura::test;

namespace {

struct Egl {
    void* lib = dlopen("libEGL.so.1", RTLD_NOW | RTLD_NOLOAD);
    template <class F>
    F get(const char* name) const {
        return lib ? reinterpret_cast<F>(dlsym(lib, name)) : nullptr;
    }
    ~Egl() {
        if (lib) dlclose(lib);
    }
};

TEST(GlThreadState, ARunLeavesNoContextCurrentAndTheApiAsItWas) {
    const std::vector<std::string> devices = glDevicesUnderTest();
    if (std::find(devices.begin(), devices.end(), "gl-egl") == devices.end()) GTEST_SKIP() << "gl-egl not under test";
    const SceneBuffers scene = renderScene(studioScene(), studioCamera(96, 64), 96, 64);
    for (const char* method : {"hbao", "ssdo"}) {
        Settings s;
        s.method = method;
        s.device = "gl-egl";
        s.radius = 0.8f;
        const OperatorOutputs out = runOperator(scene.inputs(), s);
        ASSERT_EQ(out.stats.device.rfind("gl-egl", 0), 0u) << out.stats.device;
        const Egl egl;  // the run loaded libEGL
        ASSERT_NE(egl.lib, nullptr);
        const auto current = egl.get<EGLContext (*)()>("eglGetCurrentContext");
        const auto api = egl.get<EGLenum (*)()>("eglQueryAPI");
        const auto bind = egl.get<EGLBoolean (*)(EGLenum)>("eglBindAPI");
        EXPECT_EQ(api(), (EGLenum)EGL_OPENGL_ES_API) << method << ": EGL's default, as the thread had it";
        EXPECT_EQ(current(), EGL_NO_CONTEXT) << method;
        ASSERT_TRUE(bind(EGL_OPENGL_API));
        EXPECT_EQ(current(), EGL_NO_CONTEXT) << method << ": obscura's OpenGL context is released";
        ASSERT_TRUE(bind(EGL_OPENGL_ES_API));
    }
    // So is a device probe's.
    Settings probe;
    probe.device = "gl-egl";
    EXPECT_TRUE(chooseDevice(probe).gl);
    const Egl egl;
    EXPECT_EQ(egl.get<EGLContext (*)()>("eglGetCurrentContext")(), EGL_NO_CONTEXT);
}

// A host with its own context current (OpenGL ES bound, a pbuffer surface, on Mesa's surfaceless
// platform): after a GL run its context, surface and API are current again.
TEST(GlThreadState, AHostsOwnContextIsCurrentAgain) {
    const std::vector<std::string> devices = glDevicesUnderTest();
    if (std::find(devices.begin(), devices.end(), "gl-egl") == devices.end()) GTEST_SKIP() << "gl-egl not under test";
    void* lib = dlopen("libEGL.so.1", RTLD_NOW);
    ASSERT_NE(lib, nullptr);
    auto proc = reinterpret_cast<PFNEGLGETPROCADDRESSPROC>(dlsym(lib, "eglGetProcAddress"));
    auto platformDisplay = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(proc("eglGetPlatformDisplayEXT"));
    const EGLDisplay display = platformDisplay ? platformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr)
                                               : EGL_NO_DISPLAY;
    auto initialize = reinterpret_cast<PFNEGLINITIALIZEPROC>(proc("eglInitialize"));
    EGLint major = 0, minor = 0;
    if (display == EGL_NO_DISPLAY || !initialize(display, &major, &minor)) GTEST_SKIP() << "no surfaceless EGL platform";
    auto choose = reinterpret_cast<PFNEGLCHOOSECONFIGPROC>(proc("eglChooseConfig"));
    auto pbuffer = reinterpret_cast<PFNEGLCREATEPBUFFERSURFACEPROC>(proc("eglCreatePbufferSurface"));
    auto bind = reinterpret_cast<PFNEGLBINDAPIPROC>(proc("eglBindAPI"));
    auto create = reinterpret_cast<PFNEGLCREATECONTEXTPROC>(proc("eglCreateContext"));
    auto makeCurrent = reinterpret_cast<PFNEGLMAKECURRENTPROC>(proc("eglMakeCurrent"));
    auto current = reinterpret_cast<PFNEGLGETCURRENTCONTEXTPROC>(proc("eglGetCurrentContext"));
    auto surface = reinterpret_cast<PFNEGLGETCURRENTSURFACEPROC>(proc("eglGetCurrentSurface"));
    auto api = reinterpret_cast<PFNEGLQUERYAPIPROC>(proc("eglQueryAPI"));
    const EGLint wanted[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE, EGL_OPENGL_ES2_BIT, EGL_NONE};
    EGLConfig config = nullptr;
    EGLint found = 0;
    if (!choose(display, wanted, &config, 1, &found) || found == 0) GTEST_SKIP() << "no pbuffer config";
    const EGLint size[] = {EGL_WIDTH, 16, EGL_HEIGHT, 16, EGL_NONE};
    const EGLSurface hostSurface = pbuffer(display, config, size);
    ASSERT_TRUE(bind(EGL_OPENGL_ES_API));
    const EGLint es2[] = {EGL_CONTEXT_CLIENT_VERSION, 2, EGL_NONE};
    const EGLContext host = create(display, config, EGL_NO_CONTEXT, es2);
    ASSERT_TRUE(host != EGL_NO_CONTEXT && makeCurrent(display, hostSurface, hostSurface, host));
    const SceneBuffers scene = renderScene(studioScene(), studioCamera(64, 48), 64, 48);
    Settings s;
    s.device = "gl-egl";
    for (int run = 0; run < 2; ++run) {
        const OperatorOutputs out = runOperator(scene.inputs(), s);
        ASSERT_EQ(out.stats.device.rfind("gl-egl", 0), 0u) << out.stats.device;
        EXPECT_EQ(api(), (EGLenum)EGL_OPENGL_ES_API) << run;
        EXPECT_EQ(current(), host) << run;
        EXPECT_EQ(surface(EGL_DRAW), hostSurface) << run;
    }
    makeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
}

} // namespace
