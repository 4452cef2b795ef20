// reference_render: ray-traced (Embree) reference renders for obscura. Writes a
// Blender-style multilayer EXR with beauty, depth, normals, position, albedo,
// direct and one-bounce indirect diffuse light, plus ground-truth AO layers for
// the four definitions obscura offers, and a camera sidecar.
#include "analytic_check.h"
#include "deep_output.h"
#include "exr_output.h"
#include "render.h"
#include "scene.h"
#include "tracer.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <memory>
#include <string>

namespace {

using namespace reference;

int usage(FILE* to) {
    std::fprintf(to,
                 "usage: reference_render --scene NAME -o OUTPUT.exr [options]\n"
                 "  --scene NAME       corner, sphere-plane, cornell, stairs, poles, city, terrain,\n"
                 "                     studio (the built-in demo), or obj:PATH (default studio)\n"
                 "  -o OUTPUT.exr      output; the camera sidecar goes to OUTPUT's stem + .json\n"
                 "  --width W          image width (320)\n"
                 "  --height H         image height (240)\n"
                 "  --radius R         AO radius in world units (the scene's default)\n"
                 "  --ao-rays N        AO rays per pixel and weighting (256)\n"
                 "  --gi-rays N        cosine rays per pixel for sky light and one bounce (64)\n"
                 "  --seed S           sampling seed (1)\n"
                 "  --threads N        threads, 0 = all cores (0)\n"
                 "  --overscan N       also render N pixels past each edge: a data window larger than the\n"
                 "                     W x H display window, as renderers write overscan (0)\n"
                 "  --env FILE.exr     lat-long environment: also write Reference.DO.R/G/B, the ground-truth\n"
                 "                     directional occlusion of obscura's SSDO (cosine AO rays, linear falloff)\n"
                 "                     (FILE \"sky\": the scene's own sky as a 128x64 map, written to OUTPUT's stem + _sky.exr)\n"
                 "  --env-rotate DEG   rotation of the environment about up, as obscura --env-rotate (0)\n"
                 "  --do-sun           Reference.DO also holds the sun, as obscura --light (blocked within the radius)\n"
                 "  --deep FILE.exr    also write every surface along each primary ray as a deep EXR\n"
                 "                     (one sample per solid: Z where the ray enters, ZBack where it leaves,\n"
                 "                     R, G, B what the entered surface radiates: DiffDir x DiffCol there)\n"
                 "  --check            compare with closed forms (corner crease; open ground plane); exit 1 on failure\n"
                 "  --quiet            print nothing but errors\n");
    return to == stderr ? 2 : 0;
}

bool parseInt(const char* s, long lo, long hi, long& out) {
    char* end = nullptr;
    const long v = std::strtol(s, &end, 10);
    if (end == s || *end != '\0' || v < lo || v > hi) return false;
    out = v;
    return true;
}

void printConvergence(const RenderSettings& s, const Convergence& c, double seconds) {
    std::printf("rays per pixel: AO %d per weighting (uniform, cosine; both falloffs share hits), GI %d\n", s.aoRays,
                s.giRays);
    std::printf("%-30s %-9s %-15s %-15s\n", "layer (non-sky pixels)", "mean", "std err mean", "std err max");
    for (int l = 0; l < kAoLayers; ++l)
        std::printf("Reference.%-20s %-9.4f %-15.5f %-15.5f\n", kAoLayerNames[l], c.aoMean[l], c.aoStdErrMean[l],
                    c.aoStdErrMax[l]);
    std::printf("%-30s %-9.4f %-15.5f %-15.5f\n", "ViewLayer.DiffInd (luminance)", c.indirectMean, c.indirectStdErrMean,
                c.indirectStdErrMax);
    if (s.giRays > 0)
        std::printf("%-30s %-9.4f\n%-30s %-9.4f\n", "Reference.GI (luminance)", c.giNearMean,
                    "Reference.GI_unlimited (lum.)", c.giFullMean);
    if (s.environment) std::printf("%-30s %-9.4f\n", "Reference.DO (luminance)", c.directionalMean);
    std::printf("(standard errors are iid estimates; Owen-scrambled Sobol sampling does better)\n");
    std::printf("%zu surface pixels, %.2f s\n", c.surfacePixels, seconds);
}

} // namespace

int main(int argc, char** argv) {
    std::string sceneName = "studio", outPath;
    RenderSettings settings;
    double radius = -1, envRotate = 0;
    std::string envPath, deepPath;
    bool check = false, quiet = false;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto value = [&]() -> const char* {
            if (i + 1 >= argc) {
                std::fprintf(stderr, "reference_render: %s needs a value\n", a.c_str());
                std::exit(usage(stderr));
            }
            return argv[++i];
        };
        auto integer = [&](long lo, long hi) {
            long v = 0;
            const char* s = value();
            if (!parseInt(s, lo, hi, v)) {
                std::fprintf(stderr, "reference_render: %s needs an integer in [%ld, %ld], got %s\n", a.c_str(), lo, hi, s);
                std::exit(usage(stderr));
            }
            return v;
        };
        if (a == "-h" || a == "--help") return usage(stdout);
        else if (a == "--scene") sceneName = value();
        else if (a == "-o") outPath = value();
        else if (a == "--width") settings.width = int(integer(1, 16384));
        else if (a == "--height") settings.height = int(integer(1, 16384));
        else if (a == "--ao-rays") settings.aoRays = int(integer(1, 1 << 20));
        else if (a == "--gi-rays") settings.giRays = int(integer(1, 1 << 20));
        else if (a == "--seed") settings.seed = uint32_t(integer(0, 4294967295L));
        else if (a == "--threads") settings.threads = int(integer(0, 1024));
        else if (a == "--overscan") settings.overscan = int(integer(0, 16384));
        else if (a == "--check") check = true;
        else if (a == "--quiet") quiet = true;
        else if (a == "--do-sun") settings.sunInDo = true;
        else if (a == "--env") envPath = value();
        else if (a == "--deep") deepPath = value();
        else if (a == "--env-rotate") {
            char* end = nullptr;
            const char* s = value();
            envRotate = std::strtod(s, &end);
            if (end == s || *end != '\0' || !std::isfinite(envRotate)) {
                std::fprintf(stderr, "reference_render: --env-rotate needs a number, got %s\n", s);
                return usage(stderr);
            }
        } else if (a == "--radius") {
            char* end = nullptr;
            const char* s = value();
            radius = std::strtod(s, &end);
            if (end == s || *end != '\0' || !(radius > 0)) {
                std::fprintf(stderr, "reference_render: --radius needs a positive number, got %s\n", s);
                return usage(stderr);
            }
        } else if (!a.empty() && a[0] != '-' && outPath.empty()) outPath = a;
        else {
            std::fprintf(stderr, "reference_render: unexpected argument %s\n", a.c_str());
            return usage(stderr);
        }
    }
    if (outPath.empty()) {
        std::fprintf(stderr, "reference_render: no output given (-o OUTPUT.exr)\n");
        return usage(stderr);
    }

    try {
        const auto start = std::chrono::steady_clock::now();
        const Scene scene = makeScene(sceneName);
        settings.radius = radius > 0 ? radius : scene.defaultRadius;
        if (envPath == "sky") {
            EnvironmentMap sky = skyMap(scene.lighting);
            sky.rotationDeg = envRotate;
            const std::string skyPath = outPath.substr(0, outPath.rfind('.')) + "_sky.exr";
            writeEnvironment(skyPath, sky);
            settings.environment = std::make_shared<const EnvironmentMap>(std::move(sky));
        } else if (!envPath.empty())
            settings.environment = std::make_shared<const EnvironmentMap>(EnvironmentMap::load(envPath, envRotate));
        const Tracer tracer(scene);
        const PinholeCamera camera = PinholeCamera::lookAt(scene.camera, settings.width, settings.height);
        const Integrator integrator(scene, tracer, camera, settings);
        const Frame frame = render(integrator, settings);
        const Convergence convergence = summarise(frame);
        writeReference(outPath, frame, camera, {scene.name, settings, convergence});
        if (!deepPath.empty()) writeDeep(deepPath, traceDeep(tracer, camera, settings.threads, &integrator));
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        if (!quiet) {
            std::printf("reference_render: scene %s, %dx%d, AO radius %g -> %s\n", scene.name.c_str(), settings.width,
                        settings.height, settings.radius, outPath.c_str());
            printConvergence(settings, convergence, seconds);
        }
        if (check && !runAnalyticChecks(scene.name, frame, settings, scene)) return 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "reference_render: %s\n", e.what());
        return 1;
    }
    return 0;
}
