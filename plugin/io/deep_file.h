// Deep EXR input (docs/deep.md): the surfaces along each pixel's ray, as the (front, back)
// depth planes the operator's HBAO reads (OperatorInputs::deepLayers). Scanline and tiled
// deep files, through OpenEXR's deep API (io/deep_samples.h).
#pragma once
#include "base/image.h"
#include "io/exr_file.h"
#include "io/layers.h"

#include <string>
#include <vector>

namespace obscura {

// Samples nearer than this fraction of their depth to the previous surface's back continue it:
// a renderer's adjacent volume slices and float rounding make one surface, not two.
constexpr float kDeepTouching = 1e-6f;

// One surface on a pixel's ray: back > front is a span the ray spent inside a solid.
struct DeepSpan {
    float front, back;
};

// The surfaces of every pixel, pixel after pixel, then laid out as the operator's plane.
class DeepLayerBuilder {
public:
    explicit DeepLayerBuilder(size_t pixels, size_t reserve = 0);
    // Adds the surfaces of one pixel's samples (sorted by front): a sample whose front is at or
    // before the back of the surface before it continues it; at most maxLayers surfaces, the
    // nearest. Returns false when some were dropped. The pixels come in row-major order.
    // `rgba` (for every pixel or none): each sample's premultiplied RGBA, `stride` floats apart;
    // a surface's colour is its samples composited front to back.
    bool addPixel(const DeepSpan* sorted, size_t n, int maxLayers, const float* rgba = nullptr, size_t stride = 4);
    // As addPixel, after a first surface of its own (its front +inf: none).
    bool addPixelAfter(DeepSpan first, const DeepSpan* sorted, size_t n, int maxLayers);
    int layers() const { return layers_; }
    // W x H, 2 * max(layers, 1) channels: (front, back) per layer, +inf past a pixel's last.
    Image planes(int width, int height) const;
    // Into `out` (2 * layers() channels or more, +inf), from its pixel `first` on.
    void writePlanes(Image& out, size_t first) const;
    // With colour (addPixel's rgba): 3 max(layers, 1) channels, each surface's un-premultiplied RGB
    // (0 where its alpha is 0 and past a pixel's last surface).
    Image colourPlanes(int width, int height) const;
    void writeColour(Image& out, size_t first) const;

private:
    std::vector<DeepSpan> kept_;
    std::vector<float> colour_;  // with colour: premultiplied RGBA per kept surface
    std::vector<size_t> start_;
    int layers_ = 0;
};

struct DeepLayers {
    Box2i display, data;     // the deep file's windows (display origin 0,0)
    int layers = 0;          // L: the most surfaces any pixel kept, at most the maximum asked
    Image planes;            // over `data`, 2L channels: (front, back) per layer, nearest first;
                             // front +inf past a pixel's last surface; back == front: no span known
    Image colour;            // when asked and the file has R, G and B: 3L channels (DeepLayerBuilder::colourPlanes)
    long long samples = 0;         // samples read
    long long emptyPixels = 0;     // pixels without a sample: sky
    long long droppedSamples = 0;  // NaN or infinite Z, or Z <= 0: not a surface
    long long unsortedPixels = 0;  // samples not in increasing Z: sorted here
    long long truncatedPixels = 0; // more surfaces than the maximum: the farthest dropped
};

// True when `path` is an OpenEXR file whose first part is deep (throws FileError when unreadable).
bool isDeepFile(const std::string& path);

// Reads up to maxLayers distinct surfaces per pixel: samples sorted by Z, overlapping or
// touching samples (Z at or before the current surface's back) merged into one surface; with
// `colour`, each surface's colour too (from R, G, B and A, alpha 1 without A; none without RGB).
// Throws FileError for a flat file, a missing Z channel, an unreadable file, or a window of more
// than maxPixels (checked before reading).
DeepLayers readDeepLayers(const std::string& path, int maxLayers, const DeepChannelNames& names = {},
                          long long maxPixels = kDefaultMaxPixels, bool colour = false);

// The file checked as readDeepLayers checks it, without reading a sample: its windows, no layers.
DeepLayers readDeepLayerWindows(const std::string& path, const DeepChannelNames& names = {},
                                long long maxPixels = kDefaultMaxPixels);

// Planes over the deep file's data window `from` over another (the flat passes'): pixels outside
// the deep file's get `fill` (+inf: no surface).
Image deepPlanesOver(Image&& planes, const Box2i& from, const Box2i& data, float fill);
// The depth pairs over `data`.
Image deepPlanesOver(DeepLayers&& deep, const Box2i& data);

} // namespace obscura
