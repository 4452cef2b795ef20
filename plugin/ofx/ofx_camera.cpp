// The camera from the node's parameters (ofx_camera.h).
#include "ofx_camera.h"

#include "base/error.h"

#include <cmath>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

namespace obscura::ofx {

namespace {

// 16 numbers, row-major, OpenGL convention: the same as the CLI's --camera-to-world.
glm::dmat4 parseCameraToWorld(const std::string& text) {
    std::vector<double> v;
    std::string item;
    std::stringstream ss(text);
    while (std::getline(ss, item, ',')) {
        const size_t a = item.find_first_not_of(" \t\r\n"), b = item.find_last_not_of(" \t\r\n");
        if (a == std::string::npos) throw Error("camera-to-world: empty number in '" + text + "'");
        item = item.substr(a, b - a + 1);
        char* end = nullptr;
        const double x = std::strtod(item.c_str(), &end);
        if (end == item.c_str() || *end != '\0' || !std::isfinite(x))
            throw Error("camera-to-world: '" + item + "' is not a number");
        v.push_back(x);
    }
    if (v.size() != 16) throw Error("camera-to-world expects 16 comma-separated numbers, got " + std::to_string(v.size()));
    glm::dmat4 m;
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) m[c][r] = v[r * 4 + c];
    if (std::fabs(v[12]) > 1e-6 || std::fabs(v[13]) > 1e-6 || std::fabs(v[14]) > 1e-6 || std::fabs(v[15] - 1) > 1e-6 ||
        std::fabs(glm::determinant(glm::dmat3(m))) < 1e-12)
        throw Error("camera-to-world must be an invertible affine 4x4 (rows, last row 0 0 0 1)");
    return m;
}

} // namespace

Camera makeCamera(const Params& p, const FrameMap& f) {
    Camera cam;
    if (p.filmBack) {
        if (!(p.focalMm > 0 && p.apertureMm > 0)) throw Error("the focal length and the aperture must be positive");
        cam = Camera::perspectiveFromFilmBack(p.focalMm, p.apertureMm, f.displayW, f.displayH, f.pixelAspect());
    } else if (p.projection == Projection::Perspective) {
        if (!(p.fovDeg > 0 && p.fovDeg < 180)) throw Error("the field of view must be between 0 and 180 degrees");
        cam = Camera::perspectiveFromFov(p.fovDeg * 3.14159265358979323846 / 180, f.displayW, f.displayH,
                                         f.pixelAspect());
    } else {
        if (!(p.orthoWidth > 0)) throw Error("the orthographic width must be positive");
        cam = Camera::orthographic(p.orthoWidth, f.displayW, f.displayH, f.pixelAspect());
    }
    const bool hasText = p.cameraToWorld.find_first_not_of(" \t\r\n") != std::string::npos;
    if (hasText) {
        cam.cameraToWorld = parseCameraToWorld(p.cameraToWorld);
        cam.hasPose = true;
    }
    cam.source = "OFX parameters";
    return cam;
}

} // namespace obscura::ofx
