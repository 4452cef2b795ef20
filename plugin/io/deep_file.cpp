#include "io/deep_file.h"

#include "base/error.h"

#include "io/oiio_module.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace obscura {

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// Samples nearer than this fraction of their depth to the previous surface's back continue it:
// a renderer's adjacent volume slices and float rounding make one surface, not two.
constexpr float kTouching = 1e-6f;

} // namespace

bool isDeepFile(const std::string& path) {
    int width = 0, height = 0, channels = 0;
    bool deep = false;
    const std::string failed = oiioModule().probe(path, width, height, channels, deep);
    if (!failed.empty()) throw FileError(path, failed);
    return deep;
}

DeepLayers readDeepLayers(const std::string& path, int maxLayers, const DeepChannelNames& names, long long maxPixels) {
    checkWindowsBeforeOpening(path, maxPixels);
    DeepSamples dd;
    const std::string failed = oiioModule().readDeep(path, names.z, names.zBack, dd);
    if (!failed.empty()) throw FileError(path, failed);

    DeepLayers out;
    out.display = Box2i{0, 0, dd.fullWidth, dd.fullHeight};
    out.data = Box2i{dd.x, dd.y, dd.x + dd.width, dd.y + dd.height};
    const int W = dd.width, H = dd.height;
    struct Span {
        float front, back;
    };
    // Every pixel's surfaces first, so the plane gets as many layers as the deepest pixel needs:
    // pixel p's are kept[start[p] .. start[p + 1]).
    std::vector<Span> kept;
    kept.reserve(std::min(dd.z.size(), (size_t)maxLayers * W * H));
    std::vector<size_t> start((size_t)W * H + 1, 0);
    std::vector<Span> samples;
    size_t first = 0;  // this pixel's first sample in dd.z
    for (size_t p = 0; p < (size_t)W * H; ++p) {
        start[p] = kept.size();
        const int n = dd.counts[p];
        out.samples += n;
        samples.clear();
        for (size_t i = first; i < first + (size_t)n; ++i) {
            const float z = dd.z[i];
            if (!std::isfinite(z) || z <= 0.0f) {
                ++out.droppedSamples;
                continue;
            }
            const float zb = dd.hasZBack ? dd.zBack[i] : z;
            samples.push_back({z, std::isfinite(zb) && zb > z ? zb : z});
        }
        first += (size_t)n;
        if (samples.empty()) {
            ++out.emptyPixels;
            continue;
        }
        auto byFront = [](const Span& a, const Span& b) { return a.front < b.front; };
        if (!std::is_sorted(samples.begin(), samples.end(), byFront)) {
            ++out.unsortedPixels;
            std::stable_sort(samples.begin(), samples.end(), byFront);
        }
        for (const Span& s : samples) {
            if (kept.size() > start[p] && s.front <= kept.back().back * (1.0f + kTouching)) {
                kept.back().back = std::max(kept.back().back, s.back);
                continue;
            }
            if (kept.size() - start[p] == (size_t)maxLayers) {
                ++out.truncatedPixels;
                break;
            }
            kept.push_back(s);
        }
        out.layers = std::max(out.layers, (int)(kept.size() - start[p]));
    }
    start[(size_t)W * H] = kept.size();
    out.planes = Image(W, H, 2 * std::max(out.layers, 1), kInf);
    for (size_t p = 0; p < (size_t)W * H; ++p) {
        float* v = out.planes.pixels.data() + p * out.planes.channels;
        for (size_t k = start[p]; k < start[p + 1]; ++k, v += 2) {
            v[0] = kept[k].front;
            v[1] = kept[k].back;
        }
    }
    if (out.layers == 0) out.layers = 1;  // an all-sky file: one layer of +inf
    return out;
}

Image deepPlanesOver(DeepLayers&& deep, const Box2i& data) {
    if (data == deep.data) return std::move(deep.planes);
    Image out(data.width(), data.height(), deep.planes.channels, kInf);
    const Box2i common = intersect(data, deep.data);
    for (int y = common.y0; y < common.y1; ++y)
        for (int x = common.x0; x < common.x1; ++x)
            std::copy_n(deep.planes.at(x - deep.data.x0, y - deep.data.y0), deep.planes.channels,
                        out.at(x - data.x0, y - data.y0));
    return out;
}

} // namespace obscura
