// File I/O against an oiiotool copy: a 1920 x 1440 render with 23 float channels under
// Blender's pass names, ZIP-compressed to about 100 MB, is generated, then in the same process
// timed as `oiiotool in -o out`, `obscura --write copy`, `--write new` and `--write append`
// (median of several runs, interleaved), with obscura's stages from --report (read, compute,
// write; append: copy for the input's chunks, append for the new part).
// Not a ctest. Usage: bench_files [runs (3; 0: only write the render)] [threads (0 = all cores)] [work dir]
#include "support/cli_runner.h"
#include "support/scenes.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace obscura;

namespace {

constexpr int kWidth = 1920, kHeight = 1440;

// Deterministic noise in [-1, 1): a path tracer's per-pixel sample noise.
float noise(uint32_t x, uint32_t y, uint32_t c) {
    uint32_t h = x * 0x8da6b343u ^ y * 0xd8163841u ^ c * 0xcb1ab31fu;
    h ^= h >> 16;
    h *= 0x7feb352du;
    h ^= h >> 15;
    h *= 0x846ca68bu;
    h ^= h >> 16;
    return (float)(h >> 8) / (float)(1u << 23) - 1.0f;
}

// The 23 channels, name -> plane. Geometry is the analytic studio scene; the colour passes
// are its shading with ~1% sample noise, the albedo flat per surface and the emission mostly
// zero, so the file compresses about as a render does (~100 MB).
std::map<std::string, std::vector<float>> makeRender(const Camera& cam) {
    const test::SceneBuffers s = test::renderScene(test::studioScene(), cam, kWidth, kHeight);
    std::map<std::string, std::vector<float>> ch;
    const size_t n = (size_t)kWidth * kHeight;
    auto plane = [&](const std::string& name) -> std::vector<float>& { return ch[name] = std::vector<float>(n); };
    std::vector<float>& z = plane("ViewLayer.Depth.Z");
    for (size_t i = 0; i < n; ++i) z[i] = s.depth.pixels[i];
    for (int c = 0; c < 3; ++c) {
        std::vector<float>& nrm = plane(std::string("ViewLayer.Normal.") + "XYZ"[c]);
        std::vector<float>& pos = plane(std::string("ViewLayer.Position.") + "XYZ"[c]);
        for (size_t i = 0; i < n; ++i) nrm[i] = s.normal.pixels[3 * i + c], pos[i] = s.position.pixels[3 * i + c];
    }
    enum Pass { Combined, DiffCol, DiffDir, Emit, AO };
    const char* names[] = {"Combined", "DiffCol", "DiffDir", "Emit", "AO"};
    const glm::vec3 light = glm::normalize(glm::vec3(0.4f, 1, 0.3f));
    for (int pass = Combined; pass <= AO; ++pass)
        for (int c = 0; c < 3; ++c) {
            std::vector<float>& v = plane(std::string("ViewLayer.") + names[pass] + "." + "RGB"[c]);
            for (int y = 0; y < kHeight; ++y)
                for (int x = 0; x < kWidth; ++x) {
                    const size_t i = (size_t)y * kWidth + x;
                    const float* nv = &s.normal.pixels[3 * i];
                    if (!(s.depth.pixels[i] < 1e9f)) {  // sky: a gradient in the beauty, nothing elsewhere
                        v[i] = pass == Combined ? 0.05f + 0.1f * (float)y / kHeight : 0.0f;
                        continue;
                    }
                    // Flat albedo per surface orientation; Lambert shading; a small emitter.
                    const float albedo = 0.3f + 0.15f * (float)c + 0.2f * std::fabs(nv[(c + 1) % 3]);
                    const float shade = std::max(0.0f, glm::dot(glm::vec3(nv[0], nv[1], nv[2]), light));
                    const float sample = 1.0f + 0.01f * noise(x, y, pass * 3 + c);
                    float value = 0.0f;
                    if (pass == DiffCol) value = albedo;
                    else if (pass == DiffDir) value = shade * sample;
                    else if (pass == Combined) value = albedo * (0.2f + 0.8f * shade) * sample;
                    else if (pass == AO) value = std::min(1.0f, (0.6f + 0.4f * shade) * sample);
                    else if (std::hypot(x - 300.0f, y - 400.0f) < 60.0f) value = 4.0f;  // Emit
                    v[i] = value;
                }
        }
    std::vector<float>& alpha = plane("ViewLayer.Combined.A");
    std::fill(alpha.begin(), alpha.end(), 1.0f);
    return ch;
}

void writeRender(const std::string& path, const std::map<std::string, std::vector<float>>& ch, const Camera& cam) {
    Imf::Header h(kWidth, kHeight, 1.0f, Imath::V2f(0, 0), 1.0f, Imf::INCREASING_Y, Imf::ZIP_COMPRESSION);
    h.insert("software", Imf::StringAttribute("bench_files (Blender pass names)"));
    Imf::FrameBuffer fb;
    for (const auto& [name, v] : ch) {
        h.channels().insert(name, Imf::Channel(Imf::FLOAT));
        fb.insert(name, Imf::Slice(Imf::FLOAT, (char*)v.data(), sizeof(float), sizeof(float) * kWidth));
    }
    Imf::OutputFile out(path.c_str(), h);
    out.setFrameBuffer(fb);
    out.writePixels(kHeight);
    // Blender writes no camera: the pipeline's sidecar NAME.json carries it.
    nlohmann::json rows = nlohmann::json::array();
    for (int r = 0; r < 4; ++r)
        rows.push_back({cam.cameraToWorld[0][r], cam.cameraToWorld[1][r], cam.cameraToWorld[2][r], cam.cameraToWorld[3][r]});
    std::ofstream(fs::path(path).replace_extension(".json"))
        << nlohmann::json{{"projection", "persp"}, {"horizontal_fov_rad", cam.horizontalFovRad(kWidth)}, {"camera_to_world", rows}};
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
}

struct Timing {
    std::vector<double> wall;
    std::map<std::string, std::vector<double>> stages;  // from --report
};

void run(const std::string& program, const std::vector<std::string>& args, const std::string& report, Timing& t) {
    const auto t0 = std::chrono::steady_clock::now();
    const test::CliResult r = test::runProgram(program, args);
    t.wall.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    if (r.exitCode != 0) {
        std::fprintf(stderr, "%s failed (exit %d): %s%s", program.c_str(), r.exitCode, r.out.c_str(), r.err.c_str());
        std::exit(1);
    }
    if (report.empty()) return;
    std::ifstream f(report);
    const nlohmann::json j = nlohmann::json::parse(f);  // named: items() must not outlive it
    for (const auto& [stage, secs] : j.at("timings_s").items())
        t.stages[stage].push_back(secs.get<double>());
}

} // namespace

int main(int argc, char** argv) {
    const int runs = argc > 1 ? std::max(0, std::atoi(argv[1])) : 3;
    const std::string threads = argc > 2 ? argv[2] : "0";
    const fs::path dir = argc > 3 ? fs::path(argv[3]) : fs::temp_directory_path() / "obscura_bench_files";
    fs::create_directories(dir);
    const std::string in = (dir / "render.exr").string();

    const Camera cam = test::studioCamera(kWidth, kHeight);
    auto t0 = std::chrono::steady_clock::now();
    writeRender(in, makeRender(cam), cam);
    std::printf("input: %s, %dx%d, 23 float channels, zip, %.1f MB (generated in %.1f s)\n", in.c_str(), kWidth,
                kHeight, fs::file_size(in) / 1e6,
                std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    if (runs == 0) return 0;  // bench_farm.py --render copies it as its frames

    const std::vector<std::string> settings = {"--radius", "0.5", "--weighting", "cosine", "--falloff", "none",
                                               "--threads", threads, "--quiet"};
    struct Case {
        std::string label, program;
        std::vector<std::string> args;
        std::string report;
        Timing t;
    };
    std::vector<Case> cases = {
        {"oiiotool in -o out", OBSCURA_OIIOTOOL_PATH,
         {"--threads", threads, in, "-o", (dir / "oiio.exr").string()}, "", {}},
        {"obscura --write copy", OBSCURA_CLI_PATH, {in, "-o", (dir / "copy.exr").string(), "--write", "copy"},
         (dir / "copy.json").string(), {}},
        {"obscura --write new", OBSCURA_CLI_PATH, {in, "-o", (dir / "new.exr").string(), "--write", "new"},
         (dir / "new.json").string(), {}},
        {"obscura --write append", OBSCURA_CLI_PATH, {in, "-o", (dir / "append.exr").string(), "--write", "append"},
         (dir / "append.json").string(), {}},
    };
    for (Case& c : cases)
        if (!c.report.empty()) {
            c.args.insert(c.args.end(), settings.begin(), settings.end());
            c.args.insert(c.args.end(), {"--report", c.report});
        }
    for (int r = 0; r < runs; ++r)  // interleaved, so drift in the machine's load hits every case alike
        for (Case& c : cases) run(c.program, c.args, c.report, c.t);

    const double base = median(cases[0].t.wall);
    std::printf("median of %d runs, threads %s (0 = all cores), HBAO 8x8 cosine/none\n", runs, threads.c_str());
    std::printf("%-24s %7s %6s %6s %7s %6s %6s %6s %9s %10s\n", "", "wall s", "read", "camera", "compute", "write",
                "copy", "append", "output MB", "x oiiotool");
    for (const Case& c : cases) {
        const double wall = median(c.t.wall);
        auto stage = [&](const char* s) {
            auto it = c.t.stages.find(s);
            return it == c.t.stages.end() ? std::string("-") : std::to_string(median(it->second)).substr(0, 5);
        };
        const std::string out = c.args[c.program == OBSCURA_CLI_PATH ? 2 : 4];
        std::printf("%-24s %7.3f %6s %6s %7s %6s %6s %6s %9.1f %10.2f\n", c.label.c_str(), wall, stage("read").c_str(),
                    stage("camera").c_str(), stage("compute").c_str(), stage("write").c_str(), stage("copy").c_str(),
                    stage("append").c_str(), fs::file_size(out) / 1e6, wall / base);
    }
    return 0;
}
