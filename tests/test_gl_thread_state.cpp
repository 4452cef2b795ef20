// A GL run leaves the calling thread's EGL state as it found it. An OpenFX host lends its own
// threads to a render and may draw on them with its own GL: under libglvnd a thread with an EGL
// context current cannot make a GLX one current, and the host's bound client API is its own.
#include "core/devices.h"
#include "core/operator.h"
#include "support/gl_devices.h"
#include "support/scenes.h"

#include <gtest/gtest.h>

#include <EGL/egl.h>
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

} // namespace
