#include "cpu/discs_cpu.h"

#include "base/error.h"
#include "cpu/isa.h"
#include "cpu/parallel.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <mutex>

namespace obscura::cpu {

namespace {

constexpr int kChannels = kDiscChannels;
constexpr int kMaxLevels = 16;  // p.discLevelOffset holds 16

int levelSize(int n, int level) { return (n + (1 << level) - 1) >> level; }

// One texel's channels, each in its own plane.
struct Texel {
    float* p;
    size_t stride;
    float& operator[](int c) const { return p[(size_t)c * stride]; }
};

Texel texel(DiscPyramid& pyr, int level, int x, int y) {
    return {pyr.data.get() + (size_t)pyr.offsets[level] + (size_t)y * levelSize(pyr.width, level) + x, pyr.stride};
}

// A node's children farther apart in depth than this many node sizes (on the screen, at the
// largest child's depth) stay two elements: a pole and the ground far behind it merged into
// one would be a ghost between them. Measured on the report's scenes (discs, low, hard
// levels): 4 node sizes 27.68 dB, 8 27.66, 16 27.55, never 27.32.
constexpr double kSplitDepthNodes = 4.0;

struct Element { double area, pos[3], n[3]; };

// Channels 0-6 and 17-23 of node (x, y) of `level` from the (up to eight) elements of its
// children: one element, or two where some lie far behind the largest (kSplitDepthNodes),
// each child element joining the one nearer in depth. The larger goes first.
void mergeElements(DiscPyramid& pyr, int level, int x, int y, const Texel& t) {
    const int cw = levelSize(pyr.width, level - 1), ch = levelSize(pyr.height, level - 1);
    Element e[8];
    int count = 0;
    for (int j = 2 * y; j < std::min(2 * y + 2, ch); ++j)
        for (int i = 2 * x; i < std::min(2 * x + 2, cw); ++i) {
            const Texel c = texel(pyr, level - 1, i, j);
            for (int first : {0, 17}) {
                if (!(c[first + 3] > 0)) continue;
                Element& q = e[count++];
                q.area = c[first + 3];
                for (int k = 0; k < 3; ++k) q.pos[k] = c[first + k], q.n[k] = c[first + 4 + k];
            }
        }
    int largest = 0, farthest = 0;
    for (int q = 1; q < count; ++q)
        if (e[q].area > e[largest].area) largest = q;
    auto gap = [&](int q, int from) { return std::abs(e[q].pos[2] - e[from].pos[2]); };
    for (int q = 1; q < count; ++q)
        if (gap(q, largest) > gap(farthest, largest)) farthest = q;
    // World size of one node of `level` at the largest element's depth (orthographic: invFx
    // is already world units per pixel).
    const double nodeSize = (double)(1 << level) * pyr.invF * (pyr.orthographic ? 1.0 : std::abs(e[largest].pos[2]));
    const bool split = count > 1 && gap(farthest, largest) > kSplitDepthNodes * nodeSize;
    double sum[2][7] = {};
    for (int q = 0; q < count; ++q) {
        double* g = sum[split && gap(q, farthest) < gap(q, largest) ? 1 : 0];
        g[3] += e[q].area;
        for (int k = 0; k < 3; ++k) g[k] += e[q].area * e[q].pos[k], g[4 + k] += e[q].area * e[q].n[k];
    }
    const int big = sum[1][3] > sum[0][3] ? 1 : 0;
    for (int slot = 0; slot < 2; ++slot) {
        const double* g = sum[slot == 0 ? big : 1 - big];
        const int o = slot == 0 ? 0 : 17;
        const double area = g[3];
        const double nlen = std::sqrt(g[4] * g[4] + g[5] * g[5] + g[6] * g[6]);
        const bool used = area > 0 && nlen > 0;
        for (int k = 0; k < 3; ++k) {
            t[o + k] = used ? (float)(g[k] / area) : 0.0f;
            t[o + 4 + k] = used ? (float)(g[4 + k] / nlen) : 0.0f;
        }
        t[o + 3] = used ? (float)area : 0.0f;
    }
}

// Level `level` from the one below: its elements (mergeElements), area-weighted visibility;
// the walls' likewise (centre, normal and length by wall area). With `visibilityOnly`,
// only channel 7 (the rest is already merged).
void mergeLevel(DiscPyramid& pyr, int level, bool visibilityOnly, int threads) {
    const int w = levelSize(pyr.width, level), h = levelSize(pyr.height, level);
    const int cw = levelSize(pyr.width, level - 1), ch = levelSize(pyr.height, level - 1);
    parallelForTiles(Box2i{0, 0, w, h}, w, 8, threads, [&](const Box2i& rows) {
    for (int y = rows.y0; y < rows.y1; ++y)
        for (int x = 0; x < w; ++x) {
            double sum[kChannels] = {};
            for (int j = 2 * y; j < std::min(2 * y + 2, ch); ++j)
                for (int i = 2 * x; i < std::min(2 * x + 2, cw); ++i) {
                    const Texel c = texel(pyr, level - 1, i, j);
                    const double a = c[3];
                    sum[3] += a;
                    sum[7] += a * c[7];
                    const double aw = c[11];
                    for (int k = 0; k < 3; ++k) sum[8 + k] += aw * c[8 + k], sum[12 + k] += aw * c[12 + k];
                    sum[11] += aw;
                    sum[15] += aw * c[15];
                    sum[16] += aw * c[16];
                }
            const Texel t = texel(pyr, level, x, y);
            const double area = sum[3];
            if (visibilityOnly) {
                t[7] = area > 0 ? (float)(sum[7] / area) : 1.0f;
                continue;
            }
            mergeElements(pyr, level, x, y, t);
            const bool used = t[3] > 0;
            t[7] = used ? (float)(sum[7] / area) : 1.0f;
            const double wallArea = sum[11];
            const double wlen = std::sqrt(sum[12] * sum[12] + sum[13] * sum[13] + sum[14] * sum[14]);
            const bool walled = wallArea > 0 && wlen > 0;
            for (int k = 0; k < 3; ++k) {
                t[8 + k] = walled ? (float)(sum[8 + k] / wallArea) : 0.0f;
                t[12 + k] = walled ? (float)(sum[12 + k] / wlen) : 0.0f;
            }
            t[11] = walled ? (float)wallArea : 0.0f;
            t[15] = walled ? (float)(sum[15] / wallArea) : 0.0f;
            t[16] = walled ? (float)(sum[16] / wallArea) : 0.0f;
        }
    });
}

// The coarsest top level any pixel takes (kernels/discs.glsl's discTopLevel), from the
// largest reach of any surface texel (discReachPixels, taken per tile by the base kernel).
int frameTopLevel(const KernelParams& p, float reach, int levels) {
    int top = 0;
    auto windowAt = [&](int level) { return p.discWindow + (level >= p.discWideFrom ? 1 : 0); };
    while (top + 1 < levels && (float)(2 * windowAt(top + 1)) * (float)(1 << top) < reach) ++top;
    return top;
}

} // namespace

DiscPyramid buildDiscPyramid(KernelParams& p, ConstPlane depth, ConstPlane normal, int threads) {
    DiscPyramid pyr;
    pyr.width = p.width;
    pyr.height = p.height;
    pyr.invF = p.invFx;
    pyr.orthographic = p.orthographic != 0;
    // Enough levels for the top window to span the frame, at most kMaxLevels.
    int allLevels = 1;
    while (allLevels < kMaxLevels && (levelSize(p.width, allLevels - 1) > 1 || levelSize(p.height, allLevels - 1) > 1))
        ++allLevels;
    long long texels = 0;
    for (int l = 0; l < allLevels; ++l) {
        pyr.offsets.push_back((int)std::min<long long>(texels, INT_MAX));
        texels += (long long)levelSize(p.width, l) * levelSize(p.height, l);
    }
    if (texels * kChannels + kDiscPad >= INT_MAX)
        throw Error("the frame is too large for --method discs (" + std::to_string(texels) + " elements)");

    // Room for every level, not zeroed: only the levels up to the frame's top level are
    // written, and the pages of the others are never touched.
    pyr.stride = (size_t)texels;
    pyr.floats = pyr.stride * kChannels + kDiscPad;
    p.discStride = (int)pyr.stride;
    pyr.data = allocateBigFloats(pyr.floats);
    std::fill(pyr.data.get() + pyr.stride * kChannels, pyr.data.get() + pyr.floats, 0.0f);
    const IsaKernels& k = cpuKernelsFor({depth, normal});
    float* base = pyr.data.get();
    std::mutex reachLock;
    float reach = 0.0f;
    parallelForTiles(Box2i{0, 0, p.width, p.height}, kLaneTileWidth, kLaneTileHeight, threads,
                     [&](const Box2i& tile) {
                         const float r = k.discsBaseTile(p, depth, normal, base, tile);
                         std::lock_guard<std::mutex> hold(reachLock);
                         reach = std::max(reach, r);
                     });

    const int top = frameTopLevel(p, reach, allLevels);
    p.discTop = top;
    pyr.offsets.resize(top + 1);
    for (int l = 1; l <= top; ++l) mergeLevel(pyr, l, false, threads);
    for (int l = 0; l < kMaxLevels; ++l) p.discLevelOffset[l / 4][l % 4] = l <= top ? pyr.offsets[l] : 0;
    return pyr;
}

void setDiscVisibility(DiscPyramid& pyr, ConstPlane ao, int threads) {
    for (int y = 0; y < pyr.height; ++y)
        for (int x = 0; x < pyr.width; ++x) texel(pyr, 0, x, y)[7] = *ao.at(x, y);
    for (int l = 1; l < (int)pyr.offsets.size(); ++l) mergeLevel(pyr, l, true, threads);
}

void runDiscs(const KernelParams& p, const DiscPyramid& pyramid, ConstPlane normal, MutablePlane ao, int threads,
              const std::string& isa) {
    const IsaKernels& k = isa.empty() ? cpuKernels() : cpuKernelsNamed(isa);
    const float* data = pyramid.data.get();
    parallelForTiles(Box2i{0, 0, p.width, p.height}, kLaneTileWidth, kLaneTileHeight, threads,
                     [&](const Box2i& tile) { k.discsTile(p, data, normal, ao, tile); });
}

} // namespace obscura::cpu
