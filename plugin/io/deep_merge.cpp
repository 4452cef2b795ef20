#include "io/deep_merge.h"

#include "base/error.h"

#include <OpenEXR/ImfChannelList.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <atomic>
#include <exception>
#include <functional>
#include <thread>
#include <tuple>

namespace obscura {

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

float alphaOf(const float* sample, int alpha) { return alpha < 0 ? 1.0f : std::clamp(sample[2 + alpha], 0.0f, 1.0f); }

// The part [lo, hi] of volume sample `s`: its alpha is 1 - (1 - a)^x for the fraction x of its
// depth range, and its premultiplied channels (alpha among them) scale with that alpha.
void appendPiece(const float* s, int stride, int alpha, float lo, float hi, std::vector<float>& out) {
    const size_t at = out.size();
    out.insert(out.end(), s, s + stride);
    float* piece = out.data() + at;
    const double x = (double)(hi - lo) / ((double)s[1] - s[0]);
    const double a = alphaOf(s, alpha);
    const double part = a >= 1.0 ? 1.0 : -std::expm1(x * std::log1p(-a));
    const double scale = a >= 1.0 ? 1.0 : a > 0.0 ? part / a : x;
    piece[0] = lo;
    piece[1] = hi;
    for (int c = 2; c < stride; ++c) piece[c] = (float)(piece[c] * scale);
}

// Two samples over one depth range as one: their optical depths u = -log(1 - a) add, and each
// contributes its channels in proportion to its u / a; an opaque sample wins (two: their mean).
void combineInto(float* acc, const float* s, int stride, int alpha) {
    const double a1 = alphaOf(acc, alpha), a2 = alphaOf(s, alpha);
    if (a1 >= 1.0 || a2 >= 1.0) {
        const double w1 = a2 < 1.0 ? 1.0 : a1 < 1.0 ? 0.0 : 0.5;
        for (int c = 2; c < stride; ++c) acc[c] = (float)(w1 * acc[c] + (1.0 - w1) * s[c]);
        return;
    }
    const double u1 = -std::log1p(-a1), u2 = -std::log1p(-a2), u = u1 + u2;
    const double v1 = a1 > 0.0 ? u1 / a1 : 1.0, v2 = a2 > 0.0 ? u2 / a2 : 1.0;
    const double a = -std::expm1(-u), v = a > 0.0 ? u / a : 1.0;
    for (int c = 2; c < stride; ++c) acc[c] = (float)((acc[c] * v1 + s[c] * v2) / v);
}

// The samples split where any sample begins or ends inside a volume, sorted, and those over one
// range combined: after this no two samples overlap. Returns the count; they are in `out`.
size_t tidySamples(const float* s, size_t n, int stride, int alpha, std::vector<float>& bounds, std::vector<float>& out) {
    bounds.clear();
    for (size_t i = 0; i < n; ++i) bounds.insert(bounds.end(), {s[i * stride], s[i * stride + 1]});
    std::sort(bounds.begin(), bounds.end());
    bounds.erase(std::unique(bounds.begin(), bounds.end()), bounds.end());
    std::vector<float> pieces;
    for (size_t i = 0; i < n; ++i) {
        const float* x = s + i * stride;
        if (!(x[1] > x[0])) {
            pieces.insert(pieces.end(), x, x + stride);
            continue;
        }
        float lo = x[0];
        for (auto b = std::upper_bound(bounds.begin(), bounds.end(), x[0]); b != bounds.end() && *b < x[1]; ++b) {
            appendPiece(x, stride, alpha, lo, *b, pieces);
            lo = *b;
        }
        appendPiece(x, stride, alpha, lo, x[1], pieces);
    }
    const size_t m = pieces.size() / stride;
    std::vector<size_t> order(m);
    std::iota(order.begin(), order.end(), size_t(0));
    std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
        const float *pa = &pieces[a * stride], *pb = &pieces[b * stride];
        return pa[0] < pb[0] || (pa[0] == pb[0] && pa[1] < pb[1]);
    });
    out.clear();
    for (size_t k : order) {
        const float* piece = &pieces[k * stride];
        float* last = out.empty() ? nullptr : &out[out.size() - stride];
        if (last && last[0] == piece[0] && last[1] == piece[1]) combineInto(last, piece, stride, alpha);
        else out.insert(out.end(), piece, piece + stride);
    }
    return out.size() / stride;
}

// Whether some sample overlaps another (begins inside a volume before it, or shares its range).
bool overlapping(const float* s, size_t n, int stride) {
    float reach = n ? s[1] : 0.0f;
    for (size_t i = 1; i < n; ++i) {
        const float* x = s + i * stride;
        if (x[0] < reach || (x[0] == x[-stride] && x[1] == x[1 - stride])) return true;
        reach = std::max(reach, x[1]);
    }
    return false;
}

int workerCount(int threads) { return threads > 0 ? threads : std::max(1, (int)std::thread::hardware_concurrency()); }

// task(i) for every i in [0, count), on up to `workers` threads; the first failure by index is thrown.
void runParallel(int count, int workers, const std::function<void(int)>& task) {
    std::vector<std::exception_ptr> failed(count);
    std::atomic<int> next{0};
    std::vector<std::thread> pool;
    for (int w = 0; w < std::min(workers, count); ++w)
        pool.emplace_back([&] {
            for (int i = next++; i < count; i = next++) {
                try {
                    task(i);
                } catch (...) {
                    failed[i] = std::current_exception();
                }
            }
        });
    for (std::thread& t : pool) t.join();
    for (const std::exception_ptr& e : failed)
        if (e) std::rethrow_exception(e);
}

std::string windowText(const Imath::Box2i& b) {
    return "[" + std::to_string(b.min.x) + "," + std::to_string(b.min.y) + " - " + std::to_string(b.max.x) + "," +
           std::to_string(b.max.y) + "]";
}

void requireSameWindows(const DeepElement& e, const DeepElement& first) {
    const Imf::Header &h = e.part.header, &f = first.part.header;
    for (auto [which, mine, theirs] : {std::tuple{"display", h.displayWindow(), f.displayWindow()},
                                       std::tuple{"data", h.dataWindow(), f.dataWindow()}})
        if (mine != theirs)
            throw FileError(e.path, std::string("its ") + which + " window " + windowText(mine) + " is not that of '" +
                                        first.path + "' " + windowText(theirs) + "; deep elements must agree");
}

// Where each pixel's samples start in an element's values (in samples), pixel after pixel.
std::vector<size_t> sampleStarts(const DeepChannels& d) {
    std::vector<size_t> start(d.counts.size() + 1, 0);
    for (size_t p = 0; p < d.counts.size(); ++p) start[p + 1] = start[p] + (size_t)d.counts[p];
    return start;
}

} // namespace

void flattenSamples(const float* samples, size_t n, int stride, int alpha, std::vector<float>& scratch, float* out) {
    std::fill(out, out + stride - 2, 0.0f);
    thread_local std::vector<float> bounds;
    if (overlapping(samples, n, stride)) {
        n = tidySamples(samples, n, stride, alpha, bounds, scratch);
        samples = scratch.data();
    }
    float covered = 0.0f;
    for (size_t i = 0; i < n && covered < 1.0f; ++i) {
        const float* s = samples + i * stride;
        const float through = 1.0f - covered;
        for (int c = 2; c < stride; ++c) out[c - 2] += through * s[c];
        covered += through * alphaOf(s, alpha);
    }
}

std::vector<ExrChannel> headerChannels(const Imf::Header& header) {
    std::vector<ExrChannel> channels;
    for (auto it = header.channels().begin(); it != header.channels().end(); ++it)
        channels.push_back({it.name(), it.channel().type, it.channel().xSampling, it.channel().ySampling});
    return channels;
}

std::vector<DeepElement> readDeepElements(const std::vector<std::string>& paths, const DeepChannelNames& names,
                                          long long maxPixels, int threads) {
    std::vector<DeepElement> elements(paths.size());
    runParallel((int)paths.size(), workerCount(threads),
                [&](int i) { elements[i] = readDeepElement(paths[i], names, maxPixels); });
    return elements;
}

DeepElement readDeepElement(const std::string& path, const DeepChannelNames& names, long long maxPixels) {
    DeepElement e;
    e.path = path;
    ExrInfo info = readExrInfo(path, maxPixels, true);  // the windows are checked before anything is read
    if (!info.parts[0].deep) throw FileError(path, "is not a deep image; several inputs are merged as deep elements");
    e.part = std::move(info.parts[0]);
    e.part.channels = headerChannels(e.part.header);
    if (e.part.findChannel(names.z) < 0)  // said before any sample is read
        throw FileError(path, "deep image without a " + names.z + " channel (its samples' depth)");
    e.samples = readDeepChannelSamples(path);
    const std::vector<std::string>& n = e.samples.names;
    auto index = [&](const std::string& name) {
        const auto it = std::find(n.begin(), n.end(), name);
        return it == n.end() ? -1 : (int)(it - n.begin());
    };
    e.z = index(names.z);
    e.zBack = index(names.zBack);
    return e;
}

namespace {

// Every channel of any element but its depths, by name, with the type it is written back in.
std::vector<ExrChannel> flattenedChannels(const std::vector<DeepElement>& elements) {
    std::vector<ExrChannel> channels;
    for (const DeepElement& e : elements)
        for (const ExrChannel& c : e.part.channels) {
            const std::vector<std::string>& n = e.samples.names;
            const int i = (int)(std::find(n.begin(), n.end(), c.name) - n.begin());
            const bool known =
                std::any_of(channels.begin(), channels.end(), [&](const ExrChannel& k) { return k.name == c.name; });
            if (i != e.z && i != e.zBack && !known) channels.push_back({c.name, c.type == Imf::HALF ? Imf::HALF : Imf::FLOAT, 1, 1});
        }
    std::sort(channels.begin(), channels.end(), [](const ExrChannel& a, const ExrChannel& b) { return a.name < b.name; });
    return channels;
}

struct MergeCounts {
    long long samples = 0, droppedSamples = 0, emptyPixels = 0, truncatedPixels = 0;
};

// One pixel's samples of every element, gathered as flattenSamples reads them and sorted.
class PixelSamples {
public:
    PixelSamples(const std::vector<DeepElement>& elements, const std::vector<ExrChannel>& channels, int alpha)
        : elements_(elements), stride_(2 + (int)channels.size()), alpha_(alpha) {
        for (const DeepElement& e : elements) {
            std::vector<int> from(channels.size(), -1);  // -1: absent: 0, or 1 for alpha
            for (size_t c = 0; c < channels.size(); ++c) {
                const auto it = std::find(e.samples.names.begin(), e.samples.names.end(), channels[c].name);
                if (it != e.samples.names.end()) from[c] = (int)(it - e.samples.names.begin());
            }
            from_.push_back(std::move(from));
            starts_.push_back(sampleStarts(e.samples));
        }
    }

    // Pixel p's valid samples, sorted by (Z, ZBack); counts what was dropped. A sample at Z = +inf
    // is the sky (docs/conventions.md): it comes last, and is colour without a surface.
    void gather(size_t p, MergeCounts& m) {
        buf_.clear();
        owner_.clear();
        for (size_t e = 0; e < elements_.size(); ++e) {
            const DeepElement& el = elements_[e];
            const size_t nc = el.samples.names.size();
            for (size_t s = starts_[e][p]; s < starts_[e][p + 1]; ++s) {
                const float* v = &el.samples.values[s * nc];
                ++m.samples;
                const float z = v[el.z], zb = el.zBack >= 0 ? v[el.zBack] : z;
                if (!(z > 0.0f)) {  // NaN, -inf, 0 or negative
                    ++m.droppedSamples;
                    continue;
                }
                buf_.insert(buf_.end(), {z, std::isfinite(zb) && zb > z ? zb : z});
                for (size_t c = 0; c < from_[e].size(); ++c)
                    buf_.push_back(from_[e][c] >= 0 ? v[from_[e][c]] : (int)c == alpha_ ? 1.0f : 0.0f);
                owner_.push_back((int)e);
            }
        }
        const size_t n = owner_.size(), stride = stride_;
        order_.resize(n);
        std::iota(order_.begin(), order_.end(), size_t(0));
        std::stable_sort(order_.begin(), order_.end(), [&](size_t a, size_t b) {
            const float *pa = &buf_[a * stride], *pb = &buf_[b * stride];
            return pa[0] < pb[0] || (pa[0] == pb[0] && pa[1] < pb[1]);
        });
        sorted.resize(n * stride);
        owner.resize(n);
        spans.clear();
        for (size_t i = 0; i < n; ++i) {
            std::copy_n(&buf_[order_[i] * stride], stride, &sorted[i * stride]);
            owner[i] = owner_[order_[i]];
            if (sorted[i * stride] < kInf) spans.push_back({sorted[i * stride], sorted[i * stride + 1]});
        }
    }

    std::vector<float> sorted;    // stride floats a sample: Z, ZBack, the flattened channels
    std::vector<int> owner;       // each sorted sample's element
    std::vector<DeepSpan> spans;  // the surfaces: each sorted sample's (Z, ZBack) but the sky's, which come last

private:
    const std::vector<DeepElement>& elements_;
    int stride_, alpha_;
    std::vector<std::vector<int>> from_;
    std::vector<std::vector<size_t>> starts_;
    std::vector<float> buf_;
    std::vector<int> owner_;
    std::vector<size_t> order_;
};

// Element e's visible surface at the pixel (its nearest sample and those continuing it; front
// +inf: none), and every other surface of the pixel into `rest`.
DeepSpan ownSurface(const PixelSamples& px, int e, std::vector<DeepSpan>& rest) {
    DeepSpan mine{kInf, kInf};
    for (size_t i = 0; i < px.spans.size(); ++i) {
        if (px.owner[i] != e) continue;
        if (mine.front == kInf) mine = px.spans[i];
        else if (px.spans[i].front <= mine.back * (1.0f + kDeepTouching)) mine.back = std::max(mine.back, px.spans[i].back);
        else break;
    }
    rest.clear();
    for (size_t i = 0; i < px.spans.size(); ++i)
        if (px.owner[i] != e || px.spans[i].front > mine.back * (1.0f + kDeepTouching)) rest.push_back(px.spans[i]);
    return mine;
}

// Rows [y0, y1) of the merge: the flattened planes and fronts written in place, the surfaces
// into builders of their own (the rows' pixels only).
struct MergeBand {
    int y0 = 0, y1 = 0;
    DeepLayerBuilder merged{0};
    std::vector<DeepLayerBuilder> own;
    MergeCounts counts;
};

// The premultiplied RGBA of the pixel's sorted samples (R, G, B at channels rgb, A at alpha, -1: 1).
void sampleColours(const PixelSamples& px, size_t n, int stride, const int* rgb, int alpha, std::vector<float>& out) {
    out.resize(4 * n);
    for (size_t i = 0; i < n; ++i) {
        const float* v = &px.sorted[i * stride + 2];
        for (int c = 0; c < 3; ++c) out[4 * i + c] = v[rgb[c]];
        out[4 * i + 3] = alpha >= 0 ? v[alpha] : 1.0f;
    }
}

// `rgb`: the colour channels' indices when the merge's surfaces take colour, else null.
void mergeBand(const std::vector<DeepElement>& elements, int alpha, const int* rgb, int maxLayers, DeepMerge& m,
               MergeBand& band) {
    const int C = (int)m.channels.size(), W = m.data.width();
    const size_t rows = maxLayers > 0 ? (size_t)W * (band.y1 - band.y0) : 0;
    band.merged = DeepLayerBuilder(rows, rows * 2);
    band.own.assign(m.elementFront.size(), DeepLayerBuilder(rows, rows * 2));
    PixelSamples px(elements, m.channels, alpha);
    std::vector<float> scratch, out(C), colours;
    std::vector<DeepSpan> rest;
    for (size_t p = (size_t)W * band.y0; p < (size_t)W * band.y1; ++p) {
        px.gather(p, band.counts);
        const size_t n = px.spans.size();  // the surfaces; the sky's samples follow them
        if (n == 0) ++band.counts.emptyPixels;
        flattenSamples(px.sorted.data(), px.owner.size(), 2 + C, alpha, scratch, out.data());
        for (int c = 0; c < C; ++c) m.flat[c].pixels[p] = out[c];
        if (n) m.front.pixels[p] = px.spans[0].front;
        if (maxLayers == 0) continue;  // flattened only: no surfaces, and no element's own (perElement needs them)
        if (rgb) sampleColours(px, n, 2 + C, rgb, alpha, colours);
        if (!band.merged.addPixel(px.spans.data(), n, maxLayers, rgb ? colours.data() : nullptr))
            ++band.counts.truncatedPixels;
        for (size_t e = 0; e < band.own.size(); ++e) {
            const DeepSpan mine = ownSurface(px, (int)e, rest);
            band.own[e].addPixelAfter(mine, rest.data(), rest.size(), maxLayers);
            m.elementFront[e].pixels[p] = mine.front;
        }
    }
}

// The bands' surfaces as one plane, as many layers as the deepest pixel of any band needs.
// With `colour`, their colours (3 channels a layer) instead.
Image stitchLayers(const std::vector<MergeBand>& bands, const std::function<const DeepLayerBuilder&(const MergeBand&)>& of,
                   int width, int height, int& layers, bool colour = false) {
    layers = 1;
    for (const MergeBand& b : bands) layers = std::max(layers, of(b).layers());
    Image out(width, height, (colour ? 3 : 2) * layers, colour ? 0.0f : kInf);
    for (const MergeBand& b : bands) {
        if (colour) of(b).writeColour(out, (size_t)width * b.y0);
        else of(b).writePlanes(out, (size_t)width * b.y0);
    }
    return out;
}

} // namespace

DeepMerge mergeDeepElements(const std::vector<DeepElement>& elements, int maxLayers, bool perElement, int threads,
                            bool colour) {
    const DeepElement& first = elements.at(0);
    DeepMerge m;
    m.display = first.part.displayWindow;
    m.data = first.part.dataWindow;
    for (const DeepElement& e : elements) requireSameWindows(e, first);
    m.channels = flattenedChannels(elements);
    int alpha = -1, rgb[3] = {-1, -1, -1};
    for (int c = 0; c < (int)m.channels.size(); ++c) {
        const std::string& name = m.channels[c].name;
        if (name == "A") alpha = c;
        if (name == "R" || name == "G" || name == "B") rgb[name == "R" ? 0 : name == "G" ? 1 : 2] = c;
    }
    const bool coloured = colour && rgb[0] >= 0 && rgb[1] >= 0 && rgb[2] >= 0;
    const int W = m.data.width(), H = m.data.height();
    m.flat.assign(m.channels.size(), Image(W, H, 1, 0.0f));
    m.front = Image(W, H, 1, kInf);
    if (perElement) m.elementFront.assign(elements.size(), Image(W, H, 1, kInf));
    // Bands of rows in parallel: pixels are independent, and only the surfaces' layout waits for all.
    const int n = std::clamp(workerCount(threads), 1, std::max(H, 1));
    std::vector<MergeBand> bands(n);
    for (int i = 0; i < n; ++i) {
        bands[i].y0 = (int)((long long)H * i / n);
        bands[i].y1 = (int)((long long)H * (i + 1) / n);
    }
    runParallel(n, n, [&](int i) { mergeBand(elements, alpha, coloured ? rgb : nullptr, maxLayers, m, bands[i]); });
    for (const MergeBand& b : bands) {
        m.samples += b.counts.samples;
        m.droppedSamples += b.counts.droppedSamples;
        m.emptyPixels += b.counts.emptyPixels;
        m.truncatedPixels += b.counts.truncatedPixels;
    }
    if (maxLayers == 0) return m;
    const auto merged = [](const MergeBand& b) -> const DeepLayerBuilder& { return b.merged; };
    m.layers = stitchLayers(bands, merged, W, H, m.layerCount);
    if (coloured) m.colour = stitchLayers(bands, merged, W, H, m.layerCount, true);
    for (size_t e = 0; e < m.elementFront.size(); ++e) {
        int layers = 0;
        m.elementLayers.push_back(
            stitchLayers(bands, [e](const MergeBand& b) -> const DeepLayerBuilder& { return b.own[e]; }, W, H, layers));
    }
    return m;
}

} // namespace obscura
