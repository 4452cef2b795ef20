// The camera model and every conversion between camera conventions.
// Internal convention (same as --camera-to-world): OpenGL camera space, looking
// down -Z, +Y up, +X right. Pixel (x, y) has its centre at (x + 0.5, y + 0.5) in
// display-window coordinates, y down.
#pragma once
#include <glm/glm.hpp>
#include <string>

namespace obscura {

enum class Projection { Perspective, Orthographic };

struct Camera {
    Projection projection = Projection::Perspective;
    // Perspective: focal length in pixels. Orthographic: pixels per world unit.
    double fx = 0, fy = 0;
    // Principal point in display-window pixel coordinates (centre = W/2, H/2).
    double cx = 0, cy = 0;
    glm::dmat4 cameraToWorld{1.0};  // OpenGL convention
    bool hasPose = false;            // false: only intrinsics are known
    std::string source;              // where it came from, for --inspect / --report
    double fitResidualPx = -1;       // RMS reprojection error of a fit, -1 if not fitted
    // The display window's size the camera was made for (its principal point at the centre), so a
    // host can refuse one made for another frame; 0: not known (intrinsics given as they are).
    int displayWidth = 0, displayHeight = 0;

    bool valid() const { return fx > 0 && fy > 0; }

    // Horizontal field of view across the display window of width `displayWidth`.
    // fx = (W/2) / tan(fov/2); fy = fx * pixelAspect (pixelAspect = pixel width / height,
    // so a world square covers pixelAspect times more rows than columns); principal
    // point at the display centre.
    static Camera perspectiveFromFov(double horizontalFovRad, int displayWidth, int displayHeight,
                                     double pixelAspect = 1.0);
    // The same from a focal length and the horizontal film back (aperture) it spans, in one unit
    // (mm, as a compositing app's camera node): the film back maps onto the display window's
    // width, so fx = W * focal / aperture.
    static Camera perspectiveFromFilmBack(double focal, double aperture, int displayWidth, int displayHeight,
                                          double pixelAspect = 1.0);
    // Orthographic camera `width` world units across the display window.
    static Camera orthographic(double width, int displayWidth, int displayHeight, double pixelAspect = 1.0);

    // 0 for an orthographic camera.
    double horizontalFovRad(int displayWidth) const;
    // World units across the display window (orthographic only, 0 otherwise).
    double orthoWidth(int displayWidth) const;
    glm::dmat4 worldToCamera() const { return glm::inverse(cameraToWorld); }

    // Camera-space point (OpenGL convention) -> display pixel coords (x, y) and planar depth (-z).
    glm::dvec3 project(const glm::dvec3& pCam) const;
    // Display pixel coords + depth -> camera-space point. `radial` = depth is distance to the eye.
    // Orthographic cameras have no eye point: radial depth is taken as planar there.
    glm::dvec3 unproject(double px, double py, double depth, bool radial) const;
    // World point -> display pixel coords and planar depth (uses cameraToWorld).
    glm::dvec3 projectWorld(const glm::dvec3& pWorld) const;
};

// OpenEXR's standard worldToCamera maps into a left-handed camera space looking
// down +Z; OpenGL's looks down -Z. These convert a world->camera matrix between them.
// Matrix layout: copy the Imath matrix element-wise, glm[i][j] = imath[i][j]. Imath
// multiplies row vectors (p * M) and glm is column-major, so the copy is already
// the column-vector matrix glm expects (M * p). The conversion flips camera Z and
// is its own inverse.
glm::dmat4 exrWorldToCameraToGL(const glm::dmat4& exrWorldToCamera);
glm::dmat4 glWorldToCameraToExr(const glm::dmat4& glWorldToCamera);

} // namespace obscura
