// A lat-long environment map as obscura's SSDO reads it (kernels/ssdo.glsl, environmentRadiance;
// plugin/core/operator.cpp, viewToEnvironment), for the ground-truth directional occlusion layer.
#pragma once
#include "scene.h"

#include <glm/glm.hpp>

#include <functional>

#include <string>
#include <vector>

namespace reference {

struct EnvironmentMap {
    int width = 0, height = 0;
    std::vector<float> rgb;   // row-major, row 0 = top (v = 0, env +Y)
    double rotationDeg = 0;   // obscura's --env-rotate: about the up axis

    // RGB of a lat-long map file (first three channels; OpenImageIO). Throws on failure.
    static EnvironmentMap load(const std::string& path, double rotationDeg);
    // A width x height map (rotation 0) of radiance(world direction) at the texel centres: a scene's
    // analytic sky as the lat-long map obscura reads (--env sky).
    static EnvironmentMap fromFunction(int width, int height, const std::function<glm::vec3(const glm::dvec3&)>& radiance);

    // World (z up, the reference scenes') -> environment (y up) exactly as obscura with
    // --up z --env-rotate rotationDeg: env = spin(rotation) * (x, z, -y).
    glm::dvec3 worldToEnvironment(const glm::dvec3& world) const;
    // Bilinear lookup of the level-0 map in a world direction (wraps in longitude, clamps at the poles).
    glm::dvec3 radiance(const glm::dvec3& worldDir) const;
};

// The scene's analytic sky (Lighting::sky) as a 128 x 64 map: the lat-long map the report and
// `reference_render --env sky` give obscura's SSDO, so DO sees the sky the direct pass was lit by.
EnvironmentMap skyMap(const Lighting& lighting);
// Writes the map as an RGB float EXR (OpenImageIO). Throws on failure.
void writeEnvironment(const std::string& path, const EnvironmentMap& map);

} // namespace reference
