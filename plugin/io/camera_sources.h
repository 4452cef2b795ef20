// Where the camera comes from: flags, a JSON sidecar, EXR header attributes, or a
// fit to the world-position pass (first match wins; see docs/conventions.md, "Camera sources").
#pragma once
#include "core/camera.h"
#include "core/methods.h"
#include "base/image.h"

#include <OpenEXR/ImfForward.h>

#include <array>
#include <optional>
#include <string>

namespace obscura {

struct CameraRequest {
    std::optional<double> fovDeg, orthoWidth;                 // --fov-deg / --ortho-width
    std::optional<double> focalMm, apertureMm;                // --focal-mm / --aperture-mm (horizontal film back)
    std::optional<std::array<double, 16>> cameraToWorld;     // --camera-to-world, row-major, OpenGL convention
    std::string sidecarPath;                                  // --camera FILE.json (or findSidecar's answer)
};

// "" when the request names at most one lens (--fov-deg, --focal-mm with --aperture-mm, or
// --ortho-width) and the film back's two halves come together; else the one-line refusal in
// the host's spelling. Ranges are the settings schema's (core/settings_schema.h).
std::string lensProblem(const CameraRequest& request, Spelling spelling);

// The lens the flags give (fx = 0 for none): display window `display`, principal point at its centre.
Camera lensFromFlags(const CameraRequest& request, Box2i display, double pixelAspect);

// The JSON sidecar (see tests/data/*.json): "camera_to_world" (4 rows of 4, or 16
// numbers row-major, OpenGL convention), "projection" "persp"|"ortho", and
// "horizontal_fov_rad" or "ortho_width". Throws obscura::Error on any problem.
Camera cameraFromSidecar(const std::string& path, Box2i display, double pixelAspect);

// NAME.json next to NAME.exr (then NAME.exr.json), or "" if there is none; an obscura report
// there (--report NAME.json) is not one.
std::string findSidecar(const std::string& exrPath);

// Camera attributes of an EXR header, if any:
//  - OpenEXR standard worldToCamera (+ worldToNDC, or Arnold's worldToScreen, or
//    3Delight's fieldOfViewHorizontal). Which way the camera looks (+Z as the
//    standard says, or -Z as Houdini and Arnold write it) is read from the projection
//    matrix when there is one; without it the standard is assumed.
//  - V-Ray cameraTransform (camera-to-world, camera looking down -Z) + cameraFov
//    (horizontal degrees) + cameraProjection (0 perspective; panoramic types are refused).
// A camera whose pose is known but not its intrinsics comes back with fx = fy = 0.
std::optional<Camera> cameraFromHeader(const Imf::Header& header, Box2i display);

// First match wins: flags, sidecar (request.sidecarPath), header, fit from the
// position pass. Flags that give only intrinsics (or only a pose) take the missing
// half from the next source that has it; intrinsics without any pose are returned
// with hasPose = false. A header camera that disagrees with the position pass by
// more than 2 px is replaced by the fit. `header` and `worldPosition` may be absent
// (nullptr / invalid view). Throws obscura::Error when nothing gives a camera.
Camera resolveCamera(const CameraRequest& request, const Imf::Header* header, ConstPlane worldPosition,
                     Box2i dataWindow, Box2i display, double pixelAspect);

// Row-major 16 numbers (OpenGL convention) -> matrix; throws if it is not an affine, invertible transform.
glm::dmat4 cameraToWorldFromRows(const std::array<double, 16>& rowMajor, const std::string& what);

} // namespace obscura
