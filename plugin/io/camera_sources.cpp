#include "camera_sources.h"

#include "core/camera_fit.h"
#include "base/error.h"

#include <OpenEXR/ImfDoubleAttribute.h>
#include <OpenEXR/ImfFloatAttribute.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfIntAttribute.h>
#include <OpenEXR/ImfMatrixAttribute.h>
#include <nlohmann/json.hpp>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <vector>

namespace obscura {
namespace {

constexpr double kPi = 3.14159265358979323846;

std::string fmt(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.6g", v);
    return buf;
}

// Element-wise copy: Imath's row-vector matrix becomes glm's column-vector one (see camera.h).
template <class M>
glm::dmat4 fromImath(const M& m) {
    glm::dmat4 g;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) g[i][j] = m[i][j];
    return g;
}

std::optional<glm::dmat4> findMatrix(const Imf::Header& h, const char* name) {
    if (auto* a = h.findTypedAttribute<Imf::M44fAttribute>(name)) return fromImath(a->value());
    if (auto* a = h.findTypedAttribute<Imf::M44dAttribute>(name)) return fromImath(a->value());
    return std::nullopt;
}

std::optional<double> findFloat(const Imf::Header& h, const char* name) {
    if (auto* a = h.findTypedAttribute<Imf::FloatAttribute>(name)) return a->value();
    if (auto* a = h.findTypedAttribute<Imf::DoubleAttribute>(name)) return a->value();
    return std::nullopt;
}

bool finite(const glm::dmat4& m) {
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j)
            if (!std::isfinite(m[i][j])) return false;
    return true;
}

// Intrinsics from a camera -> NDC (or screen) matrix, by projecting probe points.
// `forward` is +1 when the file's camera looks down +Z, -1 for -Z. NDC has y down
// and spans the display window with [0, 1]; a "screen" matrix has y up and spans
// the width with [-1, 1] (Arnold's and RenderMan's screen space; heuristic for
// non-square frames). Returns false if the probes do not make a sane camera.
bool intrinsicsFromProjection(const glm::dmat4& cameraToNdc, double forward, Box2i display, Camera& c) {
    const double W = display.width(), H = display.height();
    bool yDown = true;
    auto ndc = [&](double x, double y, double z) {
        const glm::dvec4 h = cameraToNdc * glm::dvec4(x, y, z * forward, 1.0);
        return glm::dvec2(h.x / h.w, h.y / h.w);
    };
    auto pixel = [&](glm::dvec2 n) {
        return yDown ? glm::dvec2(display.x0 + n.x * W, display.y0 + n.y * H)
                     : glm::dvec2(display.x0 + 0.5 * W * (1 + n.x), display.y0 + 0.5 * H - 0.5 * W * n.y);
    };
    yDown = ndc(0, 1, 1).y < ndc(0, 0, 1).y;
    const glm::dvec2 centre = pixel(ndc(0, 0, 1)), right = pixel(ndc(1, 0, 1)), up = pixel(ndc(0, 1, 1));
    const glm::dvec2 farRight = pixel(ndc(1, 0, 2));
    if (!std::isfinite(centre.x + centre.y + right.x + up.y + farRight.x)) return false;
    c.cx = centre.x;
    c.cy = centre.y;
    c.fx = right.x - centre.x;
    c.fy = centre.y - up.y;
    // Perspective shrinks the far probe towards the centre; orthographic does not.
    c.projection = std::fabs(farRight.x - right.x) < 1e-6 * std::fabs(c.fx) ? Projection::Orthographic
                                                                            : Projection::Perspective;
    return c.fx > 0 && c.fy > 0;
}

std::optional<Camera> fromOpenExrStandard(const Imf::Header& h, Box2i display, const glm::dmat4& fileWorldToCamera) {
    Camera c;
    const char* projectionName = nullptr;
    std::optional<glm::dmat4> worldToNdc = findMatrix(h, "worldToNDC");
    projectionName = "worldToNDC";
    if (!worldToNdc) {
        worldToNdc = findMatrix(h, "worldToScreen");
        projectionName = "worldToScreen";
    }
    double forward = +1;  // the standard: left-handed, looking down +Z
    bool haveIntrinsics = false;
    if (worldToNdc && finite(*worldToNdc)) {
        const glm::dmat4 cameraToNdc = *worldToNdc * glm::inverse(fileWorldToCamera);
        for (double f : {+1.0, -1.0}) {
            Camera probe;
            if (intrinsicsFromProjection(cameraToNdc, f, display, probe)) {
                forward = f;
                c = probe;
                haveIntrinsics = true;
                break;
            }
        }
    }
    if (!haveIntrinsics) {
        if (auto fov = findFloat(h, "fieldOfViewHorizontal"); fov && *fov > 0 && *fov < 180) {
            c = Camera::perspectiveFromFov(*fov * kPi / 180, display.width(), display.height(), h.pixelAspectRatio());
            c.cx += display.x0;
            c.cy += display.y0;
            projectionName = "fieldOfViewHorizontal";
            haveIntrinsics = true;
        }
    }
    const glm::dmat4 glWorldToCamera = forward > 0 ? exrWorldToCameraToGL(fileWorldToCamera) : fileWorldToCamera;
    c.cameraToWorld = glm::inverse(glWorldToCamera);
    c.hasPose = true;
    c.source = std::string("header:worldToCamera") + (forward > 0 ? "" : " (looking down -Z)");
    if (haveIntrinsics) {
        c.source += std::string(" + ") + projectionName;
    } else {
        c.fx = c.fy = 0;  // pose only
    }
    return c;
}

// V-Ray's cameraTransform is camera-to-world with the camera looking down -Z. Files
// seen in the wild keep the translation in the last column (column-vector layout);
// the Imath layout (last row) is accepted too.
std::optional<Camera> fromVRay(const Imf::Header& h, Box2i display, glm::dmat4 m) {
    const glm::dvec3 lastRow(m[3][0], m[3][1], m[3][2]), lastColumn(m[0][3], m[1][3], m[2][3]);
    if (glm::length(lastColumn) > glm::length(lastRow)) m = glm::transpose(m);
    int projection = 0;
    if (auto* a = h.findTypedAttribute<Imf::IntAttribute>("cameraProjection")) projection = a->value();
    Camera c;
    if (projection == 0) {
        auto fov = findFloat(h, "cameraFov");
        if (fov && *fov > 0 && *fov < 180) {
            c = Camera::perspectiveFromFov(*fov * kPi / 180, display.width(), display.height(), h.pixelAspectRatio());
            c.cx += display.x0;
            c.cy += display.y0;
        }
    } else if (projection != 6) {  // 6 is orthographic: pose only, its width is not written
        return std::nullopt;       // spherical, cylindrical, fisheye...: not a pinhole
    }
    c.cameraToWorld = m;
    c.hasPose = true;
    c.source = c.fx > 0 ? "header:cameraTransform + cameraFov (V-Ray)" : "header:cameraTransform (V-Ray)";
    return c;
}

std::string describeFlags(const CameraRequest& r) {
    std::string s;
    if (r.fovDeg) s = "--fov-deg " + fmt(*r.fovDeg);
    if (r.focalMm && r.apertureMm) s = "--focal-mm " + fmt(*r.focalMm) + " --aperture-mm " + fmt(*r.apertureMm);
    if (r.orthoWidth) s = "--ortho-width " + fmt(*r.orthoWidth);
    if (r.cameraToWorld) s += std::string(s.empty() ? "" : " ") + "--camera-to-world";
    return s;
}

const char* kNoCamera =
    "no camera: give --fov-deg, --focal-mm with --aperture-mm, or --ortho-width (and --camera-to-world for world-space normals), "
    "a JSON sidecar with --camera, or include a position pass";

} // namespace

glm::dmat4 cameraToWorldFromRows(const std::array<double, 16>& v, const std::string& what) {
    glm::dmat4 m;
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) m[c][r] = v[r * 4 + c];
    const bool affine = std::fabs(v[12]) < 1e-6 && std::fabs(v[13]) < 1e-6 && std::fabs(v[14]) < 1e-6 &&
                        std::fabs(v[15] - 1) < 1e-6;
    if (!finite(m) || !affine || std::fabs(glm::determinant(glm::dmat3(m))) < 1e-12)
        throw Error(what + ": camera_to_world must be an invertible affine 4x4 (rows, last row 0 0 0 1)");
    return m;
}

// A finite number at j[key], or one line naming the sidecar and the key.
static double sidecarNumber(const nlohmann::json& j, const char* key, const std::string& path,
                            const std::string& where) {
    if (!j.contains(key)) throw FileError(path, where + " has no \"" + key + "\"");
    if (!j[key].is_number() || !std::isfinite(j[key].get<double>()))
        throw FileError(path, where + ": \"" + key + "\" must be a finite number");
    return j[key].get<double>();
}

Camera cameraFromSidecar(const std::string& path, Box2i display, double pixelAspect) {
    const std::string where = "camera sidecar";
    std::ifstream in(path);
    if (!in) throw FileError(path, "cannot open the camera sidecar");
    nlohmann::json j;
    try {
        in >> j;
    } catch (const nlohmann::json::parse_error& e) {
        throw FileError(path, where + " is not valid JSON (at byte " + std::to_string(e.byte) + ")");
    } catch (const std::exception&) {
        throw FileError(path, where + " is not valid JSON");
    }
    if (!j.is_object()) throw FileError(path, where + " is not a JSON object");
    const std::string rowsMessage = where + ": \"camera_to_world\" must be 4 rows of 4 numbers (or 16 numbers)";
    if (!j.contains("camera_to_world") || !j["camera_to_world"].is_array()) throw FileError(path, rowsMessage);
    const auto& m = j["camera_to_world"];
    std::vector<const nlohmann::json*> flat;
    if (m.size() == 4) {
        for (const auto& row : m) {
            if (!row.is_array() || row.size() != 4) throw FileError(path, rowsMessage);
            for (const auto& v : row) flat.push_back(&v);
        }
    } else if (m.size() == 16) {
        for (const auto& v : m) flat.push_back(&v);
    } else {
        throw FileError(path, rowsMessage);
    }
    std::array<double, 16> rows{};
    for (int i = 0; i < 16; ++i) {
        if (!flat[i]->is_number()) throw FileError(path, rowsMessage);
        rows[i] = flat[i]->get<double>();
    }
    // Without "projection", the lens it gives says which: an ortho_width alone is orthographic.
    std::string projection = j.contains("ortho_width") && !j.contains("horizontal_fov_rad") ? "ortho" : "persp";
    if (j.contains("projection")) {
        if (!j["projection"].is_string()) throw FileError(path, where + ": \"projection\" must be \"persp\" or \"ortho\"");
        projection = j["projection"].get<std::string>();
    }
    Camera c;
    if (projection == "persp" || projection == "PERSP" || projection == "perspective") {
        const double fov = sidecarNumber(j, "horizontal_fov_rad", path, where);
        if (!(fov > 0 && fov < kPi)) throw FileError(path, where + ": horizontal_fov_rad must be in (0, pi)");
        c = Camera::perspectiveFromFov(fov, display.width(), display.height(), pixelAspect);
    } else if (projection == "ortho" || projection == "ORTHO" || projection == "orthographic") {
        const double width = sidecarNumber(j, "ortho_width", path, where);
        if (!(width > 0)) throw FileError(path, where + ": ortho_width must be positive");
        c = Camera::orthographic(width, display.width(), display.height(), pixelAspect);
    } else {
        throw FileError(path, where + ": projection is not supported (persp or ortho)");
    }
    if (j.contains("width") && j.contains("height") && j["width"].is_number() && j["height"].is_number()) {
        const double w = j["width"].get<double>(), h = j["height"].get<double>();
        const double displayAspect = double(display.width()) / display.height();
        if (!(w > 0 && h > 0 && std::isfinite(w / h)) || std::fabs((w / h) / displayAspect - 1) > 0.01)
            throw FileError(path, where + " is for a " + fmt(w) + "x" + fmt(h) + " frame, the image is " +
                        std::to_string(display.width()) + "x" + std::to_string(display.height()));
    }
    c.cx += display.x0;
    c.cy += display.y0;
    try {
        c.cameraToWorld = cameraToWorldFromRows(rows, where);
    } catch (const Error& e) {
        throw FileError(path, e.what());
    }
    c.hasPose = true;
    c.source = "sidecar:" + path;
    return c;
}

namespace {
// An obscura report (`--report NAME.json` beside its input): not a camera sidecar, though it sits
// where one would.
bool isObscuraReport(const std::string& path) {
    std::ifstream f(path);
    const nlohmann::json j = nlohmann::json::parse(f, nullptr, false);
    return j.is_object() && j.contains("timings_s") && j.contains("settings") && j.contains("recipe");
}
} // namespace

std::string findSidecar(const std::string& exrPath) {
    namespace fs = std::filesystem;
    std::error_code ec;
    for (const fs::path& candidate : {fs::path(exrPath).replace_extension(".json"), fs::path(exrPath + ".json")})
        if (fs::is_regular_file(candidate, ec) && !isObscuraReport(candidate.string())) return candidate.string();
    return "";
}

std::optional<Camera> cameraFromHeader(const Imf::Header& header, Box2i display) {
    if (auto w2c = findMatrix(header, "worldToCamera"); w2c && finite(*w2c) && glm::determinant(*w2c) != 0)
        return fromOpenExrStandard(header, display, *w2c);
    if (auto m = findMatrix(header, "cameraTransform"); m && finite(*m) && glm::determinant(*m) != 0)
        return fromVRay(header, display, *m);
    return std::nullopt;
}

std::string lensProblem(const CameraRequest& r, Spelling spelling) {
    const bool flag = spelling == Spelling::Flag;
    const char* focal = flag ? "--focal-mm" : "focal_mm";
    const char* aperture = flag ? "--aperture-mm" : "aperture_mm";
    if (r.focalMm.has_value() != r.apertureMm.has_value())
        return std::string(r.focalMm ? focal : aperture) + " needs " + (r.focalMm ? aperture : focal) +
               ": the focal length and the horizontal film back (aperture) go together";
    std::vector<std::string> lenses;
    if (r.fovDeg) lenses.push_back(flag ? "--fov-deg" : "fov_deg");
    if (r.focalMm) lenses.push_back(std::string(focal) + (flag ? "/" : " and ") + aperture);
    if (r.orthoWidth) lenses.push_back(flag ? "--ortho-width" : "ortho_width");
    if (lenses.size() < 2) return "";
    return "give either " + lenses[0] + " or " + lenses[1] + ", not both";
}

Camera lensFromFlags(const CameraRequest& r, Box2i display, double pixelAspect) {
    Camera c;
    const int w = display.width(), h = display.height();
    if (r.fovDeg) c = Camera::perspectiveFromFov(*r.fovDeg * kPi / 180, w, h, pixelAspect);
    if (r.focalMm && r.apertureMm) c = Camera::perspectiveFromFilmBack(*r.focalMm, *r.apertureMm, w, h, pixelAspect);
    if (r.orthoWidth) c = Camera::orthographic(*r.orthoWidth, w, h, pixelAspect);
    // The principal point is the display window's centre, wherever the data window lies in it.
    c.cx += display.x0;
    c.cy += display.y0;
    return c;
}

Camera resolveCamera(const CameraRequest& request, const Imf::Header* header, ConstPlane worldPosition,
                     Box2i dataWindow, Box2i display, double pixelAspect) {
    if (const std::string problem = lensProblem(request, Spelling::Flag); !problem.empty()) throw Error(problem);
    if (request.fovDeg && !(*request.fovDeg > 0 && *request.fovDeg < 180))
        throw Error("--fov-deg must be between 0 and 180, got " + fmt(*request.fovDeg));
    if (request.orthoWidth && !(*request.orthoWidth > 0))
        throw Error("--ortho-width must be positive, got " + fmt(*request.orthoWidth));
    for (const auto& [value, name] : {std::pair{request.focalMm, "--focal-mm"}, {request.apertureMm, "--aperture-mm"}})
        if (value && !(*value > 0 && std::isfinite(*value)))
            throw Error(std::string(name) + " must be positive, got " + fmt(*value));

    // Flags: each half (intrinsics, pose) is optional.
    const bool flagIntrinsics = request.fovDeg || request.focalMm || request.orthoWidth;
    Camera flags = lensFromFlags(request, display, pixelAspect);
    if (request.cameraToWorld) {
        flags.cameraToWorld = cameraToWorldFromRows(*request.cameraToWorld, "--camera-to-world");
        flags.hasPose = true;
    }
    flags.source = "flags (" + describeFlags(request) + ")";
    if (flagIntrinsics && flags.hasPose) return flags;

    // The other sources, in order; each is tried only if the earlier ones gave nothing.
    const bool havePosition = worldPosition.valid() && worldPosition.channels >= 3;
    std::optional<Camera> found;
    std::string note;
    if (!request.sidecarPath.empty()) found = cameraFromSidecar(request.sidecarPath, display, pixelAspect);
    if (!found && header) {
        found = cameraFromHeader(*header, display);
        if (found && found->valid() && havePosition) {
            const double rms = reprojectionRmsPx(*found, worldPosition, dataWindow);
            if (rms > 2.0) {
                note = found->source + " disagrees with the position pass (rms " + fmt(rms) + " px); ";
                try {
                    found = fitCameraFromPosition(worldPosition, dataWindow, display, pixelAspect);
                } catch (const Error&) {
                    note.clear();
                    found->source += " (disagrees with the position pass: rms " + fmt(rms) + " px)";
                }
            }
        }
    }
    // Flags with a lens only need a pose; otherwise the lens is needed.
    const bool enough = found && (flagIntrinsics ? found->hasPose : found->valid());
    if (!enough && havePosition) {
        if (flagIntrinsics) {
            try {
                found = fitCameraFromPosition(worldPosition, dataWindow, display, pixelAspect);
            } catch (const Error& e) {
                flags.source += std::string(", no pose (") + e.what() + ")";
                return flags;
            }
        } else {
            found = fitCameraFromPosition(worldPosition, dataWindow, display, pixelAspect);  // throws with the residual
        }
    }

    if (flagIntrinsics) {  // flags' intrinsics, pose from the source (if any)
        if (found && found->hasPose) {
            flags.cameraToWorld = found->cameraToWorld;
            flags.hasPose = true;
            flags.source += " + pose from " + found->source;
        } else {
            flags.source += ", no pose";
        }
        return flags;
    }
    if (!found || !found->valid()) {
        if (flags.hasPose)
            throw Error("--camera-to-world needs --fov-deg, --focal-mm with --aperture-mm, or --ortho-width (no other "
                        "source gives the lens)");
        throw Error(kNoCamera);
    }
    Camera c = *found;
    if (flags.hasPose) {  // the flag's pose overrides the source's
        c.cameraToWorld = flags.cameraToWorld;
        c.hasPose = true;
        c.source = flags.source + " + lens from " + c.source;
    }
    c.source = note + c.source;
    return c;
}

} // namespace obscura
