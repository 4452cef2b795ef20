// Embree 3 scene built from a reference::Scene: first-hit and shadow queries.
#pragma once
#include "scene.h"

#include <embree3/rtcore.h>

namespace reference {

struct Hit {
    bool found = false;
    float t = 0;
    glm::dvec3 normal{0.0};  // unit geometric normal, turned to face the ray
    glm::vec3 albedo{0.0f};
    bool backFace = false;   // the ray leaves the solid here: its outward normal faces along the ray
};

class Tracer {
public:
    explicit Tracer(const Scene& scene);
    ~Tracer();
    Tracer(const Tracer&) = delete;
    Tracer& operator=(const Tracer&) = delete;

    // First hit in (tnear, tfar). `direction` need not be unit length; t is in its units.
    Hit intersect(const glm::dvec3& origin, const glm::dvec3& direction, float tnear, float tfar) const;
    bool occluded(const glm::dvec3& origin, const glm::dvec3& direction, float tnear, float tfar) const;
    // Up to 8 rays from one origin as one Embree packet (AO rays share their origin):
    // t[i] = first hit distance in [0, tfar], or +inf for a miss.
    void hitDistances8(const glm::dvec3& origin, const glm::dvec3* directions, int count, float tfar, float* t) const;

private:
    RTCDevice device_ = nullptr;
    RTCScene scene_ = nullptr;
    const Scene& source_;
    unsigned sphereGeometry_ = RTC_INVALID_GEOMETRY_ID;
};

} // namespace reference
