// What the report compares: the registered methods, the devices, and the AO
// definitions (weighting + falloff) with the ray-traced layer each is measured against.
#pragma once
#include "core/settings.h"

#include <string>
#include <vector>

namespace report {

// Occlusion methods, by Settings::method name. A new method joins every table,
// chart and contact sheet by adding its name here (e.g. "ssdo").
inline const std::vector<std::string>& registeredMethods() {
    static const std::vector<std::string> methods = {
        "hbao",
    };
    return methods;
}

// Every device runOperator accepts that the report times (llvmpipe here for both GL ones).
inline const std::vector<std::string>& registeredDevices() {
    static const std::vector<std::string> devices = {"cpu", "gl-osmesa", "gl-egl"};
    return devices;
}

// An AO definition: obscura's weighting and falloff, and the reference layer that
// computes the same integral ("cosine_none" -> Reference.AO_cosine_none.Y).
struct AoDefinition {
    std::string name;              // "cosine_none"
    obscura::Weighting weighting;
    obscura::Falloff falloff;
    int referenceLayer;            // reference::AoLayer
    std::string exrLayer() const { return "Reference.AO_" + name; }
};

// "uniform_linear", "uniform_none", "cosine_linear", "cosine_none"; false for anything else.
bool parseDefinition(const std::string& name, AoDefinition& out);

} // namespace report
