// The deep reference (docs/deep.md): every surface along each pixel's primary ray, found by
// repeated Embree queries past each hit, written as a deep scanline EXR beside the flat one.
#pragma once
#include "camera.h"
#include "integrators.h"
#include "tracer.h"

#include <string>
#include <vector>

namespace reference {

// One solid the ray passes through: entered at `front`, left at `back` (planar depths, as the
// flat Depth pass). back == front where the ray never leaves it (an open surface, the ground).
// `colour`: what the surface where the ray enters radiates, DiffDir x DiffCol (Reference.GI's
// senders; the first span's is the flat render's DiffDir x DiffCol at that pixel).
struct DeepSpan {
    float front, back;
    glm::vec3 colour{0.0f};
};

struct DeepFrame {
    int width = 0, height = 0;
    bool coloured = false;                      // spans carry `colour`
    std::vector<std::vector<DeepSpan>> pixels;  // row-major, nearest first
};

// With `light`, each span's colour from its directDiffuse (giRays sky rays per span: the cost of
// a flat render's bounce rays per surface); without, primary rays only. maxHits bounds the queries
// per pixel (a ray grazing a tessellated surface may cross it often).
DeepFrame traceDeep(const Tracer& tracer, const PinholeCamera& camera, int threads, const Integrator* light = nullptr,
                    int maxHits = 64);

// A deep scanline EXR: per span one sample, A = 1, Z = front, ZBack = back (OpenEXR's volume
// sample form; a point sample where the two are equal), the display window of the flat render;
// when coloured, R, G, B too (premultiplied by A, as OpenEXR's deep samples are).
void writeDeep(const std::string& path, const DeepFrame& frame);

} // namespace reference
