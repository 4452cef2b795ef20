// What the report compares: the registered methods, the devices, and the AO
// definitions (weighting + falloff) with the ray-traced layer each is measured against.
#pragma once
#include "core/settings.h"

#include <string>
#include <vector>

namespace report {

// The report's method variants: every AO method of obscura's method table (core/methods.h) by
// its name, so a new method joins every table, chart and contact sheet on registration; plus
//   "hbao+horizon" hbao with an infinite thickness and open sky past the edge (before --thickness and --border)
//   "hbao+open", "hbao+clamp"  hbao with --border open / clamp (the default is tangent)
//   "hbao+deep"    hbao with the scene's deep render as --flat input
//   "hbao+bounce", "hbao+deep+bounce"  hbao --bounce (senders DiffDir x DiffCol), flat or with the deep
//                  render, whose hidden layers radiate their deep colour
//   "rtao+sheet"   rtao without extrusion (--thickness 0)
//   "rtao+thick"   rtao with every surface extruded by R / 5 (--thickness)
//   "ssdo"         SSDO: DO + AO, no bounce; interleave 2 with its automatic 2 px blur
//   "ssdo+bounce"  the same with the one-bounce GI (sender radiance DiffDir x DiffCol)
//   "ssdo-noint"   SSDO without interleaving: interleave 1, no blur
const std::vector<std::string>& registeredMethods();

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

// True for the report's SSDO variants ("ssdo", "ssdo+bounce", "ssdo-noint").
bool isSsdoMethod(const std::string& method);
// True when the method computes the one-bounce GI (its rows also measure GI): a "+bounce" variant
// ("ssdo+bounce", "hbao+bounce"), or a method of the table with a "gi" output and no "ao" one.
bool hasBounce(const std::string& method);
// True when the method writes directional occlusion (its rows also measure DO): SSDO's variants.
bool hasDirectional(const std::string& method);
// hasBounce or hasDirectional: the method runs under the scene's lights (sky map, sun, DiffDir x DiffCol).
bool isLit(const std::string& method);
// hbao+deep, hbao+deep+bounce: hbao with the scene's deep reference as extra layers (docs/deep.md);
// the bounce variant also reads the layers' colours (the hidden surfaces' light).
bool usesDeep(const std::string& method);
// True when `test` holds for one of `methods` (e.g. anyMethod(o.methods, isSsdoMethod)).
bool anyMethod(const std::vector<std::string>& methods, bool (*test)(const std::string&));
// SSDO sample count N per preset, from the method table (--quality): low 16, medium 64, high 256,
// ultra 1024 (0 for an unknown name).
int ssdoSamplesForPreset(const std::string& preset);
// The operator's method a report variant runs ("rtao+thick" -> "rtao", "hbao+clamp" -> "hbao").
std::string operatorMethod(const std::string& method);
// Settings for `method` at `preset`, after s.radius is set: AO methods take the quality preset as it is; the SSDO variants take
// ssdoSamplesForPreset, interleave 2 and blur 0 (the operator's automatic blur as wide as the block),
// or interleave 1 and no blur for "ssdo-noint". Sets `s.method` to the operator's name.
void configureMethod(const std::string& method, const std::string& preset, obscura::Settings& s);
// The AO definition a method is compared under: the report's `chosen` one for HBAO, cosine_linear for
// SSDO (cosine-distributed directions, points uniform along each: linear falloff by construction).
AoDefinition definitionFor(const std::string& method, const AoDefinition& chosen);

} // namespace report
