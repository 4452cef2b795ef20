// The surface the depth pass describes, as a triangle mesh in view space, for ray-traced AO
// (method rtao). Two triangles per 2 x 2 block of pixel centres; blocks are not joined across
// depth discontinuities, judged against the local slope; optionally extruded away from the
// eye so that thin objects occlude as solids of a given thickness.
#pragma once
#include "base/image.h"
#include "base/kernel_params.h"

#include <glm/glm.hpp>
#include <cstdint>
#include <vector>

namespace obscura::cpu {

// Per buffer texel: its surface point and normal, in view space (OpenGL camera, -Z ahead).
struct SurfacePoints {
    int width = 0, height = 0;
    std::vector<glm::vec3> position;
    std::vector<glm::vec3> normal;  // unit, facing the eye (bent as the kernels bend it)
    std::vector<float> w;           // 1 / planar depth (perspective) or planar depth (orthographic); 0: no surface
    bool surface(int i) const { return w[i] > 0.0f; }
};

// Two numbers in [0, 1) hashed from a display pixel, as the kernels hash it (kernels/common.glsl).
glm::vec2 pixelJitter(int displayX, int displayY);

SurfacePoints reconstructSurface(const glsl::KernelParams& p, ConstPlane depth, ConstPlane normal, int threads);

struct SurfaceMesh {
    std::vector<glm::vec3> vertices;       // the texels' points first (index = texel), then extruded copies
    std::vector<std::uint32_t> triangles;  // three indices each
};

// thickness 0: the sheet alone. Otherwise each triangle also gets a copy pushed `thickness`
// away from the eye, and the mesh's boundary edges are walled in between.
SurfaceMesh triangulateSurface(const SurfacePoints& s, bool orthographic, float thickness);

} // namespace obscura::cpu
