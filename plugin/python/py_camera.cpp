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
unit; fy defaults to fx), principal point (cx, cy) in display pixels; camera_to_world an optional
4x4 row-major pose (OpenGL convention); orthographic=True for a parallel projection.)doc";

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
    os << "<obscura.Camera " << (c.projection == Projection::Perspective ? "perspective" : "orthographic")
       << " fx=" << c.fx << " fy=" << c.fy << " cx=" << c.cx << " cy=" << c.cy;
    if (c.displayWidth > 0) os << " display=" << c.displayWidth << "x" << c.displayHeight;
    if (c.hasPose) {
        os << " camera_to_world=[";
        for (int row = 0; row < 4; ++row)
            for (int col = 0; col < 4; ++col) os << (row || col ? ", " : "") << c.cameraToWorld[col][row];
        os << "]";
    } else {
        os << " no pose";
    }
    if (!c.source.empty()) os << " source='" << c.source << "'";
    os << ">";
    return os.str();
}

// Equal: the same projection of the same frame (provenance, source and fit residual, aside).
bool sameCamera(const Camera& a, const Camera& b) {
    return a.projection == b.projection && a.fx == b.fx && a.fy == b.fy && a.cx == b.cx && a.cy == b.cy &&
           a.hasPose == b.hasPose && (!a.hasPose || a.cameraToWorld == b.cameraToWorld) &&
           a.displayWidth == b.displayWidth && a.displayHeight == b.displayHeight;
}

// Every field, for pickle (Dask and multiprocessing send read_passes() dicts) and copy.
py::tuple cameraState(const Camera& c) {
    py::list pose;
    for (int col = 0; col < 4; ++col)
        for (int row = 0; row < 4; ++row) pose.append(c.cameraToWorld[col][row]);
    return py::make_tuple(1, c.projection == Projection::Perspective ? "perspective" : "orthographic", c.fx, c.fy,
                          c.cx, c.cy, pose, c.hasPose, c.source, c.fitResidualPx, c.displayWidth, c.displayHeight);
}

Camera cameraFromState(const py::tuple& t) {
    if (t.size() != 12 || t[0].cast<int>() != 1) valueError("not a pickled obscura.Camera of this version");
    Camera c;
    c.projection = t[1].cast<std::string>() == "perspective" ? Projection::Perspective : Projection::Orthographic;
    c.fx = t[2].cast<double>();
    c.fy = t[3].cast<double>();
    c.cx = t[4].cast<double>();
    c.cy = t[5].cast<double>();
    const py::list pose = t[6].cast<py::list>();
    for (int i = 0; i < 16; ++i) c.cameraToWorld[i / 4][i % 4] = pose[i].cast<double>();
    c.hasPose = t[7].cast<bool>();
    c.source = t[8].cast<std::string>();
    c.fitResidualPx = t[9].cast<double>();
    c.displayWidth = t[10].cast<int>();
    c.displayHeight = t[11].cast<int>();
    return c;
}

Camera withPose(Camera c, const py::object& m) {
    if (!m.is_none()) {
        c.cameraToWorld = cameraToWorldFromRows(matrixRowsArg(m, "camera_to_world"), "camera_to_world");
        c.hasPose = true;
    }
    return c;
}

Camera fromIntrinsics(const py::object& fxObj, py::object fy, py::object cx, py::object cy, py::object c2w,
                      const py::object& orthoObj) {
    const double fx = floatArg(fxObj, "fx");
    const bool ortho = boolArg(orthoObj, "orthographic");
    if (!(fx > 0)) valueError("fx must be positive");
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

// The display size and pixel aspect every constructor takes, each checked in one line naming it.
struct Frame {
    int width, height;
    double pixelAspect;
};

Frame frameArgs(const py::object& width, const py::object& height, const py::object& pixelAspect) {
    const long long lim = 1 << 30;
    Frame f{intInRange(width, "width", 1, lim), intInRange(height, "height", 1, lim), floatArg(pixelAspect, "pixel_aspect")};
    if (!(f.pixelAspect > 0)) valueError("pixel_aspect must be positive");
    return f;
}

Camera perspective(const py::object& fovDegObj, const py::object& width, const py::object& height, py::object c2w,
                   const py::object& pixelAspect) {
    const double fovDeg = floatArg(fovDegObj, "fov_deg");
    if (!(fovDeg > 0 && fovDeg < 180)) valueError("fov_deg must be between 0 and 180, got " + std::to_string(fovDeg));
    const Frame f = frameArgs(width, height, pixelAspect);
    Camera c = Camera::perspectiveFromFov(fovDeg * M_PI / 180.0, f.width, f.height, f.pixelAspect);
    c.source = "python (perspective)";
    return withPose(c, c2w);
}

Camera filmBack(const py::object& focalObj, const py::object& apertureObj, const py::object& width,
                const py::object& height, py::object c2w, const py::object& pixelAspect) {
    const double focalMm = floatArg(focalObj, "focal_mm"), apertureMm = floatArg(apertureObj, "aperture_mm");
    for (const auto& [value, key] : {std::pair{focalMm, "focal_mm"}, {apertureMm, "aperture_mm"}}) {
        const std::string problem = numberProblem(numberSetting(key), value, Spelling::Key);
        if (!problem.empty()) valueError(problem);
    }
    const Frame f = frameArgs(width, height, pixelAspect);
    Camera c = Camera::perspectiveFromFilmBack(focalMm, apertureMm, f.width, f.height, f.pixelAspect);
    c.source = "python (film back)";
    return withPose(c, c2w);
}

Camera orthographic(const py::object& widthWorldObj, const py::object& width, const py::object& height, py::object c2w,
                    const py::object& pixelAspect) {
    const double widthWorld = floatArg(widthWorldObj, "width_world");
    if (!(widthWorld > 0)) valueError("width_world must be positive");
    const Frame f = frameArgs(width, height, pixelAspect);
    Camera c = Camera::orthographic(widthWorld, f.width, f.height, f.pixelAspect);
    c.source = "python (orthographic)";
    return withPose(c, c2w);
}

Camera fromSidecar(const py::object& path, const py::object& width, const py::object& height,
                   const py::object& pixelAspect) {
    const std::string p = pathArg(path, "path");
    const Frame f = frameArgs(width, height, pixelAspect);
    py::gil_scoped_release release;
    return cameraFromSidecar(p, Box2i{0, 0, f.width, f.height}, f.pixelAspect);
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
        .def_property_readonly("fy", [](const Camera& c) { return c.fy; }, "Vertical focal length in pixels (fx times the pixel aspect).")
        .def_property_readonly("cx", [](const Camera& c) { return c.cx; }, "Principal point's column, display pixels.")
        .def_property_readonly("cy", [](const Camera& c) { return c.cy; }, "Principal point's row, display pixels (y down).")
        .def_property("camera_to_world", &poseOf, &setPose,
                      "4x4 row-major camera-to-world matrix (OpenGL convention), or None if the pose is unknown.")
        .def_property_readonly("has_pose", [](const Camera& c) { return c.hasPose; }, "Whether camera_to_world is known.")
        .def_property_readonly("source", [](const Camera& c) { return c.source; },
                               "Where the camera came from (flags, sidecar, header, fit, python).")
        .def_property_readonly(
            "fit_residual_px",
            [](const Camera& c) -> py::object { return c.fitResidualPx >= 0 ? py::cast(c.fitResidualPx) : py::none(); },
            "RMS reprojection error of a fit to the position pass, None if not fitted.")
        .def(
            "horizontal_fov_deg",
            [](const Camera& c, const py::object& width) {
                return c.horizontalFovRad(intInRange(width, "width", 1, 1 << 30)) * 180.0 / M_PI;
            },
            py::arg("width"), "Horizontal FOV across a display `width` pixels wide (0 for orthographic).")
        .def_property_readonly(
            "display_size",
            [](const Camera& c) -> py::object {
                return c.displayWidth > 0 ? py::object(py::make_tuple(c.displayWidth, c.displayHeight)) : py::none();
            },
            "(width, height) of the display window the camera was made for, or None (intrinsics given as they are).")
        .def("__repr__", &cameraRepr)
        .def("__eq__", [](const Camera& a, const py::object& b) -> py::object {
            if (!py::isinstance<Camera>(b)) return py::reinterpret_borrow<py::object>(Py_NotImplemented);
            return py::bool_(sameCamera(a, b.cast<Camera>()));
        })
        .def(py::pickle(&cameraState, &cameraFromState));
}

} // namespace

void bindCamera(py::module_& m) {
    py::class_<Camera> cls(m, "Camera", kCameraDoc);
    bindConstructors(cls);
    bindProperties(cls);
}

} // namespace obscura::python
