// Pinhole camera looking from CameraSpec::eye at its target, world +Z up.
// Camera space is OpenGL's (looks down -Z, +Y up); pixel centres at (x + 0.5, y + 0.5).
#pragma once
#include "scene.h"

#include <cmath>

namespace reference {

struct PinholeCamera {
    glm::dvec3 eye, right, up, back;  // columns of camera_to_world
    double horizontalFovRad = 0, focalPx = 0;
    int width = 0, height = 0;

    static PinholeCamera lookAt(const CameraSpec& spec, int width, int height) {
        PinholeCamera c;
        const glm::dvec3 forward = glm::normalize(spec.target - spec.eye);
        glm::dvec3 side = glm::cross(forward, glm::dvec3(0, 0, 1));
        if (glm::length(side) < 1e-9) side = glm::cross(forward, glm::dvec3(0, 1, 0));  // looking straight up/down
        c.eye = spec.eye;
        c.right = glm::normalize(side);
        c.up = glm::cross(c.right, forward);
        c.back = -forward;
        c.horizontalFovRad = spec.horizontalFovRad;
        c.width = width;
        c.height = height;
        c.focalPx = 0.5 * width / std::tan(0.5 * spec.horizontalFovRad);
        return c;
    }

    // World direction through pixel position (px, py), scaled to planar depth 1.
    glm::dvec3 ray(double px, double py) const {
        const double x = (px - 0.5 * width) / focalPx, y = -(py - 0.5 * height) / focalPx;
        return x * right + y * up - back;
    }

    // Row-major camera_to_world (OpenGL convention), as the sidecar stores it.
    glm::dmat4 cameraToWorld() const {
        glm::dmat4 m(1.0);  // glm: m[column][row]
        m[0] = glm::dvec4(right, 0);
        m[1] = glm::dvec4(up, 0);
        m[2] = glm::dvec4(back, 0);
        m[3] = glm::dvec4(eye, 1);
        return m;
    }
};

} // namespace reference
