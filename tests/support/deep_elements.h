// Deep elements rendered apart (docs/deep.md), for the tests and the benchmark: a ball, the tree
// beside it and the ground, each ray-traced in closed form into a deep EXR of its own.
#pragma once
#include <functional>
#include <string>
#include <vector>

namespace obscura::test {

struct DeepSample {
    float z, zBack, r, g, b, a;  // colour premultiplied
};
// The samples along a ray from the origin (its forward component -1: t is the planar depth).
using DeepHit = std::function<std::vector<DeepSample>(const double ray[3])>;

constexpr double kDeepFovDeg = 40.0;

// The ray through pixel (x, y)'s centre of a width x height frame, horizontal FOV kDeepFovDeg,
// looking down -Z.
void deepRay(int x, int y, int width, int height, double ray[3]);

// A deep EXR (R, G, B, A, Z, ZBack, float) of what `hit` returns on every pixel's ray.
void writeDeepElement(const std::string& path, const DeepHit& hit, int width, int height);

// The ground y = -1: a point sample (an open surface), grey.
std::vector<DeepSample> deepGround(const double ray[3]);
// The ball: radius 0.5 on the ground at (0, -0.5, -5), a red solid (a volume sample).
std::vector<DeepSample> deepBall(const double ray[3]);
// An axis-aligned box lo .. hi of colour (r, g, b), a solid (a volume sample).
std::vector<DeepSample> deepBox(const double ray[3], const double lo[3], const double hi[3], float r, float g, float b);
// The tree: a green trunk, the box x 0.55..0.95, y -1..1.5, z -5.4..-4.6, 5 cm from the ball.
std::vector<DeepSample> deepTree(const double ray[3]);

// Per pixel, whether `hit` finds a surface whose world x passes `side` (any, when null).
std::vector<bool> deepCoverage(const DeepHit& hit, int width, int height,
                               const std::function<bool(double x)>& side = nullptr);

} // namespace obscura::test
