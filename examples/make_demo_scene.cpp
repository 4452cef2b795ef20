// make_demo_scene: writes obscura's built-in demo scene, with no external data.
//
// An analytic ray caster (one ray per pixel, through the pixel centre) renders a
// ground plane, a 90-degree wall corner, a few boxes and spheres and some sky,
// and writes a single-part multilayer EXR named the way Blender Cycles names its
// passes, plus a camera sidecar `<stem>.json` like the ones in shared/samples.
//
// World space is Blender's: +Z up. The camera uses the OpenGL convention
// (looks down its -Z, +Y up).
//
// Usage: make_demo_scene OUTPUT.exr [--width W] [--height H]

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStandardAttributes.h>
#include <OpenEXR/ImfStringAttribute.h>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using glm::dvec3;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kInf = 1e30;
constexpr float kSkyDepth = 1e10f;  // Blender's depth for the background

// ---- Scene ---------------------------------------------------------------

struct Sphere { dvec3 centre; double radius; dvec3 albedo; };
// A box standing on its own centre, rotated by `yaw` radians about world +Z.
struct Box { dvec3 centre, half; double yaw; dvec3 albedo; };

struct Hit { double t = kInf; dvec3 normal{0.0}; dvec3 albedo{0.0}; };

const dvec3 kGroundAlbedo{0.60, 0.60, 0.58};
const dvec3 kWallAlbedo{0.75, 0.72, 0.68};

const std::vector<Box> kBoxes = {
    {{-1.35, 4.15, 1.5}, {2.85, 0.15, 1.5}, 0.0, kWallAlbedo},   // back wall  (y = 4)
    {{-4.15, 1.00, 1.5}, {0.15, 3.30, 1.5}, 0.0, kWallAlbedo},   // left wall  (x = -4)
    {{-3.30, 3.30, 0.55}, {0.55, 0.55, 0.55}, 0.0, {0.70, 0.25, 0.20}},  // in the corner
    {{0.60, 2.00, 0.40}, {0.80, 0.50, 0.40}, 0.50, {0.25, 0.45, 0.70}},  // low, turned
    {{-2.90, -0.30, 1.00}, {0.40, 0.40, 1.00}, 0.30, {0.80, 0.75, 0.35}}, // tall pillar
};
const std::vector<Sphere> kSpheres = {
    {{-0.60, -0.40, 0.70}, 0.70, {0.85, 0.85, 0.85}},
    {{1.90, 0.20, 0.45}, 0.45, {0.30, 0.65, 0.30}},
    {{0.60, 2.00, 1.15}, 0.35, {0.90, 0.55, 0.20}},  // resting on the low box
};

void intersectGround(const dvec3& o, const dvec3& d, Hit& h) {
    if (std::abs(d.z) < 1e-12) return;
    double t = -o.z / d.z;
    if (t > 1e-9 && t < h.t) h = {t, {0, 0, 1}, kGroundAlbedo};
}

void intersectSphere(const Sphere& s, const dvec3& o, const dvec3& d, Hit& h) {
    dvec3 oc = o - s.centre;
    double b = glm::dot(oc, d), c = glm::dot(oc, oc) - s.radius * s.radius;
    double disc = b * b - c;  // d is unit length
    if (disc < 0) return;
    double sq = std::sqrt(disc);
    double t = -b - sq;
    if (t <= 1e-9) t = -b + sq;
    if (t > 1e-9 && t < h.t) h = {t, glm::normalize(o + t * d - s.centre), s.albedo};
}

dvec3 rotateZ(const dvec3& v, double a) {
    double c = std::cos(a), s = std::sin(a);
    return {c * v.x - s * v.y, s * v.x + c * v.y, v.z};
}

// Slab test in the box's own frame.
void intersectBox(const Box& b, const dvec3& o, const dvec3& d, Hit& h) {
    dvec3 lo = rotateZ(o - b.centre, -b.yaw), ld = rotateZ(d, -b.yaw);
    double tNear = -kInf, tFar = kInf;
    int axisNear = 0, axisFar = 0;
    for (int i = 0; i < 3; ++i) {
        if (std::abs(ld[i]) < 1e-12) {
            if (std::abs(lo[i]) > b.half[i]) return;
            continue;
        }
        double t0 = (-b.half[i] - lo[i]) / ld[i], t1 = (b.half[i] - lo[i]) / ld[i];
        if (t0 > t1) std::swap(t0, t1);
        if (t0 > tNear) { tNear = t0; axisNear = i; }
        if (t1 < tFar) { tFar = t1; axisFar = i; }
        if (tNear > tFar) return;
    }
    double t = tNear;
    int axis = axisNear;
    if (t <= 1e-9) { t = tFar; axis = axisFar; }
    if (t <= 1e-9 || t >= h.t) return;
    dvec3 n(0.0);
    n[axis] = (lo[axis] + t * ld[axis]) > 0 ? 1.0 : -1.0;
    h = {t, rotateZ(n, b.yaw), b.albedo};
}

Hit trace(const dvec3& o, const dvec3& d) {
    Hit h;
    intersectGround(o, d, h);
    for (const Box& b : kBoxes) intersectBox(b, o, d, h);
    for (const Sphere& s : kSpheres) intersectSphere(s, o, d, h);
    return h;
}

// ---- Lighting: a sun with hard shadows plus an unoccluded sky dome --------

const dvec3 kSunDir = glm::normalize(dvec3(0.45, -0.55, 0.70));  // towards the sun
const dvec3 kSunRadiance{1.45, 1.38, 1.25};
const dvec3 kSkyZenith{0.30, 0.50, 0.95}, kSkyHorizon{0.75, 0.85, 1.00};

dvec3 skyColour(const dvec3& d) {
    double k = std::clamp(d.z, 0.0, 1.0);
    return glm::mix(kSkyHorizon, kSkyZenith, std::sqrt(k));
}

// Direct diffuse irradiance / pi (what Blender's DiffDir holds, before albedo).
dvec3 directDiffuse(const dvec3& p, const dvec3& n) {
    dvec3 light = 0.30 * glm::mix(kSkyHorizon, kSkyZenith, 0.5) * (0.5 + 0.5 * n.z);
    double cosSun = glm::dot(n, kSunDir);
    if (cosSun > 0 && trace(p + 1e-6 * n, kSunDir).t >= kInf) light += kSunRadiance * cosSun;
    return light;
}

// ---- Camera --------------------------------------------------------------

struct Camera {
    dvec3 eye, right, up, back;  // columns of camera_to_world
    double hfov;
};

Camera lookAt(const dvec3& eye, const dvec3& target, double hfovRad) {
    dvec3 fwd = glm::normalize(target - eye);
    dvec3 right = glm::normalize(glm::cross(fwd, dvec3(0, 0, 1)));
    dvec3 up = glm::cross(right, fwd);
    return {eye, right, up, -fwd, hfovRad};
}

// ---- Output --------------------------------------------------------------

void writeExr(const std::string& path, int W, int H, std::vector<std::pair<std::string, std::vector<float>>>& planes) {
    Imf::Header header(W, H);
    header.compression() = Imf::ZIP_COMPRESSION;
    header.insert("Software", Imf::StringAttribute("obscura make_demo_scene"));
    Imf::FrameBuffer fb;
    for (auto& [name, data] : planes) {
        header.channels().insert(name, Imf::Channel(Imf::FLOAT));
        fb.insert(name, Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(data.data()), sizeof(float),
                                   sizeof(float) * W));
    }
    Imf::OutputFile file(path.c_str(), header);
    file.setFrameBuffer(fb);
    file.writePixels(H);
}

void writeSidecar(const std::string& path, const Camera& cam, int W, int H) {
    auto row = [](double a, double b, double c, double d) { return nlohmann::json::array({a, b, c, d}); };
    nlohmann::json j;
    j["scene"] = "demo";
    j["width"] = W;
    j["height"] = H;
    j["projection"] = "persp";
    j["horizontal_fov_rad"] = cam.hfov;
    j["ortho_width"] = nullptr;
    j["camera_to_world"] = nlohmann::json::array({
        row(cam.right.x, cam.up.x, cam.back.x, cam.eye.x),
        row(cam.right.y, cam.up.y, cam.back.y, cam.eye.y),
        row(cam.right.z, cam.up.z, cam.back.z, cam.eye.z),
        row(0, 0, 0, 1)});
    j["conventions"] = "depth planar along -Z of camera, sky 1e10, normals and position world-space";
    std::ofstream out(path);
    out << j.dump(1) << "\n";
    if (!out) throw std::runtime_error("cannot write " + path);
}

int usage(const char* argv0) {
    std::fprintf(stderr,
                 "usage: %s OUTPUT.exr [--width W] [--height H]\n"
                 "Writes the built-in demo scene as a Blender-style multilayer EXR (default 640x360)\n"
                 "and its camera as OUTPUT's stem + .json in the same directory.\n",
                 argv0);
    return 2;
}

bool parseSize(const char* s, int& out) {
    char* end = nullptr;
    long v = std::strtol(s, &end, 10);
    if (end == s || *end != '\0' || v < 1 || v > 16384) return false;
    out = static_cast<int>(v);
    return true;
}

}  // namespace

int main(int argc, char** argv) {
    std::string outPath;
    int W = 640, H = 360;
    for (int i = 1; i < argc; ++i) {
        std::string a = argv[i];
        if (a == "-h" || a == "--help") { usage(argv[0]); return 0; }
        if (a == "--width" || a == "--height") {
            if (i + 1 >= argc || !parseSize(argv[i + 1], a == "--width" ? W : H)) {
                std::fprintf(stderr, "make_demo_scene: %s needs an integer in [1, 16384]\n", a.c_str());
                return usage(argv[0]);
            }
            ++i;
        } else if (!a.empty() && a[0] == '-') {
            std::fprintf(stderr, "make_demo_scene: unknown option %s\n", a.c_str());
            return usage(argv[0]);
        } else if (outPath.empty()) {
            outPath = a;
        } else {
            std::fprintf(stderr, "make_demo_scene: more than one output path given\n");
            return usage(argv[0]);
        }
    }
    if (outPath.empty()) return usage(argv[0]);

    const Camera cam = lookAt({5.0, -6.5, 2.6}, {-1.0, 1.5, 1.0}, 60.0 * kPi / 180.0);
    const double f = (W / 2.0) / std::tan(cam.hfov / 2.0);  // focal length in pixels
    const dvec3 fwd = -cam.back;

    std::vector<std::pair<std::string, std::vector<float>>> planes;
    auto plane = [&](const std::string& name) -> std::vector<float>& {
        planes.emplace_back(name, std::vector<float>(static_cast<size_t>(W) * H, 0.0f));
        return planes.back().second;
    };
    plane("ViewLayer.Combined.R"), plane("ViewLayer.Combined.G"), plane("ViewLayer.Combined.B");
    plane("ViewLayer.Combined.A"), plane("ViewLayer.Depth.Z");
    plane("ViewLayer.Normal.X"), plane("ViewLayer.Normal.Y"), plane("ViewLayer.Normal.Z");
    plane("ViewLayer.Position.X"), plane("ViewLayer.Position.Y"), plane("ViewLayer.Position.Z");
    plane("ViewLayer.DiffCol.R"), plane("ViewLayer.DiffCol.G"), plane("ViewLayer.DiffCol.B");
    plane("ViewLayer.DiffDir.R"), plane("ViewLayer.DiffDir.G"), plane("ViewLayer.DiffDir.B");
    // Same order as above: combined(4) depth(1) normal(3) position(3) diffcol(3) diffdir(3).
    auto set = [&](size_t first, size_t pix, const dvec3& v) {
        for (int c = 0; c < 3; ++c) planes[first + c].second[pix] = static_cast<float>(v[c]);
    };

    for (int y = 0; y < H; ++y) {
        for (int x = 0; x < W; ++x) {
            const size_t pix = static_cast<size_t>(y) * W + x;
            const dvec3 dirCam((x + 0.5 - W / 2.0) / f, -(y + 0.5 - H / 2.0) / f, -1.0);
            const dvec3 dir = glm::normalize(dirCam.x * cam.right + dirCam.y * cam.up + dirCam.z * cam.back);
            const Hit h = trace(cam.eye, dir);
            planes[3].second[pix] = 1.0f;  // alpha: an opaque film, like Blender's default
            if (h.t >= kInf) {
                set(0, pix, skyColour(dir));
                planes[4].second[pix] = kSkyDepth;  // normal, position, albedo, light stay 0
                continue;
            }
            const dvec3 p = cam.eye + h.t * dir;
            const dvec3 light = directDiffuse(p, h.normal);
            set(0, pix, h.albedo * light);
            planes[4].second[pix] = static_cast<float>(glm::dot(p - cam.eye, fwd));
            set(5, pix, h.normal);
            set(8, pix, p);
            set(11, pix, h.albedo);
            set(14, pix, light);
        }
    }

    try {
        const fs::path out(outPath);
        const fs::path sidecar = out.parent_path() / (out.stem().string() + ".json");
        if (!out.parent_path().empty()) fs::create_directories(out.parent_path());
        const std::string tmpExr = outPath + ".tmp", tmpJson = sidecar.string() + ".tmp";
        writeExr(tmpExr, W, H, planes);
        writeSidecar(tmpJson, cam, W, H);
        fs::rename(tmpExr, out);
        fs::rename(tmpJson, sidecar);
        std::printf("wrote %s (%dx%d) and %s\n", outPath.c_str(), W, H, sidecar.string().c_str());
    } catch (const std::exception& e) {
        std::fprintf(stderr, "make_demo_scene: %s\n", e.what());
        std::error_code ec;
        fs::remove(outPath + ".tmp", ec);
        fs::remove((fs::path(outPath).parent_path() / (fs::path(outPath).stem().string() + ".json.tmp")), ec);
        return 1;
    }
    return 0;
}
