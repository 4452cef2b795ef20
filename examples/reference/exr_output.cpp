#include "exr_output.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStandardAttributes.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>

namespace fs = std::filesystem;

namespace reference {
namespace {

Imath::M44f toImath(const glm::dmat4& m) {  // element-wise: see plugin/core/camera.h
    Imath::M44f r;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) r[i][j] = float(m[i][j]);
    return r;
}

std::string number(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.6g", v);
    return buf;
}

std::string stdErrSummary(const Convergence& c) {
    std::string s;
    for (int l = 0; l < kAoLayers; ++l)
        s += std::string(kAoLayerNames[l]) + " mean " + number(c.aoStdErrMean[l]) + " max " + number(c.aoStdErrMax[l]) + "; ";
    return s + "DiffInd luminance mean " + number(c.indirectStdErrMean) + " max " + number(c.indirectStdErrMax) +
           " (per-pixel standard error of the mean, iid estimate; scrambled Sobol sampling usually does better)";
}

struct Plane {
    std::string name;
    std::vector<float> data;
};

std::vector<Plane> makePlanes(const Frame& f, bool directionalOcclusion, bool bounce) {
    const size_t n = f.pixels.size();
    std::vector<Plane> planes;
    auto add = [&](const std::string& name, const std::function<float(const PixelResult&)>& get) {
        Plane p{name, std::vector<float>(n)};
        for (size_t i = 0; i < n; ++i) p.data[i] = get(f.pixels[i]);
        planes.push_back(std::move(p));
    };
    const char* rgb[] = {"R", "G", "B"};
    const char* xyz[] = {"X", "Y", "Z"};
    for (int c = 0; c < 3; ++c) {
        add(std::string("ViewLayer.Combined.") + rgb[c], [c](const PixelResult& p) { return p.beauty[c]; });
        add(std::string("ViewLayer.Normal.") + xyz[c], [c](const PixelResult& p) { return float(p.normal[c]); });
        add(std::string("ViewLayer.Position.") + xyz[c], [c](const PixelResult& p) { return float(p.position[c]); });
        add(std::string("ViewLayer.DiffCol.") + rgb[c], [c](const PixelResult& p) { return p.albedo[c]; });
        add(std::string("ViewLayer.DiffDir.") + rgb[c], [c](const PixelResult& p) { return p.direct[c]; });
        add(std::string("ViewLayer.DiffInd.") + rgb[c], [c](const PixelResult& p) { return p.indirect[c]; });
    }
    add("ViewLayer.Combined.A", [](const PixelResult&) { return 1.0f; });  // opaque film, as Blender's default
    add("ViewLayer.Depth.Z", [](const PixelResult& p) { return float(p.depth); });
    for (int l = 0; l < kAoLayers; ++l)
        add(std::string("Reference.") + kAoLayerNames[l] + ".Y", [l](const PixelResult& p) { return float(p.ao[l]); });
    if (directionalOcclusion)
        for (int c = 0; c < 3; ++c)
            add(std::string("Reference.DO.") + rgb[c], [c](const PixelResult& p) { return p.directionalOcclusion[c]; });
    if (bounce)
        for (int c = 0; c < 3; ++c) {
            add(std::string("Reference.GI.") + rgb[c], [c](const PixelResult& p) { return p.giNear[c]; });
            add(std::string("Reference.GI_unlimited.") + rgb[c], [c](const PixelResult& p) { return p.giFull[c]; });
        }
    return planes;
}

void writeExr(const std::string& path, const Frame& f, const PinholeCamera& camera, const OutputInfo& info) {
    std::vector<Plane> planes = makePlanes(f, info.settings.environment != nullptr, info.settings.giRays > 0);
    // The camera and the display window are the width x height frame; overscan widens the data window.
    const Imath::Box2i display(Imath::V2i(0, 0), Imath::V2i(camera.width - 1, camera.height - 1));
    const Imath::Box2i data(Imath::V2i(f.originX, f.originY),
                            Imath::V2i(f.originX + f.width - 1, f.originY + f.height - 1));
    Imf::Header header(display, data);
    header.compression() = Imf::ZIP_COMPRESSION;
    header.insert("Software", Imf::StringAttribute("obscura reference_render"));
    Imf::addWorldToCamera(header, toImath(exrWorldToCamera(camera)));
    Imf::addWorldToNDC(header, toImath(exrWorldToNdc(camera)));
    const RenderSettings& s = info.settings;
    auto text = [&](const char* name, const std::string& value) { header.insert(name, Imf::StringAttribute(value)); };
    text("reference/scene", info.sceneName);
    text("reference/radius", number(s.radius));
    text("reference/aoRaysPerPixel", std::to_string(s.aoRays) + " per weighting (uniform, cosine); falloffs share hits");
    text("reference/giRaysPerPixel", std::to_string(s.giRays));
    text("reference/seed", std::to_string(s.seed));
    if (s.overscan > 0) text("reference/overscan", std::to_string(s.overscan) + " pixels past each edge of the display window");
    text("reference/stdErr", stdErrSummary(info.convergence));
    text("reference/definition",
         "AO = 1 - E[W(t)] over the hemisphere of the shading normal; t = first hit distance; W = 1 - t/R (linear) "
         "or 1 (none) for t <= R, else 0; uniform = solid angle, cosine = projected solid angle; sky AO = 1; "
         "Owen-scrambled Sobol samples per pixel");
    if (s.environment) {
        text("reference/environmentRotationDeg", number(s.environment->rotationDeg));
        text("reference/doDefinition",
             "DO = integral over the hemisphere of L_env(w) (1 - W(t(w))) cos(theta) dw, W linear as AO_cosine_linear, "
             "from the same cosine-weighted rays; L_env = bilinear lookup of the level-0 lat-long map, world z up "
             "-> env (x, z, -y), then rotated about up as obscura --up z --env-rotate; sky DO = 0" +
                 std::string(s.sunInDo ? "; plus the sun as obscura --light: pi x sunColour x cos unless hit within R" : ""));
    }
    if (s.giRays > 0)
        text("reference/giDefinition",
             "GI = irradiance (not / pi) of one diffuse bounce: pi x mean over cosine-weighted rays of the radiance of "
             "the first surface hit, albedo x (sun + point lights + one sky sample, DiffDir units); Reference.GI counts "
             "hits within R (obscura's SSDO GI), Reference.GI_unlimited every hit (= pi x DiffInd)");
    Imf::FrameBuffer fb;
    for (Plane& p : planes) {
        header.channels().insert(p.name, Imf::Channel(Imf::FLOAT));
        // The slice's base is where pixel (0, 0) of the display would be.
        char* origin = reinterpret_cast<char*>(p.data.data()) -
                       (ptrdiff_t(f.originY) * f.width + f.originX) * ptrdiff_t(sizeof(float));
        fb.insert(p.name, Imf::Slice(Imf::FLOAT, origin, sizeof(float), sizeof(float) * f.width));
    }
    Imf::OutputFile file(path.c_str(), header);
    file.setFrameBuffer(fb);
    file.writePixels(f.height);  // from data.min.y
}

void writeSidecar(const std::string& path, const PinholeCamera& camera, const OutputInfo& info) {
    const glm::dmat4 m = camera.cameraToWorld();
    nlohmann::json rows = nlohmann::json::array();
    for (int r = 0; r < 4; ++r) rows.push_back({m[0][r], m[1][r], m[2][r], m[3][r]});
    nlohmann::json j;
    j["scene"] = info.sceneName;
    j["width"] = camera.width;
    j["height"] = camera.height;
    j["ao_distance"] = info.settings.radius;
    j["samples"] = info.settings.aoRays;
    j["gi_samples"] = info.settings.giRays;
    j["seed"] = info.settings.seed;
    j["projection"] = "persp";
    j["sensor_width_mm"] = 36.0;
    j["sensor_fit"] = "HORIZONTAL";
    j["focal_length_mm"] = 18.0 / std::tan(0.5 * camera.horizontalFovRad);
    j["horizontal_fov_rad"] = camera.horizontalFovRad;
    j["ortho_width"] = nullptr;
    j["camera_to_world"] = rows;
    j["conventions"] = "depth planar along -Z of camera, sky 1e10, normals and position world-space";
    std::ofstream out(path);
    out << j.dump(1) << "\n";
    if (!out) throw std::runtime_error("cannot write " + path);
}

} // namespace

glm::dmat4 exrWorldToCamera(const PinholeCamera& camera) {
    glm::dmat4 m = glm::inverse(camera.cameraToWorld());  // OpenGL: looks down -Z
    for (int col = 0; col < 4; ++col) m[col][2] = -m[col][2];  // OpenEXR: looks down +Z
    return m;
}

glm::dmat4 exrWorldToNdc(const PinholeCamera& camera) {
    const double near = 1e-4, far = 1e6;
    glm::dmat4 p(0.0);  // glm: p[column][row]; acts on camera points with z forward
    p[0][0] = camera.focalPx / camera.width;    // x_ndc = 0.5 + f x / (W z)
    p[1][1] = -camera.focalPx / camera.height;  // y_ndc = 0.5 - f y / (H z): y down
    p[2][0] = 0.5;
    p[2][1] = 0.5;
    p[2][2] = far / (far - near);  // z_ndc in [0, 1] between near and far
    p[3][2] = -far * near / (far - near);
    p[2][3] = 1.0;                 // w = z
    return p * exrWorldToCamera(camera);
}

void writeReference(const std::string& path, const Frame& frame, const PinholeCamera& camera, const OutputInfo& info) {
    const fs::path out(path);
    const fs::path sidecar = out.parent_path() / (out.stem().string() + ".json");
    if (!out.parent_path().empty()) fs::create_directories(out.parent_path());
    const std::string tmpExr = path + ".tmp", tmpJson = sidecar.string() + ".tmp";
    try {
        writeExr(tmpExr, frame, camera, info);
        writeSidecar(tmpJson, camera, info);
        fs::rename(tmpExr, out);
        fs::rename(tmpJson, sidecar);
    } catch (...) {
        std::error_code ec;
        fs::remove(tmpExr, ec);
        fs::remove(tmpJson, ec);
        throw;
    }
}

} // namespace reference
