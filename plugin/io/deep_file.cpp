#include "io/deep_file.h"

#include "base/error.h"

#include "io/deep_samples.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace obscura {

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

} // namespace

bool isDeepFile(const std::string& path) { return readExrInfo(path, kDefaultMaxPixels, true).parts.at(0).deep; }

namespace {

// Every sample's depths, and with colour its premultiplied RGBA (4 floats a sample), as the file
// holds them, pixel after pixel.
struct DeepRead : DeepWindows {
    std::vector<float> z, zBack, rgba;
};

DeepRead readSamples(const std::string& path, const DeepChannelNames& names, bool colour) {
    DeepRead out;
    if (!colour) {
        DeepSamples dd = readDeepDepthSamples(path, names.z, names.zBack);
        static_cast<DeepWindows&>(out) = dd;
        out.z = std::move(dd.z);
        out.zBack = std::move(dd.zBack);
        return out;
    }
    const DeepChannels dc = readDeepChannelSamples(path);
    static_cast<DeepWindows&>(out) = dc;
    const auto index = [&](const std::string& name) {
        const auto it = std::find(dc.names.begin(), dc.names.end(), name);
        return it == dc.names.end() ? -1 : (int)(it - dc.names.begin());
    };
    const int z = index(names.z), zBack = index(names.zBack), r = index("R"), g = index("G"), b = index("B"), a = index("A");
    if (z < 0) throw FileError(path, "deep image without a " + names.z + " channel");
    const size_t nc = dc.names.size(), n = nc ? dc.values.size() / nc : 0;
    const bool rgb = r >= 0 && g >= 0 && b >= 0;
    for (size_t i = 0; i < n; ++i) {
        const float* v = &dc.values[i * nc];
        out.z.push_back(v[z]);
        if (zBack >= 0) out.zBack.push_back(v[zBack]);
        if (rgb) out.rgba.insert(out.rgba.end(), {v[r], v[g], v[b], a >= 0 ? v[a] : 1.0f});
    }
    return out;
}

// The sample `under` composited behind `acc` (premultiplied RGBA, front to back: "over").
void compositeUnder(float* acc, const float* under) {
    const float t = 1.0f - acc[3];
    for (int c = 0; c < 4; ++c) acc[c] += t * under[c];
}

void setWindows(const DeepWindows& w, DeepLayers& out) {
    out.display = Box2i{0, 0, w.fullWidth, w.fullHeight};
    out.data = Box2i{w.x, w.y, w.x + w.width, w.y + w.height};
}

} // namespace

DeepLayers readDeepLayerWindows(const std::string& path, const DeepChannelNames& names, long long maxPixels) {
    checkWindowsBeforeOpening(path, maxPixels);
    DeepLayers out;
    setWindows(readDeepWindows(path, names.z), out);
    return out;
}

DeepLayers readDeepLayers(const std::string& path, int maxLayers, const DeepChannelNames& names, long long maxPixels,
                          bool colour) {
    checkWindowsBeforeOpening(path, maxPixels);
    const DeepRead dd = readSamples(path, names, colour);
    const bool rgba = !dd.rgba.empty();

    DeepLayers out;
    setWindows(dd, out);
    const size_t pixels = (size_t)dd.width * dd.height;
    DeepLayerBuilder builder(pixels, std::min(dd.z.size(), (size_t)maxLayers * pixels));
    std::vector<DeepSpan> samples;
    std::vector<size_t> order;  // each kept sample's index in dd
    std::vector<float> colours;
    size_t first = 0;  // this pixel's first sample in dd.z
    for (size_t p = 0; p < pixels; ++p) {
        const int n = dd.counts[p];
        out.samples += n;
        samples.clear();
        order.clear();
        for (size_t i = first; i < first + (size_t)n; ++i) {
            const float z = dd.z[i];
            if (z == std::numeric_limits<float>::infinity()) continue;  // the sky: no surface
            if (!std::isfinite(z) || z <= 0.0f) {
                ++out.droppedSamples;
                continue;
            }
            const float zb = dd.zBack.empty() ? z : dd.zBack[i];
            samples.push_back({z, std::isfinite(zb) && zb > z ? zb : z});
            order.push_back(i);
        }
        first += (size_t)n;
        if (samples.empty()) ++out.emptyPixels;
        auto byFront = [](const DeepSpan& a, const DeepSpan& b) { return a.front < b.front; };
        if (!std::is_sorted(samples.begin(), samples.end(), byFront)) {
            ++out.unsortedPixels;
            std::vector<size_t> perm(samples.size());
            for (size_t i = 0; i < perm.size(); ++i) perm[i] = i;
            std::stable_sort(perm.begin(), perm.end(), [&](size_t a, size_t b) { return byFront(samples[a], samples[b]); });
            std::vector<DeepSpan> s(samples);
            std::vector<size_t> o(order);
            for (size_t i = 0; i < perm.size(); ++i) {
                samples[i] = s[perm[i]];
                order[i] = o[perm[i]];
            }
        }
        colours.clear();
        for (size_t i : order)
            if (rgba) colours.insert(colours.end(), &dd.rgba[4 * i], &dd.rgba[4 * i] + 4);
        if (!builder.addPixel(samples.data(), samples.size(), maxLayers, rgba ? colours.data() : nullptr))
            ++out.truncatedPixels;
    }
    out.planes = builder.planes(dd.width, dd.height);
    if (rgba) out.colour = builder.colourPlanes(dd.width, dd.height);
    out.layers = std::max(builder.layers(), 1);  // an all-sky file: one layer of +inf
    return out;
}

DeepLayerBuilder::DeepLayerBuilder(size_t pixels, size_t reserve) {
    kept_.reserve(reserve);
    start_.reserve(pixels + 1);
    start_.push_back(0);
}

bool DeepLayerBuilder::addPixel(const DeepSpan* sorted, size_t n, int maxLayers, const float* rgba, size_t stride) {
    const size_t begin = start_.back();
    bool all = true;
    for (size_t i = 0; i < n; ++i) {
        const DeepSpan& s = sorted[i];
        const float* c = rgba ? rgba + i * stride : nullptr;
        if (kept_.size() > begin && s.front <= kept_.back().back * (1.0f + kDeepTouching)) {
            kept_.back().back = std::max(kept_.back().back, s.back);
            if (c) compositeUnder(&colour_[colour_.size() - 4], c);
            continue;
        }
        if (kept_.size() - begin == (size_t)maxLayers) {
            all = false;
            break;
        }
        kept_.push_back(s);
        if (c) colour_.insert(colour_.end(), c, c + 4);
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

namespace {
// put(v, k) for every kept surface k of every pixel p (its surfaces start[p] .. start[p + 1]),
// v its `width` floats in pixel first + p of `out`.
template <class Put>
void writeKept(const std::vector<size_t>& start, Image& out, size_t first, int width, Put put) {
    for (size_t p = 0; p + 1 < start.size(); ++p) {
        float* v = out.pixels.data() + (first + p) * out.channels;
        for (size_t k = start[p]; k < start[p + 1]; ++k, v += width) put(v, k);
    }
}
} // namespace

void DeepLayerBuilder::writePlanes(Image& out, size_t first) const {
    writeKept(start_, out, first, 2, [&](float* v, size_t k) {
        v[0] = kept_[k].front;
        v[1] = kept_[k].back;
    });
}

Image DeepLayerBuilder::colourPlanes(int width, int height) const {
    Image out(width, height, 3 * std::max(layers_, 1), 0.0f);
    writeColour(out, 0);
    return out;
}

void DeepLayerBuilder::writeColour(Image& out, size_t first) const {
    writeKept(start_, out, first, 3, [&](float* v, size_t k) {
        const float* c = &colour_[4 * k];
        for (int i = 0; i < 3; ++i) v[i] = c[3] > 0.0f ? c[i] / c[3] : 0.0f;
    });
}

Image deepPlanesOver(Image&& planes, const Box2i& from, const Box2i& data, float fill) {
    if (data == from) return std::move(planes);
    Image out(data.width(), data.height(), planes.channels, fill);
    const Box2i common = intersect(data, from);
    for (int y = common.y0; y < common.y1; ++y)
        for (int x = common.x0; x < common.x1; ++x)
            std::copy_n(planes.at(x - from.x0, y - from.y0), planes.channels, out.at(x - data.x0, y - data.y0));
    return out;
}

Image deepPlanesOver(DeepLayers&& deep, const Box2i& data) {
    return deepPlanesOver(std::move(deep.planes), deep.data, data, kInf);
}

} // namespace obscura
