// The roof scene of the deep tests (tests/test_deep.cpp, tests/test_hbao_deep_gi.cpp): a solid
// hidden under a roof, which only deep input shows.
#pragma once
#include "core/operator.h"

#include <cmath>
#include <limits>

namespace obscura::test {

// Top-down orthographic view of a floor (camera-space normals facing the camera, depth 10):
// over the right half, a roof plate at height `roof` hides a solid block of height `block`
// standing on the floor. Layer 0 is what the camera sees; the block is layer 1 (a span from
// its top down to the floor), seen only through the deep input.
struct RoofScene {
    static constexpr int W = 320, H = 96;
    static constexpr double kPixelsPerUnit = 32.0;
    Image depth{W, H, 1}, normal{W, H, 3}, deep{W, H, 4};
    Camera camera = Camera::orthographic(W / kPixelsPerUnit, W, H);
    RoofScene(float roof, float block) {
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) {
                const bool covered = x >= W / 2;
                *depth.at(x, y) = covered ? 10.0f - roof : 10.0f;
                float* n = normal.at(x, y);
                n[0] = 0, n[1] = 0, n[2] = 1;
                float* d = deep.at(x, y);
                d[0] = d[1] = *depth.at(x, y);
                d[2] = covered ? 10.0f - block : std::numeric_limits<float>::infinity();
                d[3] = covered ? 10.0f : std::numeric_limits<float>::infinity();
            }
    }
    OperatorInputs inputs(bool withDeep) const {
        OperatorInputs in;
        in.displayWindow = in.dataWindow = Box2i{0, 0, W, H};
        in.depth = depth.view();
        in.normal = normal.view();
        in.normalSpace = NormalSpace::Camera;
        in.camera = camera;
        if (withDeep) in.deepLayers = deep.view();
        return in;
    }
    // Mean AO of the floor column at distance `units` left of the block's face, over the rows
    // more than R (32 pixels) from the frame's top and bottom, whose samples all stay inside.
    static double columnMean(const Image& ao, double units) {
        const int x = W / 2 - 1 - (int)std::lround(units * kPixelsPerUnit - 0.5);
        double sum = 0;
        for (int y = 40; y < H - 40; ++y) sum += *ao.at(x, y);
        return sum / (H - 80);
    }
};

} // namespace obscura::test
