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
    const size_t pixels = (size_t)dd.width * dd.height;
    DeepLayerBuilder builder(pixels, std::min(dd.z.size(), (size_t)maxLayers * pixels));
    std::vector<DeepSpan> samples;
    size_t first = 0;  // this pixel's first sample in dd.z
    for (size_t p = 0; p < pixels; ++p) {
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
        if (samples.empty()) ++out.emptyPixels;
        auto byFront = [](const DeepSpan& a, const DeepSpan& b) { return a.front < b.front; };
        if (!std::is_sorted(samples.begin(), samples.end(), byFront)) {
            ++out.unsortedPixels;
            std::stable_sort(samples.begin(), samples.end(), byFront);
        }
        if (!builder.addPixel(samples.data(), samples.size(), maxLayers)) ++out.truncatedPixels;
    }
    out.planes = builder.planes(dd.width, dd.height);
    out.layers = std::max(builder.layers(), 1);  // an all-sky file: one layer of +inf
    return out;
}

DeepLayerBuilder::DeepLayerBuilder(size_t pixels, size_t reserve) {
    kept_.reserve(reserve);
    start_.reserve(pixels + 1);
    start_.push_back(0);
}

bool DeepLayerBuilder::addPixel(const DeepSpan* sorted, size_t n, int maxLayers) {
    const size_t begin = start_.back();
    bool all = true;
    for (size_t i = 0; i < n; ++i) {
        const DeepSpan& s = sorted[i];
        if (kept_.size() > begin && s.front <= kept_.back().back * (1.0f + kDeepTouching)) {
            kept_.back().back = std::max(kept_.back().back, s.back);
            continue;
        }
        if (kept_.size() - begin == (size_t)maxLayers) {
            all = false;
            break;
        }
        kept_.push_back(s);
    }
    layers_ = std::max(layers_, (int)(kept_.size() - begin));
    start_.push_back(kept_.size());
    return all;
}

bool DeepLayerBuilder::addPixelAfter(DeepSpan first, const DeepSpan* sorted, size_t n, int maxLayers) {
    const size_t begin = start_.back();
    kept_.push_back(first);
    start_.back() = kept_.size();  // the rest merge among themselves, never into `first`
    const bool all = addPixel(sorted, n, maxLayers - 1);
    start_[start_.size() - 2] = begin;
    layers_ = std::max(layers_, (int)(kept_.size() - begin));
    return all;
}

Image DeepLayerBuilder::planes(int width, int height) const {
    Image out(width, height, 2 * std::max(layers_, 1), kInf);
    writePlanes(out, 0);
    return out;
}

void DeepLayerBuilder::writePlanes(Image& out, size_t first) const {
    for (size_t p = 0; p + 1 < start_.size(); ++p) {
        float* v = out.pixels.data() + (first + p) * out.channels;
        for (size_t k = start_[p]; k < start_[p + 1]; ++k, v += 2) {
            v[0] = kept_[k].front;
            v[1] = kept_[k].back;
        }
    }
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
