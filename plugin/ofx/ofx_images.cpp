// Clip images and display planes (ofx_images.h).
#include "ofx_images.h"

#include "ofx_suites.h"

#include "base/error.h"

#include <new>
#include <string>

namespace obscura::ofx {

ClipImage::~ClipImage() {
    if (handle_) gEffect->clipReleaseImage(handle_);
}

bool ClipImage::fetch(OfxImageClipHandle clip, OfxTime t, const OfxRectD* region, const char* what) {
    const OfxStatus status = gEffect->clipGetImage(clip, t, region, &handle_);
    if (status == kOfxStatErrMemory) throw std::bad_alloc();
    if (status != kOfxStatOK || !handle_) {
        handle_ = nullptr;
        if (status == kOfxStatFailed || status == kOfxStatOK) return false;
        throw Error(std::string("the ") + what + " clip gave no image (status " + std::to_string(status) + ")");
    }
    const std::string depth = getString(handle_, kOfxImageEffectPropPixelDepth);
    if (depth != kOfxBitDepthFloat)
        throw Error(std::string("the ") + what + " image is " + depth + "; only 32-bit float is supported");
    const std::string comps = getString(handle_, kOfxImageEffectPropComponents);
    comps_ = comps == kOfxImageComponentRGBA ? 4 : comps == kOfxImageComponentRGB ? 3 : comps == kOfxImageComponentAlpha ? 1 : 0;
    if (comps_ == 0) throw Error(std::string("the ") + what + " image has unsupported components " + comps);
    void* data = nullptr;
    check(gProp->propGetPointer(handle_, kOfxImagePropData, 0, &data));
    data_ = static_cast<char*>(data);
    int b[4] = {0, 0, 0, 0};
    check(gProp->propGetIntN(handle_, kOfxImagePropBounds, 4, b));
    bounds_ = {b[0], b[1], b[2], b[3]};
    rowBytes_ = getInt(handle_, kOfxImagePropRowBytes, 0);
    if (!data_ && !bounds_.empty()) throw Error(std::string("the ") + what + " image has no pixels");
    return true;
}

void fetchInput(ClipImage& img, OfxImageClipHandle clip, OfxTime t, const OfxRectD& region, const char* what) {
    img.fetch(clip, t, &region, what);
}

Image toDisplayPlane(const ClipImage& img, const PixRect& r, const FrameMap& f, int channels, float fill) {
    Image out(r.width(), r.height(), channels, fill);
    for (int row = 0; row < r.height(); ++row) {
        const int y = f.ofxRow(r, row);
        for (int col = 0; col < r.width(); ++col) {
            const float* p = img.pixel(r.x1 + col, y);
            if (!p) continue;
            float* o = out.at(col, row);
            for (int c = 0; c < channels; ++c) o[c] = c < img.components() ? p[c] : fill;
        }
    }
    return out;
}

} // namespace obscura::ofx
