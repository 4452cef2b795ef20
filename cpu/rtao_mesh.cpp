#include "cpu/rtao_mesh.h"

#include "cpu/lanes_scalar.h"
#include "cpu/parallel.h"

#include <cmath>

namespace obscura::glsl {
namespace {
// The kernels' own camera reconstruction and normal handling (kernels/common.glsl), a pixel at a time.
struct SurfaceKernel {
    KernelParams P;
    ConstPlane depth; // the loads of common.glsl's surfaceDepth (0 where not used: not a surface)
    float gatherDepth(int x, int y, bool use) const { return use && depth.valid() ? *depth.at(x, y) : 0.0f; }
#include "kernels/common.glsl"
};
} // namespace
} // namespace obscura::glsl

namespace obscura::cpu {

namespace {

// Grid steps of the edges a triangle can have; an edge is stored from its first endpoint.
constexpr int kDirs = 4;
const int kDx[kDirs] = {1, 0, 1, -1};
const int kDy[kDirs] = {0, 1, 1, 1};

// Whether the surface runs on from texel (x, y) to (x + dx, y + dy). In w (1/z under
// perspective, z orthographic) a plane is affine in pixel coordinates: its steps are equal.
// Across a crease the step lies between the steps beside it; across a depth discontinuity it
// lies far outside them (a step edge), or against them (a surface one or two pixels wide in
// front of another, whose edges would otherwise hang a curtain back to the far surface).
bool connected(const SurfacePoints& s, int x, int y, int dx, int dy) {
    const int W = s.width, H = s.height;
    auto at = [&](int px, int py) { return px < 0 || py < 0 || px >= W || py >= H ? 0.0f : s.w[py * W + px]; };
    const float wp = at(x, y), wq = at(x + dx, y + dy);
    if (!(wp > 0.0f && wq > 0.0f)) return false;
    const float across = wq - wp;
    const float wb = at(x - dx, y - dy), wa = at(x + 2 * dx, y + 2 * dy);
    // 1e-5 of w: the float noise of a surface facing the eye, whose steps are all ~0.
    const float noise = 1e-5f * std::max(wp, wq);
    if (!(wb > 0.0f) && !(wa > 0.0f)) return std::abs(across) <= 0.01f * std::max(wp, wq) + noise;
    const float before = wb > 0.0f ? wp - wb : wa - wq;
    const float after = wa > 0.0f ? wa - wq : before;
    const float lo = std::min(before, after), hi = std::max(before, after);
    const float outside = across < lo ? lo - across : across > hi ? across - hi : 0.0f;
    // Slack from the gentler side only: a step beside this one must not excuse it.
    const float gentle = std::min(std::abs(before), std::abs(after));
    if (outside > 0.5f * gentle + noise) return false;
    // The second step of a staircase (near surface, one-pixel object, far surface) lies between
    // its neighbours too, but is several times the gentler one. So is the step across a crease
    // next to a surface facing the eye. They differ in the tangent planes: across a crease (or
    // a curve) each point lies on the same side of the other's plane (both below a ridge, both
    // above a valley); across a step the far point is below the near one's plane and the near
    // point above the far one's.
    if (std::abs(across) <= 4.0f * gentle + noise) return true;
    const size_t ip = (size_t)y * W + x, iq = (size_t)(y + dy) * W + (x + dx);
    const glm::vec3 e = s.position[iq] - s.position[ip];
    return glm::dot(s.normal[ip], e) * glm::dot(s.normal[iq], -e) > 0.0f;
}

} // namespace

glm::vec2 pixelJitter(int displayX, int displayY) {
    glsl::SurfaceKernel k{};
    const std::uint32_t h = k.hashPixel(displayX, displayY);
    return glm::vec2(k.hashToUnit(h), k.hashToUnit(k.hashU32(h)));
}

SurfacePoints reconstructSurface(const glsl::KernelParams& p, ConstPlane depth, ConstPlane normal, int threads) {
    SurfacePoints s;
    s.width = p.width;
    s.height = p.height;
    const size_t n = (size_t)p.width * p.height;
    s.position.assign(n, glm::vec3(0.0f));
    s.normal.assign(n, glm::vec3(0.0f, 0.0f, 1.0f));
    s.w.assign(n, 0.0f);
    parallelForTiles(Box2i{0, 0, p.width, p.height}, 64, threads, [&](const Box2i& tile) {
        glsl::SurfaceKernel k;
        k.P = p;
        for (int y = tile.y0; y < tile.y1; ++y)
            for (int x = tile.x0; x < tile.x1; ++x) {
                const float d = *depth.at(x, y) * p.depthScale;
                if (!k.isSurfaceDepth(d)) continue;
                const glm::vec2 centre(float(x + p.originX) + 0.5f, float(y + p.originY) + 0.5f);
                const glm::vec3 ray = k.viewRay(centre);
                const glm::vec3 pos = k.positionOnRay(ray, d);
                const float* nn = normal.at(x, y);
                const size_t i = (size_t)y * p.width + x;
                s.position[i] = pos;
                s.normal[i] = k.viewNormal(glm::vec3(nn[0], nn[1], nn[2]), k.viewVector(ray));
                s.w[i] = p.orthographic != 0 ? -pos.z : 1.0f / -pos.z;
                if (!(s.w[i] > 0.0f && std::isfinite(s.w[i]))) s.w[i] = 0.0f;
            }
    });
    return s;
}

SurfaceMesh triangulateSurface(const SurfacePoints& s, bool orthographic, float thickness) {
    const int W = s.width, H = s.height;
    SurfaceMesh m;
    m.vertices = s.position;
    std::vector<std::uint8_t> edgeUses;  // per (texel, direction): triangles using that edge
    if (thickness > 0.0f) edgeUses.assign((size_t)W * H * kDirs, 0);
    auto edgeId = [&](int a, int b) {
        int ax = a % W, ay = a / W, bx = b % W, by = b / W;
        if (by < ay || (by == ay && bx < ax)) std::swap(ax, bx), std::swap(ay, by);
        for (int d = 0; d < kDirs; ++d)
            if (bx - ax == kDx[d] && by - ay == kDy[d]) return ((size_t)ay * W + ax) * kDirs + d;
        return (size_t)0;  // not reached: triangles only join grid neighbours
    };
    // A triangle spanning more than three decades of distance from the eye is a plane seen edge-on
    // within a pixel of its horizon; from its near end, float ray tests against its far
    // vertices are unreliable (and it covers nothing a ray of radius R from its near end needs).
    auto distance = [&](int i) { return glm::length(s.position[i]); };
    auto emit = [&](int a, int b, int c) {
        const float da = distance(a), db = distance(b), dc = distance(c);
        if (std::max(da, std::max(db, dc)) > 1e3f * std::min(da, std::min(db, dc))) return;
        m.triangles.insert(m.triangles.end(), {(std::uint32_t)a, (std::uint32_t)b, (std::uint32_t)c});
        if (!edgeUses.empty())
            for (auto [u, v] : {std::pair{a, b}, std::pair{b, c}, std::pair{c, a}}) ++edgeUses[edgeId(u, v)];
    };
    for (int y = 0; y + 1 < H; ++y)
        for (int x = 0; x + 1 < W; ++x) {
            const int a = y * W + x, b = a + 1, c = a + W, d = c + 1;
            const bool ab = connected(s, x, y, 1, 0), cd = connected(s, x, y + 1, 1, 0);
            const bool ac = connected(s, x, y, 0, 1), bd = connected(s, x + 1, y, 0, 1);
            const bool ad = connected(s, x, y, 1, 1), bc = connected(s, x + 1, y, -1, 1);
            // The diagonal that keeps more triangles; on a tie, the one across the smaller step.
            const int withAd = int(ab && bd && ad) + int(ac && cd && ad);
            const int withBc = int(ab && ac && bc) + int(bd && cd && bc);
            const bool useAd = withAd > withBc ||
                               (withAd == withBc && std::abs(s.w[a] - s.w[d]) <= std::abs(s.w[b] - s.w[c]));
            if (useAd) {
                if (ab && bd && ad) emit(a, b, d);
                if (ac && cd && ad) emit(a, d, c);
            } else {
                if (ab && ac && bc) emit(a, b, c);
                if (bd && cd && bc) emit(b, d, c);
            }
        }
    if (thickness <= 0.0f) return m;

    // The back copy: each point pushed `thickness` along its view ray (along -Z orthographic).
    const std::uint32_t back = (std::uint32_t)m.vertices.size();
    m.vertices.resize(2 * (size_t)back);
    for (std::uint32_t i = 0; i < back; ++i) {
        const glm::vec3 p = m.vertices[i];
        const glm::vec3 away = orthographic ? glm::vec3(0.0f, 0.0f, -1.0f) : p * (1.0f / std::max(glm::length(p), 1e-30f));
        m.vertices[back + i] = p + away * thickness;
    }
    const size_t front = m.triangles.size();
    for (size_t t = 0; t < front; t += 3)
        m.triangles.insert(m.triangles.end(), {back + m.triangles[t], back + m.triangles[t + 1], back + m.triangles[t + 2]});
    // Walls along edges used by one triangle only: the outline of each connected sheet.
    for (size_t t = 0; t < front; t += 3)
        for (int e = 0; e < 3; ++e) {
            const std::uint32_t u = m.triangles[t + e], v = m.triangles[t + (e + 1) % 3];
            if (edgeUses[edgeId((int)u, (int)v)] != 1) continue;
            m.triangles.insert(m.triangles.end(), {u, v, back + v, u, back + v, back + u});
        }
    return m;
}

} // namespace obscura::cpu
