// Where the operator computes: the device names every host offers (one list, in the order the
// OpenFX node stores as its choice index) and what a name resolves to on this machine.
#pragma once
#include "settings.h"

#include <string>
#include <vector>

namespace obscura {
namespace gpu {
class GlBackend;
}

struct DeviceName {
    const char* name;     // "cpu", "auto", "gl", "gl-egl", "gl-osmesa"
    const char* meaning;  // one line, for --help and the node's hint
};
// In the node's choice order: hosts store the index, so names are only appended.
const std::vector<DeviceName>& deviceNames();
bool isDeviceName(const std::string& name);
// "cpu, auto, gl, gl-egl or gl-osmesa" (joined with `sep`, the last with `last`).
std::string deviceNameList(const char* sep = ", ", const char* last = " or ");

// What a device request resolves to here: the CPU or a GL context, and whether that context
// is a hardware GPU (what "auto" asks for), with the reasons a fallback was taken.
struct DeviceChoice {
    bool gl = false;                 // a GL backend, else the CPU
    bool hardware = false;           // a GL backend on a hardware GPU (not llvmpipe)
    std::string description;         // "cpu (N threads)", "gl-egl: <renderer>, OpenGL <version>"
    std::vector<std::string> notes;  // why "auto" fell back to the CPU
};
// Probes the device settings.device names (a GL context for any GL name). Throws
// obscura::Error for an unknown name or an explicit GL device that cannot be made.
DeviceChoice chooseDevice(const Settings& settings);

// For the operator: the GL backend `requested` asks for, or nullptr for the CPU. An explicit
// GL device that cannot be made throws; "auto" falls back to the CPU and says why in `notes`.
gpu::GlBackend* selectGlBackend(const std::string& requested, std::vector<std::string>& notes);
// "cpu (N threads)" or "<backend>: <renderer>, OpenGL <version>".
std::string deviceDescription(const gpu::GlBackend* gl, int threads);

} // namespace obscura
