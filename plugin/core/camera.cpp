#include "camera.h"

#include <cmath>

namespace obscura {

// A camera of `fx` pixels per unit (per unit of depth, in perspective) across, centred on a
// displayWidth x displayHeight display window whose pixels are `pixelAspect` wide per unit high.
static Camera centred(Projection projection, double fx, int displayWidth, int displayHeight,
                      double pixelAspect) {
    Camera c;
    c.projection = projection;
    c.fx = fx;
    c.fy = fx * pixelAspect;
    c.cx = 0.5 * displayWidth;
    c.cy = 0.5 * displayHeight;
    c.displayWidth = displayWidth;
    c.displayHeight = displayHeight;
    return c;
}

Camera Camera::perspectiveFromFov(double horizontalFovRad, int displayWidth, int displayHeight,
                                  double pixelAspect) {
    return centred(Projection::Perspective, 0.5 * displayWidth / std::tan(0.5 * horizontalFovRad), displayWidth,
                   displayHeight, pixelAspect);
}

Camera Camera::perspectiveFromFilmBack(double focal, double aperture, int displayWidth, int displayHeight,
                                      double pixelAspect) {
    return centred(Projection::Perspective, displayWidth * focal / aperture, displayWidth, displayHeight, pixelAspect);
}

Camera Camera::orthographic(double width, int displayWidth, int displayHeight, double pixelAspect) {
    return centred(Projection::Orthographic, displayWidth / width, displayWidth, displayHeight, pixelAspect);
}

double Camera::horizontalFovRad(int displayWidth) const {
    if (projection != Projection::Perspective || fx <= 0) return 0;
    return 2.0 * std::atan(0.5 * displayWidth / fx);
}

double Camera::orthoWidth(int displayWidth) const {
    if (projection != Projection::Orthographic || fx <= 0) return 0;
    return displayWidth / fx;
}

glm::dvec3 Camera::project(const glm::dvec3& p) const {
    const double depth = -p.z;
    if (projection == Projection::Orthographic)
        return {cx + fx * p.x, cy - fy * p.y, depth};
    return {cx + fx * p.x / depth, cy - fy * p.y / depth, depth};
}

glm::dvec3 Camera::unproject(double px, double py, double depth, bool radial) const {
    const double x = (px - cx) / fx, y = -(py - cy) / fy;
    if (projection == Projection::Orthographic) return {x, y, -depth};
    const glm::dvec3 ray(x, y, -1.0);  // planar depth 1
    return radial ? ray * (depth / glm::length(ray)) : ray * depth;
}

glm::dvec3 Camera::projectWorld(const glm::dvec3& pWorld) const {
    return project(glm::dvec3(worldToCamera() * glm::dvec4(pWorld, 1.0)));
}

// Negating the camera's Z row turns "z forward" into "z backward"; both sides
// keep x right and y up, so nothing else changes.
static glm::dmat4 flipCameraZ(const glm::dmat4& worldToCamera) {
    glm::dmat4 m = worldToCamera;
    for (int col = 0; col < 4; ++col) m[col][2] = -m[col][2];
    return m;
}

glm::dmat4 exrWorldToCameraToGL(const glm::dmat4& exrWorldToCamera) { return flipCameraZ(exrWorldToCamera); }
glm::dmat4 glWorldToCameraToExr(const glm::dmat4& glWorldToCamera) { return flipCameraZ(glWorldToCamera); }

} // namespace obscura
