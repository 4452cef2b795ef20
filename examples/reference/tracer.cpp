#include "tracer.h"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace reference {
namespace {

void check(RTCDevice device, const char* what) {
    const RTCError e = rtcGetDeviceError(device);
    if (e != RTC_ERROR_NONE) throw std::runtime_error(std::string("embree: ") + what + " failed (error " + std::to_string(int(e)) + ")");
}

RTCRayHit makeRay(const glm::dvec3& o, const glm::dvec3& d, float tnear, float tfar) {
    RTCRayHit rh{};
    rh.ray.org_x = float(o.x), rh.ray.org_y = float(o.y), rh.ray.org_z = float(o.z);
    rh.ray.dir_x = float(d.x), rh.ray.dir_y = float(d.y), rh.ray.dir_z = float(d.z);
    rh.ray.tnear = tnear;
    rh.ray.tfar = tfar;
    rh.ray.mask = 0xffffffffu;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    return rh;
}

} // namespace

Tracer::Tracer(const Scene& scene) : source_(scene) {
    device_ = rtcNewDevice(nullptr);
    if (!device_) throw std::runtime_error("embree: cannot create a device");
    scene_ = rtcNewScene(device_);
    // Robust traversal: the terrain spans centimetres to kilometres in one BVH.
    rtcSetSceneFlags(scene_, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_HIGH);

    for (unsigned id = 0; id < scene.meshes.size(); ++id) {
        const Mesh& m = scene.meshes[id];
        RTCGeometry g = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
        auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                              3 * sizeof(float), m.vertices.size()));
        for (size_t i = 0; i < m.vertices.size(); ++i)
            for (int c = 0; c < 3; ++c) v[3 * i + c] = m.vertices[i][c];
        auto* t = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                 3 * sizeof(unsigned), m.triangles.size()));
        for (size_t i = 0; i < m.triangles.size(); ++i)
            for (int c = 0; c < 3; ++c) t[3 * i + c] = m.triangles[i][c];
        rtcCommitGeometry(g);
        rtcAttachGeometryByID(scene_, g, id);  // geomID = mesh index
        rtcReleaseGeometry(g);
    }
    if (!scene.spheres.empty()) {
        RTCGeometry g = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_SPHERE_POINT);
        auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4,
                                                              4 * sizeof(float), scene.spheres.size()));
        for (size_t i = 0; i < scene.spheres.size(); ++i) {
            const Sphere& s = scene.spheres[i];
            v[4 * i] = float(s.centre.x), v[4 * i + 1] = float(s.centre.y), v[4 * i + 2] = float(s.centre.z);
            v[4 * i + 3] = float(s.radius);
        }
        rtcCommitGeometry(g);
        sphereGeometry_ = static_cast<unsigned>(scene.meshes.size());
        rtcAttachGeometryByID(scene_, g, sphereGeometry_);
        rtcReleaseGeometry(g);
    }
    rtcCommitScene(scene_);
    check(device_, "building the scene");
}

Tracer::~Tracer() {
    rtcReleaseScene(scene_);
    rtcReleaseDevice(device_);
}

Hit Tracer::intersect(const glm::dvec3& origin, const glm::dvec3& direction, float tnear, float tfar) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit rh = makeRay(origin, direction, tnear, tfar);
    rtcIntersect1(scene_, &context, &rh);
    Hit h;
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return h;
    h.found = true;
    h.t = rh.ray.tfar;
    glm::dvec3 n(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z);
    if (rh.hit.geomID == sphereGeometry_) {
        // Embree's sphere normal is float; recompute it from the centre in double.
        const Sphere& s = source_.spheres[rh.hit.primID];
        n = origin + double(h.t) * direction - s.centre;
        h.albedo = s.albedo;
    } else {
        const Mesh& m = source_.meshes[rh.hit.geomID];
        h.albedo = m.triangleAlbedo.empty() ? m.albedo : m.triangleAlbedo[rh.hit.primID];
    }
    n = glm::normalize(n);
    // Every shape is wound outwards (shapes.cpp: cross(v1 - v0, v2 - v0), which is Embree's Ng), and
    // a sphere's normal points away from its centre, so the side the ray meets is known.
    h.backFace = glm::dot(n, direction) > 0;
    if (h.backFace) n = -n;  // two-sided surfaces
    h.normal = n;
    return h;
}

bool Tracer::occluded(const glm::dvec3& origin, const glm::dvec3& direction, float tnear, float tfar) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit rh = makeRay(origin, direction, tnear, tfar);
    rtcOccluded1(scene_, &context, &rh.ray);
    return rh.ray.tfar < 0;  // embree sets tfar = -inf on a hit
}

void Tracer::hitDistances8(const glm::dvec3& origin, const glm::dvec3* directions, int count, float tfar,
                           float* t) const {
    alignas(32) int valid[8];
    alignas(32) RTCRayHit8 rh;
    for (int i = 0; i < 8; ++i) {
        valid[i] = i < count ? -1 : 0;
        const glm::dvec3 d = i < count ? directions[i] : glm::dvec3(0, 0, 1);
        rh.ray.org_x[i] = float(origin.x), rh.ray.org_y[i] = float(origin.y), rh.ray.org_z[i] = float(origin.z);
        rh.ray.dir_x[i] = float(d.x), rh.ray.dir_y[i] = float(d.y), rh.ray.dir_z[i] = float(d.z);
        rh.ray.tnear[i] = 0;
        rh.ray.tfar[i] = tfar;
        rh.ray.mask[i] = 0xffffffffu;
        rh.ray.time[i] = 0;
        rh.ray.flags[i] = 0;
        rh.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
    }
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    rtcIntersect8(valid, scene_, &context, &rh);
    for (int i = 0; i < count; ++i)
        t[i] = rh.hit.geomID[i] == RTC_INVALID_GEOMETRY_ID ? std::numeric_limits<float>::infinity() : rh.ray.tfar[i];
}

} // namespace reference
