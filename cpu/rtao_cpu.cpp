#include "cpu/rtao_cpu.h"

#include "base/error.h"
#include "cpu/parallel.h"
#include "cpu/rtao_mesh.h"

#include <embree3/rtcore.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

namespace obscura::cpu {

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// A ray's context: its pixel's display position and the parameter block, so that hits whose
// image lies beyond p.maxRadiusPixels of the pixel are ignored, as HBAO ignores samples there:
// a host rendering tiles with an apron of that cap then gets the whole frame's values.
struct CappedContext {
    RTCIntersectContext base;  // first: Embree hands the filter a pointer to it
    const glsl::KernelParams* p;
    glm::vec2 centre;
};

void capFilter(const RTCFilterFunctionNArguments* args) {
    const auto* c = reinterpret_cast<const CappedContext*>(args->context);
    const glsl::KernelParams& p = *c->p;
    for (unsigned i = 0; i < args->N; ++i) {
        if (args->valid[i] != -1) continue;
        const float t = RTCRayN_tfar(args->ray, args->N, i);  // the candidate hit's distance
        const glm::vec3 h(RTCRayN_org_x(args->ray, args->N, i) + t * RTCRayN_dir_x(args->ray, args->N, i),
                          RTCRayN_org_y(args->ray, args->N, i) + t * RTCRayN_dir_y(args->ray, args->N, i),
                          RTCRayN_org_z(args->ray, args->N, i) + t * RTCRayN_dir_z(args->ray, args->N, i));
        const float scale = p.orthographic != 0 ? 1.0f : 1.0f / std::max(-h.z, 1e-30f);
        const glm::vec2 image(p.cx + p.fx * h.x * scale, p.cy - p.fy * h.y * scale);
        const glm::vec2 reach = image - c->centre;
        if ((p.orthographic == 0 && !(h.z < 0.0f)) || glm::dot(reach, reach) > p.maxRadiusPixels * p.maxRadiusPixels)
            args->valid[i] = 0;
    }
}

// The Embree scene of a mesh; released with it.
class MeshScene {
public:
    MeshScene(const SurfaceMesh& m, int threads) {
        const std::string config = "threads=" + std::to_string(threads);
        device_ = rtcNewDevice(config.c_str());
        if (!device_) throw Error("Embree: cannot create a device");
        scene_ = rtcNewScene(device_);
        rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_MEDIUM);
        if (!m.triangles.empty()) {
            RTCGeometry g = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
            // Buffers Embree allocates: it pads vertex buffers for its 16-byte loads.
            void* v = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, sizeof(glm::vec3),
                                              m.vertices.size());
            void* t = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(std::uint32_t),
                                              m.triangles.size() / 3);
            if (!v || !t) throw Error("Embree: out of memory for " + std::to_string(m.triangles.size() / 3) + " triangles");
            std::memcpy(v, m.vertices.data(), m.vertices.size() * sizeof(glm::vec3));
            std::memcpy(t, m.triangles.data(), m.triangles.size() * sizeof(std::uint32_t));
            rtcSetGeometryIntersectFilterFunction(g, &capFilter);
            rtcSetGeometryOccludedFilterFunction(g, &capFilter);
            rtcCommitGeometry(g);
            rtcAttachGeometry(scene_, g);
            rtcReleaseGeometry(g);
        }
        rtcCommitScene(scene_);
        if (rtcGetDeviceError(device_) != RTC_ERROR_NONE) throw Error("Embree: the scene could not be built");
    }
    ~MeshScene() {
        rtcReleaseScene(scene_);
        rtcReleaseDevice(device_);
    }
    MeshScene(const MeshScene&) = delete;
    MeshScene& operator=(const MeshScene&) = delete;

    // Distance to the first hit within tfar (and the cap of `context`), or +inf.
    float hitDistance(CappedContext& context, const glm::vec3& o, const glm::vec3& d, float tfar) const {
        rtcInitIntersectContext(&context.base);
        RTCRayHit rh{};
        rh.ray.org_x = o.x, rh.ray.org_y = o.y, rh.ray.org_z = o.z;
        rh.ray.dir_x = d.x, rh.ray.dir_y = d.y, rh.ray.dir_z = d.z;
        rh.ray.tnear = 0.0f;
        rh.ray.tfar = tfar;
        rh.ray.mask = 0xffffffffu;
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(scene_, &context.base, &rh);
        return rh.hit.geomID == RTC_INVALID_GEOMETRY_ID ? std::numeric_limits<float>::infinity() : rh.ray.tfar;
    }
    bool occluded(CappedContext& context, const glm::vec3& o, const glm::vec3& d, float tfar) const {
        rtcInitIntersectContext(&context.base);
        RTCRay r{};
        r.org_x = o.x, r.org_y = o.y, r.org_z = o.z;
        r.dir_x = d.x, r.dir_y = d.y, r.dir_z = d.z;
        r.tnear = 0.0f;
        r.tfar = tfar;
        r.mask = 0xffffffffu;
        rtcOccluded1(scene_, &context.base, &r);
        return r.tfar < 0.0f;  // Embree sets -inf on a hit
    }

private:
    RTCDevice device_ = nullptr;
    RTCScene scene_ = nullptr;
};

// AO of one surface texel: `rays` directions over its hemisphere, a Fibonacci lattice
// (stratified elevation, golden-ratio azimuth) rotated by the texel's hash.
float traceTexel(const MeshScene& scene, const SurfacePoints& s, size_t i, int displayX, int displayY,
                 const glsl::KernelParams& p, int rays) {
    const glm::vec3 n = s.normal[i];
    // Frame around n (Duff et al. 2017).
    const float sgn = n.z >= 0.0f ? 1.0f : -1.0f;
    const float a = -1.0f / (sgn + n.z), b = n.x * n.y * a;
    const glm::vec3 b1(1.0f + sgn * n.x * n.x * a, sgn * b, -sgn * n.x), b2(b, sgn + n.y * n.y * a, -n.y);
    // Lifted off the mesh by more than float rounding of its vertices (~1e-7 of their distance).
    const glm::vec3 origin = s.position[i] + n * (1e-5f * glm::length(s.position[i]));
    const glm::vec2 jitter = pixelJitter(displayX, displayY);
    CappedContext context{{}, &p, glm::vec2(float(displayX) + 0.5f, float(displayY) + 0.5f)};
    const float j1 = jitter.x, j2 = jitter.y;
    double occlusion = 0.0;
    for (int k = 0; k < rays; ++k) {
        const float u = (float(k) + j1) / float(rays);        // [0, 1)
        const float phi = 6.2831853f * std::fmod(float(k) * 0.618034f + j2, 1.0f);
        const float z = p.cosineWeighting != 0 ? std::sqrt(1.0f - u) : 1.0f - u;  // cosine / uniform, > 0
        const float r = std::sqrt(std::max(1.0f - z * z, 0.0f));
        const glm::vec3 d = b1 * (r * std::cos(phi)) + b2 * (r * std::sin(phi)) + n * z;
        if (p.linearFalloff != 0) {
            const float t = scene.hitDistance(context, origin, d, p.radius);
            if (t <= p.radius) occlusion += 1.0 - t / p.radius;
        } else if (scene.occluded(context, origin, d, p.radius)) {
            occlusion += 1.0;
        }
    }
    return (float)std::min(std::max(1.0 - occlusion / rays, 0.0), 1.0);
}

bool onGrid(int display, int grid) { return ((display % grid) + grid) % grid == 0; }
int gridBelow(int display, int grid) { return display - (((display % grid) + grid) % grid); }

} // namespace

void runRtao(const glsl::KernelParams& p, ConstPlane depth, ConstPlane normal, MutablePlane ao, const RtaoOptions& o,
             int threads, RtaoStats* stats) {
    RtaoStats st;
    auto t0 = Clock::now();
    const SurfacePoints s = reconstructSurface(p, depth, normal, threads);
    float thickness = o.thickness;
    if (!std::isfinite(thickness)) {  // a height field: walls reaching past the farthest point by more than a ray's reach
        float farthest = 0.0f, nearest = std::numeric_limits<float>::max();
        for (size_t i = 0; i < s.position.size(); ++i) {
            if (!s.surface((int)i)) continue;
            const float d = p.orthographic != 0 ? -s.position[i].z : glm::length(s.position[i]);
            farthest = std::max(farthest, d);
            nearest = std::min(nearest, d);
        }
        thickness = farthest > nearest ? farthest - nearest + 2.0f * p.radius : 2.0f * p.radius;
    }
    const SurfaceMesh mesh = triangulateSurface(s, p.orthographic != 0, thickness);
    st.triangles = (long long)mesh.triangles.size() / 3;
    st.meshSeconds = since(t0);
    t0 = Clock::now();
    const MeshScene scene(mesh, threads);
    st.bvhSeconds = since(t0);
    t0 = Clock::now();

    const int W = p.width, H = p.height, G = std::max(o.grid, 1);
    // Pass 1: the texels on the grid (every texel when G = 1).
    std::vector<float> traced((size_t)W * H, -1.0f);
    parallelForTiles(Box2i{0, 0, W, H}, 32, threads, [&](const Box2i& tile) {
        for (int y = tile.y0; y < tile.y1; ++y)
            for (int x = tile.x0; x < tile.x1; ++x) {
                const size_t i = (size_t)y * W + x;
                const int dx = x + p.originX, dy = y + p.originY;
                if (!s.surface(i)) *ao.at(x, y) = 1.0f;
                else if (onGrid(dx, G) && onGrid(dy, G)) traced[i] = traceTexel(scene, s, i, dx, dy, p, o.rays);
            }
    });
    long long rays = 0;
    for (float v : traced) rays += v >= 0.0f ? o.rays : 0;
    // Pass 2: the rest from the four grid texels around them, weighted by the bilinear weight
    // times how well each lies on this texel's tangent plane and faces its way; a texel whose
    // neighbours are all on other surfaces (or sky) is traced itself.
    const float planeScale = 1.0f / (0.05f * p.radius);
    std::vector<unsigned char> selfTraced((size_t)W * H, 0);
    parallelForTiles(Box2i{0, 0, W, H}, 32, threads, [&](const Box2i& tile) {
        for (int y = tile.y0; y < tile.y1; ++y)
            for (int x = tile.x0; x < tile.x1; ++x) {
                const size_t i = (size_t)y * W + x;
                if (!s.surface(i)) continue;
                if (traced[i] >= 0.0f) {
                    *ao.at(x, y) = traced[i];
                    continue;
                }
                const int dx = x + p.originX, dy = y + p.originY;
                const int gx = gridBelow(dx, G) - p.originX, gy = gridBelow(dy, G) - p.originY;
                double sum = 0.0, weights = 0.0;
                for (int cy = 0; cy < 2; ++cy)
                    for (int cx = 0; cx < 2; ++cx) {
                        const int qx = gx + cx * G, qy = gy + cy * G;
                        if (qx < 0 || qy < 0 || qx >= W || qy >= H) continue;
                        const size_t q = (size_t)qy * W + qx;
                        if (traced[q] < 0.0f) continue;
                        const float bilinear = (1.0f - std::abs(float(qx - x)) / G) * (1.0f - std::abs(float(qy - y)) / G);
                        const float off = glm::dot(s.normal[i], s.position[q] - s.position[i]) * planeScale;
                        const float facing = std::max(glm::dot(s.normal[i], s.normal[q]), 0.0f);
                        const float f2 = facing * facing;
                        const float w = bilinear * f2 * f2 / (1.0f + off * off);
                        sum += w * traced[q];
                        weights += w;
                    }
                if (weights > 1e-3) {
                    *ao.at(x, y) = (float)(sum / weights);
                } else {
                    *ao.at(x, y) = traceTexel(scene, s, i, dx, dy, p, o.rays);
                    selfTraced[i] = 1;
                }
            }
    });
    for (unsigned char t : selfTraced) rays += t ? o.rays : 0;
    st.rays = rays;
    st.traceSeconds = since(t0);
    if (stats) *stats = st;
}

} // namespace obscura::cpu
