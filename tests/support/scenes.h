// Analytic test scenes: rectangles ray-cast at pixel centres into exact
// depth / normal / position planes, through the same camera conventions as obscura.
#pragma once
#include "core/camera.h"
#include "base/image.h"
#include "core/operator.h"

#include <glm/glm.hpp>
#include <string>
#include <utility>
#include <vector>

namespace obscura::test {

// Points origin + a*u + b*v for a, b in [0, 1]; an infinite plane is a huge rectangle.
struct Rect {
    glm::dvec3 origin, u, v;
};

struct SceneBuffers {
    Box2i display, data;
    Image depth, normal, position;  // depth planar (or radial); normal/position world space
    Camera camera;
    DepthKind depthKind = DepthKind::Planar;
    NormalSpace normalSpace = NormalSpace::World;

    OperatorInputs inputs() const;   // views of these buffers, world normals
    // Pixel (data-window coordinates) where a world point projects; returns false if outside.
    bool pixelOf(const glm::dvec3& world, int& x, int& y) const;
};

// Camera at `eye` looking at `target` (OpenGL convention), +Y up.
Camera lookAtPerspective(glm::dvec3 eye, glm::dvec3 target, double hfovRad, int width, int height);
Camera lookAtOrthographic(glm::dvec3 eye, glm::dvec3 target, double orthoWidth, int width, int height);

// Ray-casts the rectangles. `data` may be larger than the display (overscan) or offset.
SceneBuffers renderScene(const std::vector<Rect>& rects, const Camera& cam, Box2i display, Box2i data,
                         DepthKind depthKind = DepthKind::Planar, float skyDepth = 1e10f);
inline SceneBuffers renderScene(const std::vector<Rect>& rects, const Camera& cam, int width, int height) {
    return renderScene(rects, cam, Box2i{0, 0, width, height}, Box2i{0, 0, width, height});
}

// Appends the six faces of the axis-aligned box [lo, hi].
void addBox(std::vector<Rect>& rects, glm::dvec3 lo, glm::dvec3 hi);
// A floor, two walls meeting in a corner and a few boxes: creases, contact shadows,
// silhouettes and sky, for tests that want a bit of everything. Seen by studioCamera().
std::vector<Rect> studioScene();
// A 90-degree corner: the floor y = 0 for x <= 0 and the wall x = 0 for y >= 0, 1e3 each way
// (the closed form is tests/support/closed_forms.h cornerAo).
std::vector<Rect> cornerScene();
Camera studioCamera(int width, int height);
// The benchmarks' frame (tests/bench): a room corner open to the sky on the right and above:
// floor, back and left walls, boxes of several sizes (some stacked, some touching walls), a
// tilted slab. Seen by benchRoomCamera().
std::vector<Rect> benchRoomScene();
Camera benchRoomCamera(int width, int height);

// A square well: floor y = 0 over [-a, a]^2, four walls up to y = h, ground y = h outside (a
// furnace for GI: the closed form is closed_forms.h's wellIrradiance).
std::vector<Rect> wellScene(double a, double h);
// A bounce source of radiance `value` (grey) on every surface texel.
Image uniformRadiance(const SceneBuffers& sb, float value);

// The rectangle of a plane through `point` spanned by unit vectors s, t, `half` units each way.
Rect planeRect(glm::dvec3 point, glm::dvec3 s, glm::dvec3 t, double half = 1e4);

// The tests' view of cornerScene(): the floor beside the wall, the corner line across the frame.
Camera cornerCamera(int width, int height);
// Mean of `ao` over the floor pixels on the line at distance d from cornerScene()'s wall
// (x = -d, z in [-1, 1] every 0.05); a point outside the frame fails the running test.
double meanOnCornerLine(const SceneBuffers& sb, const Image& ao, double d);

// Mean |cropped - whole| over the surface pixels of `full` within `band` pixels of the edge of
// `crop` (cropped: the AO of the frame cut there; whole: of the full frame); *pixels: how many.
double meanEdgeBandError(const SceneBuffers& full, const Image& whole, const Box2i& crop, const Image& cropped, int band,
                         int* pixels);

// cornerScene() at 200 x 150 through cornerCamera(): the whole frame, and the same frame with
// its buffer cut to `crop` (no overscan), for the border tests. Rendered once.
struct CornerCrop {
    SceneBuffers full, part;
    Box2i crop;
};
const CornerCrop& cornerCrop();

// A plane through the origin, its normal tilted `tiltDeg` from the view axis, seen from `dist`
// along +Z (70 degree pinhole, or an orthographic view `dist` wide).
SceneBuffers tiltedPlaneView(double tiltDeg, double dist, bool ortho, int width, int height);

// HBAO settings for analytic tests: weighting, falloff, radius, slices x steps, no blur, 2 threads.
Settings hbaoSettings(Weighting w, Falloff f, float radius, int dirs = 8, int steps = 8);

// Deep input layers (OperatorInputs::deepLayers) from a depth plane: layer k's (front, back)
// at each texel is (z + offsets[k].first, z + offsets[k].second), z that texel's depth.
Image deepLayersFromDepth(const Image& depth, const std::vector<std::pair<float, float>>& offsets);

// The largest |a - b| over two images of the same size; +inf when their sizes differ.
double maxAbsDiff(const Image& a, const Image& b);
// Where `a` and `b` differ by more than `tol`: how many values, and the worst texel with both
// values ("" when none do), for a parity failure's message.
std::string diffSummary(const Image& a, const Image& b, double tol);

} // namespace obscura::test
