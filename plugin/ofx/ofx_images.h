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
    // False when the host gives none; throws for a pixel depth or components it cannot be read in.
    bool fetch(OfxImageClipHandle clip, OfxTime t, const OfxRectD* region, const char* what);

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

// `clip`'s image over canonical `region` into `img`; throws "the <what> clip gave no image".
void fetchOrThrow(ClipImage& img, OfxImageClipHandle clip, OfxTime t, const OfxRectD& region, const char* what);

// Copies `channels` channels of `img` over OFX region `r` into a packed display-ordered
// (y down) plane; pixels the image does not cover read `fill`.
Image toDisplayPlane(const ClipImage& img, const PixRect& r, const FrameMap& f, int channels, float fill);

} // namespace obscura::ofx
