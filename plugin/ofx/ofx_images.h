// Images fetched from clips, and their pixels as the operator's planes.
#pragma once
#include "ofx_api.h"
#include "ofx_coords.h"

#include "base/image.h"

#include <cstddef>

namespace obscura::ofx {

// One image the host lent for a render (32-bit float, 1, 3 or 4 channels), released with it.
class ClipImage {
public:
    ClipImage() = default;
    ClipImage(const ClipImage&) = delete;
    ClipImage& operator=(const ClipImage&) = delete;
    ~ClipImage();

    // region = nullptr: the whole image the host offers (the render window for Output).
    // False when the host has none there (kOfxStatFailed, or OK without an image); throws for any
    // other failure, and for a pixel depth or components it cannot be read in.
    bool fetch(OfxImageClipHandle clip, OfxTime t, const OfxRectD* region, const char* what);

    bool empty() const { return handle_ == nullptr; }  // none fetched: every pixel a hole
    int components() const { return comps_; }
    const PixRect& bounds() const { return bounds_; }
    // The pixel at OFX pixel (x, y), or nullptr outside the image's bounds.
    float* pixel(int x, int y) const {
        if (x < bounds_.x1 || x >= bounds_.x2 || y < bounds_.y1 || y >= bounds_.y2) return nullptr;
        return reinterpret_cast<float*>(data_ + (std::ptrdiff_t)(y - bounds_.y1) * rowBytes_) + (size_t)(x - bounds_.x1) * comps_;
    }

private:
    OfxPropertySetHandle handle_ = nullptr;
    char* data_ = nullptr;
    PixRect bounds_;
    int rowBytes_ = 0;
    int comps_ = 0;
};

// A connected input clip's image over canonical `region` into `img`. A host may answer that the
// clip has none at that time or there (kOfxStatFailed): the spec says to go on as if it were
// black and transparent, so `img` stays empty and every pixel reads as a hole.
void fetchInput(ClipImage& img, OfxImageClipHandle clip, OfxTime t, const OfxRectD& region, const char* what);

// Copies `channels` channels of `img` over OFX region `r` into a packed display-ordered
// (y down) plane; pixels the image does not cover read `fill`.
Image toDisplayPlane(const ClipImage& img, const PixRect& r, const FrameMap& f, int channels, float fill);

} // namespace obscura::ofx
