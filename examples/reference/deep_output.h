// The deep reference (docs/deep.md): every surface along each pixel's primary ray, found by
// repeated Embree queries past each hit, written as a deep scanline EXR beside the flat one.
#pragma once
#include "camera.h"
#include "tracer.h"

#include <string>
#include <vector>

namespace reference {

// One solid the ray passes through: entered at `front`, left at `back` (planar depths, as the
// flat Depth pass). back == front where the ray never leaves it (an open surface, the ground).
struct DeepSpan {
    float front, back;
};

struct DeepFrame {
    int width = 0, height = 0;
    std::vector<std::vector<DeepSpan>> pixels;  // row-major, nearest first
};

// maxHits bounds the queries per pixel (a ray grazing a tessellated surface may cross it often).
DeepFrame traceDeep(const Tracer& tracer, const PinholeCamera& camera, int threads, int maxHits = 64);

// A deep scanline EXR: per span one sample, A = 1, Z = front, ZBack = back (OpenEXR's volume
// sample form; a point sample where the two are equal), the display window of the flat render.
void writeDeep(const std::string& path, const DeepFrame& frame);

} // namespace reference
