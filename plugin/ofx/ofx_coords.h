// Geometry: OFX pixel coordinates (y up) <-> the operator's display coordinates (y down).
//
// OFX images live in pixel coordinates, y up, origin bottom-left, rows possibly stored
// bottom-up or top-down (rowBytes < 0); the operator's planes are display-window
// coordinates, y down. The one conversion between them is FrameMap.
//
// Tiles. A render window is computed from the depth/normal data over the window plus an
// apron of the largest projected radius (+ texel snapping + blur), clipped to the Depth
// clip's region of definition, with the radius cap pinned (Settings::maxRadiusPixels) so
// every tile runs the kernel exactly as the whole frame does.
#pragma once
#include "ofx_api.h"
#include "ofx_instance.h"
#include "ofx_params.h"

#include "base/image.h"
#include "core/camera.h"

#include <algorithm>
#include <cmath>

namespace obscura::ofx {

// Half-open pixel rectangle in OFX pixel coordinates (y up).
struct PixRect {
    int x1 = 0, y1 = 0, x2 = 0, y2 = 0;
    bool empty() const { return x2 <= x1 || y2 <= y1; }
    int width() const { return x2 - x1; }
    int height() const { return y2 - y1; }
    bool contains(int x, int y) const { return x >= x1 && x < x2 && y >= y1 && y < y2; }
};

inline PixRect intersect(const PixRect& a, const PixRect& b) {
    PixRect r{std::max(a.x1, b.x1), std::max(a.y1, b.y1), std::min(a.x2, b.x2), std::min(a.y2, b.y2)};
    return r.empty() ? PixRect{} : r;
}
inline PixRect grow(const PixRect& a, int by) { return {a.x1 - by, a.y1 - by, a.x2 + by, a.y2 + by}; }

// The frame of one render: the project's pixel aspect ratio, the render scale, the display
// window (the project extent) and the region of definition of the depth pass (the data
// window), the last two in pixels at the render scale. Regions of interest, regions of
// definition and fetch regions are canonical; render windows and image bounds are pixels.
struct FrameMap {
    double par = 1;
    double sx = 1, sy = 1;            // render scale (proxy renders: 0.5, ...)
    int displayW = 0, displayH = 0;  // display window: OFX pixels [0, W) x [0, H)
    PixRect rod;                      // Depth clip's region of definition, OFX pixels

    // Canonical -> pixel: x * scale / PAR, y * scale.
    PixRect toPixels(const OfxRectD& r) const {
        const double kx = sx / par;
        return {(int)std::floor(r.x1 * kx + 1e-6), (int)std::floor(r.y1 * sy + 1e-6), (int)std::ceil(r.x2 * kx - 1e-6),
                (int)std::ceil(r.y2 * sy - 1e-6)};
    }
    OfxRectD toCanonical(const PixRect& r) const {
        if (r.empty()) return {0, 0, 0, 0};
        const double kx = par / sx;
        return {r.x1 * kx, r.y1 / sy, r.x2 * kx, r.y2 / sy};
    }
    // The width / height of one pixel at this render scale, which is what the camera sees.
    double pixelAspect() const { return par * sy / sx; }
    // The single flip: an OFX pixel rectangle as a display-window box (y down).
    Box2i toDisplay(const PixRect& r) const { return Box2i{r.x1, displayH - r.y2, r.x2, displayH - r.y1}; }
    // Row `row` (y down) of the display box of `r` is OFX row:
    int ofxRow(const PixRect& r, int row) const { return r.y2 - 1 - row; }
};

// `actionArgs`: the RoI or render action's in-args, which carry the render scale.
FrameMap frameMap(const Instance& in, OfxTime t, OfxPropertySetHandle actionArgs);

// The parameters for a render at the frame's scale. Blur and Max Screen Radius are in
// full-resolution pixels, so a proxy render scales them; the radius is in world units and
// scales through the camera (whose display window is at the render scale).
Params paramsAt(const Instance& in, OfxTime t, const FrameMap& f);

// The cap on the projected radius, the same for every tile of the frame: the parameter,
// or with 0 (automatic) the CLI's rule over the whole frame (its extent + 2 pixels).
float radiusCap(const Params& p, const FrameMap& f);

// How far from a pixel its AO reads, in pixels (ofx_coords.cpp says how). Known before any
// depth is fetched, so it can answer the RoI action.
int apronPixels(const Params& p, const Camera& cam, float cap);

// The depth/normal pixels a render window reads.
PixRect dataRegion(const PixRect& window, int apron, const FrameMap& f);

// The depth/normal pixels a render window reads under parameters `p` at frame `f` (the
// window, its apron, clipped to the RoD); empty when the output computes nothing.
PixRect dataRegionFor(const PixRect& window, const Params& p, const FrameMap& f);

} // namespace obscura::ofx
