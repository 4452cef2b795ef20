// obscura.Camera: core's Camera (core/camera.h) with constructors named like the CLI's camera
// flags, and the sidecar reader of plugin/io.
#include "core/settings_schema.h"
#include "io/camera_sources.h"
#include "python/py_args.h"
#include "python/py_bind.h"

#include <cmath>
#include <sstream>
#include <utility>
#include <string>

namespace obscura::python {

namespace {

const char* kCameraDoc = R"doc(A pinhole or orthographic camera (OpenGL convention: camera looks down -Z, +Y up).

Pixel (x, y) has its centre at (x + 0.5, y + 0.5) in display-window coordinates, y down.
Build one with Camera.perspective, Camera.orthographic or Camera.from_sidecar, or take
read_passes(path)['camera']. camera_to_world is a 4x4 row-major matrix (numpy float64),
or None when only the intrinsics are known.)doc";

const char* kInitDoc = R"doc(Camera from intrinsics: fx, fy focal lengths in pixels (orthographic: pixels per world
unit; fy defaults to fx), principal point (cx, cy) in display pixels.)doc";

const char* kPerspectiveDoc = R"doc(Perspective camera with horizontal field of view fov_deg across a display window of
width x height pixels (the CLI's --fov-deg); optional 4x4 camera_to_world (--camera-to-world).)doc";

const char* kFilmBackDoc = R"doc(Perspective camera from a focal length and the horizontal film back (aperture) spanning a
display window of width x height pixels, both in mm (the CLI's --focal-mm, --aperture-mm), as a
compositing app's camera node gives them; optional 4x4 camera_to_world.)doc";

const char* kOrthographicDoc = R"doc(Orthographic camera width_world world units across a display window of width x height
pixels (the CLI's --ortho-width).)doc";

const char* kFromSidecarDoc = R"doc(Camera from a JSON sidecar (camera_to_world rows, horizontal_fov_rad or ortho_width), as
--camera FILE.json reads it, for a display window of width x height pixels. Raises obscura.Error
when the file is missing or invalid.)doc";

std::string cameraRepr(const Camera& c) {
    std::ostringstream os;
    os.precision(9);
    os << "obscura.Camera(" << (c.projection == Projection::Perspective ? "perspective" : "orthographic")
       << ", fx=" << c.fx << ", fy=" << c.fy << ", cx=" << c.cx << ", cy=" << c.cy
       << (c.hasPose ? ", posed" : ", no pose");
    if (!c.source.empty()) os << ", source='" << c.source << "'";
    os << ")";
    return os.str();
}

Camera withPose(Camera c, const py::object& m) {
    if (!m.is_none()) {
        c.cameraToWorld = cameraToWorldFromRows(matrixRowsArg(m, "camera_to_world"), "camera_to_world");
        c.hasPose = true;
    }
    return c;
}

void checkDisplaySize(int width, int height) {
    if (width < 1 || height < 1)
        valueError("width and height are the display window's size in pixels and must be positive, got " +
                   std::to_string(width) + "x" + std::to_string(height));
}

Camera fromIntrinsics(double fx, py::object fy, py::object cx, py::object cy, py::object c2w, bool ortho) {
    if (!(fx > 0) || !std::isfinite(fx)) valueError("fx must be positive");
    Camera c;
    c.projection = ortho ? Projection::Orthographic : Projection::Perspective;
    c.fx = fx;
    c.fy = fy.is_none() ? fx : floatArg(fy, "fy");
    if (!(c.fy > 0)) valueError("fy must be positive");
    c.cx = floatArg(cx, "cx");
    c.cy = floatArg(cy, "cy");
    c.source = "python";
    return withPose(c, c2w);
}

Camera perspective(double fovDeg, int width, int height, py::object c2w, double pixelAspect) {
    if (!(fovDeg > 0 && fovDeg < 180)) valueError("fov_deg must be between 0 and 180, got " + std::to_string(fovDeg));
    checkDisplaySize(width, height);
    if (!(pixelAspect > 0) || !std::isfinite(pixelAspect)) valueError("pixel_aspect must be positive");
    Camera c = Camera::perspectiveFromFov(fovDeg * M_PI / 180.0, width, height, pixelAspect);
    c.source = "python (perspective)";
    return withPose(c, c2w);
}

Camera filmBack(double focalMm, double apertureMm, int width, int height, py::object c2w, double pixelAspect) {
    for (const auto& [value, key] : {std::pair{focalMm, "focal_mm"}, {apertureMm, "aperture_mm"}}) {
        const std::string problem = numberProblem(numberSetting(key), value, Spelling::Key);
        if (!problem.empty()) valueError(problem);
    }
    checkDisplaySize(width, height);
    if (!(pixelAspect > 0) || !std::isfinite(pixelAspect)) valueError("pixel_aspect must be positive");
    Camera c = Camera::perspectiveFromFilmBack(focalMm, apertureMm, width, height, pixelAspect);
    c.source = "python (film back)";
    return withPose(c, c2w);
}

Camera orthographic(double widthWorld, int width, int height, py::object c2w, double pixelAspect) {
    if (!(widthWorld > 0) || !std::isfinite(widthWorld)) valueError("width_world must be positive");
    checkDisplaySize(width, height);
    if (!(pixelAspect > 0) || !std::isfinite(pixelAspect)) valueError("pixel_aspect must be positive");
    Camera c = Camera::orthographic(widthWorld, width, height, pixelAspect);
    c.source = "python (orthographic)";
    return withPose(c, c2w);
}

Camera fromSidecar(const py::object& path, int width, int height, double pixelAspect) {
    const std::string p = pathArg(path, "path");
    checkDisplaySize(width, height);
    py::gil_scoped_release release;
    return cameraFromSidecar(p, Box2i{0, 0, width, height}, pixelAspect);
}

py::object poseOf(const Camera& c) { return c.hasPose ? py::object(matrixToRows(c.cameraToWorld)) : py::none(); }

void setPose(Camera& c, py::object m) {
    if (m.is_none()) {
        c.cameraToWorld = glm::dmat4(1.0);
        c.hasPose = false;
    } else {
        c = withPose(c, m);
    }
}

// The constructors: Camera(fx, ...) and the static perspective, orthographic, from_sidecar.
void bindConstructors(py::class_<Camera>& cls) {
    cls.def(py::init(&fromIntrinsics), py::arg("fx"), py::kw_only(), py::arg("fy") = py::none(), py::arg("cx"),
            py::arg("cy"), py::arg("camera_to_world") = py::none(), py::arg("orthographic") = false, kInitDoc)
        .def_static("perspective", &perspective, py::arg("fov_deg"), py::arg("width"), py::arg("height"),
                    py::arg("camera_to_world") = py::none(), py::arg("pixel_aspect") = 1.0, kPerspectiveDoc)
        .def_static("film_back", &filmBack, py::arg("focal_mm"), py::arg("aperture_mm"), py::arg("width"),
                    py::arg("height"), py::arg("camera_to_world") = py::none(), py::arg("pixel_aspect") = 1.0,
                    kFilmBackDoc)
        .def_static("orthographic", &orthographic, py::arg("width_world"), py::arg("width"), py::arg("height"),
                    py::arg("camera_to_world") = py::none(), py::arg("pixel_aspect") = 1.0, kOrthographicDoc)
        .def_static("from_sidecar", &fromSidecar, py::arg("path"), py::arg("width"), py::arg("height"),
                    py::arg("pixel_aspect") = 1.0, kFromSidecarDoc);
}

// The properties, horizontal_fov_deg and __repr__.
void bindProperties(py::class_<Camera>& cls) {
    cls.def_property_readonly(
           "projection",
           [](const Camera& c) { return c.projection == Projection::Perspective ? "perspective" : "orthographic"; },
           "'perspective' or 'orthographic'.")
        .def_property_readonly("fx", [](const Camera& c) { return c.fx; }, "Focal length in pixels (orthographic: pixels per unit).")
        .def_property_readonly("fy", [](const Camera& c) { return c.fy; })
        .def_property_readonly("cx", [](const Camera& c) { return c.cx; }, "Principal point, display pixels.")
        .def_property_readonly("cy", [](const Camera& c) { return c.cy; })
        .def_property("camera_to_world", &poseOf, &setPose,
                      "4x4 row-major camera-to-world matrix (OpenGL convention), or None if the pose is unknown.")
        .def_property_readonly("has_pose", [](const Camera& c) { return c.hasPose; })
        .def_property_readonly("source", [](const Camera& c) { return c.source; },
                               "Where the camera came from (flags, sidecar, header, fit, python).")
        .def_property_readonly(
            "fit_residual_px",
            [](const Camera& c) -> py::object { return c.fitResidualPx >= 0 ? py::cast(c.fitResidualPx) : py::none(); },
            "RMS reprojection error of a fit to the position pass, None if not fitted.")
        .def(
            "horizontal_fov_deg", [](const Camera& c, int width) { return c.horizontalFovRad(width) * 180.0 / M_PI; },
            py::arg("width"), "Horizontal FOV across a display `width` pixels wide (0 for orthographic).")
        .def("__repr__", &cameraRepr);
}

} // namespace

void bindCamera(py::module_& m) {
    py::class_<Camera> cls(m, "Camera", kCameraDoc);
    bindConstructors(cls);
    bindProperties(cls);
}

} // namespace obscura::python
