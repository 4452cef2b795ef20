// Closed-form checks of the AO reference (--check):
//  - corner: a floor point at distance d from an infinite wall, c = d / R, has
//    uniform/none (1 + c) / 2, cosine/none 1/2 + (c sqrt(1 - c^2) + asin c) / pi,
//    and the linear-falloff forms integrated the same way;
//  - an open plane (ground points farther than R from anything else) has AO = 1,
//    on every scene with a ground at z = 0 (including the terrain's centimetre scale).
#pragma once
#include "render.h"

namespace reference {

// Prints the comparison; returns false if any check fails its tolerance.
bool runAnalyticChecks(const std::string& sceneName, const Frame& frame, const RenderSettings& settings,
                       const Scene& scene);

// The corner's four AO values at c = d / R (c >= 1: no occlusion).
std::array<double, kAoLayers> cornerAo(double c);

} // namespace reference
