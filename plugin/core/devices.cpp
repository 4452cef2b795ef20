#include "devices.h"

#include "base/error.h"
#include "core/backend_cpu.h"
#include "core/backend_gl.h"
#include "cpu/parallel.h"
#include "gpu/gl_backend.h"

namespace obscura {

const std::vector<DeviceName>& deviceNames() {
    static const std::vector<DeviceName> names = {
        {"cpu", "the CPU's SIMD lanes on every core"},
        {"auto", "a hardware GPU through EGL if there is one, else the CPU"},
        {"gl", "OpenGL through EGL, else OSMesa"},
        {"gl-egl", "OpenGL on an EGL device"},
        {"gl-osmesa", "OpenGL in Mesa's off-screen software renderer"},
    };
    return names;
}

bool isDeviceName(const std::string& name) {
    for (const DeviceName& d : deviceNames())
        if (name == d.name) return true;
    return false;
}

std::string deviceNameList(const char* sep, const char* last) {
    std::string list;
    const auto& names = deviceNames();
    for (size_t i = 0; i < names.size(); ++i)
        list += (i == 0 ? "" : i + 1 == names.size() ? last : sep) + std::string(names[i].name);
    return list;
}

gpu::GlBackend* selectGlBackend(const std::string& requested, std::vector<std::string>& notes) {
    const std::string device = requested.empty() ? "cpu" : requested;
    if (!isDeviceName(device)) throw Error("unknown device '" + device + "' (" + deviceNameList(", ", ", ") + ")");
    if (device == "cpu") return nullptr;
    if (device != "auto") return &gpu::glBackendFor(device);
    // auto means "a real GPU if there is one": a software GL would be slower than the CPU path.
    try {
        return &gpu::glBackendFor("gl-egl-hardware");
    } catch (const Error& e) {
        notes.push_back(std::string("--device auto: ") + e.what() + "; using the CPU");
        return nullptr;
    }
}

std::string deviceDescription(const gpu::GlBackend* gl, int threads) {
    if (!gl) return "cpu (" + std::to_string(threads) + " threads)";
    return gl->info().backend + ": " + gl->info().renderer + ", OpenGL " + gl->info().version;
}

DeviceChoice chooseDevice(const Settings& s) {
    const gpu::ThreadGlState callersGl;  // probing makes a context current: not left so
    DeviceChoice c;
    const gpu::GlBackend* gl = selectGlBackend(s.device, c.notes);
    c.gl = gl != nullptr;
    c.hardware = gl && !gl->info().software;
    c.description = deviceDescription(gl, cpu::resolveThreads(s.threads));
    return c;
}

std::unique_ptr<Backend> chooseBackend(const Settings& s, bool methodRunsOnGl, int threads,
                                       std::vector<std::string>& notes) {
    gpu::GlBackend* gl = selectGlBackend(s.device, notes);
    if (gl && !methodRunsOnGl) {
        if (s.device != "auto") throw Error("--method " + s.method + " runs on the CPU only; use --device cpu");
        notes.push_back("--device auto: --method " + s.method + " runs on the CPU only");
        gl = nullptr;
    }
    return gl ? makeGlBackend(*gl) : makeCpuBackend(threads);
}

} // namespace obscura
