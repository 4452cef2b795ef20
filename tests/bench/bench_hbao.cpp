// Throughput of HBAO on a realistic 1920x1080 frame (floor, walls, boxes, some sky)
// at 8 directions x 8 steps, in megapixels per second, on the CPU (1 thread and all
// threads) and on every OpenGL device this machine can open (gl-osmesa, gl-egl), side
// by side. GL runs also report their upload / compute / readback split in ms.
//
// Every run also reports two ratios measured in this process, so numbers from
// noisy machines stay comparable:
//   "xCopy"  frame time / time to memcpy the depth + normal planes once
//            ("AO costs as much as copying the inputs N times");
//   "xBase"  frame time / frame time of the first run (1 thread, uniform, linear);
//   "xCpu"   (GL runs) frame time / the all-threads CPU frame time of the same case.
//
// Environment: OBSCURA_BENCH_WIDTH / OBSCURA_BENCH_HEIGHT override the frame size.
#include "core/operator.h"
#include "support/scenes.h"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <string>
#include <thread>
#include <vector>

using namespace obscura;
using namespace obscura::test;
using glm::dvec3;

namespace {

int envInt(const char* name, int fallback) {
    const char* v = std::getenv(name);
    return v && std::atoi(v) > 0 ? std::atoi(v) : fallback;
}

// A room corner open to the sky on the right and above: floor, back and left walls,
// boxes of several sizes (some stacked, some touching walls), a tilted slab.
SceneBuffers& scene() {
    static SceneBuffers sb = [] {
        const int w = envInt("OBSCURA_BENCH_WIDTH", 1920), h = envInt("OBSCURA_BENCH_HEIGHT", 1080);
        std::vector<Rect> rects;
        rects.push_back({dvec3(-6, 0, -8), dvec3(14, 0, 0), dvec3(0, 0, 16)});  // floor, ends at x = 8
        rects.push_back({dvec3(-6, 0, -8), dvec3(14, 0, 0), dvec3(0, 3, 0)});   // back wall, 3 high
        rects.push_back({dvec3(-6, 0, -8), dvec3(0, 0, 16), dvec3(0, 4, 0)});   // left wall, 4 high
        addBox(rects, dvec3(-6, 0, -8), dvec3(-4.5, 2.2, -6.5));  // cupboard in the corner
        addBox(rects, dvec3(-2, 0, -3), dvec3(-0.8, 1.2, -1.8));
        addBox(rects, dvec3(-1.9, 1.2, -2.9), dvec3(-1.1, 1.8, -2.1)); // stacked
        addBox(rects, dvec3(0.5, 0, -5), dvec3(2.5, 0.6, -4));
        addBox(rects, dvec3(1.5, 0, -1), dvec3(1.9, 0.4, -0.6));
        addBox(rects, dvec3(-6, 0, -1), dvec3(-5.4, 0.9, 1));     // against the left wall
        addBox(rects, dvec3(3, 0, -7.9), dvec3(4, 2.5, -7));      // pillar at the back wall
        rects.push_back({dvec3(-3.5, 0, 0.5), dvec3(1.2, 0.6, 0), dvec3(0, 0, 1.0)}); // ramp
        const Camera cam = lookAtPerspective(dvec3(1.5, 2.2, 5.5), dvec3(-1, 0.6, -3), 75.0 * M_PI / 180, w, h);
        return renderScene(rects, cam, w, h);
    }();
    return sb;
}

Settings settingsFor(Weighting w, Falloff f, int threads, const std::string& device) {
    Settings s;
    s.device = device;
    s.radius = 0.5f;
    s.directions = envInt("OBSCURA_BENCH_DIRECTIONS", 8);
    s.steps = envInt("OBSCURA_BENCH_STEPS", 8);
    s.weighting = w;
    s.falloff = f;
    s.threads = threads;
    return s;
}

// Best-of-N time to copy the inputs the kernel reads (depth + 3-channel normal).
double copySeconds() {
    static const double t = [] {
        const SceneBuffers& sb = scene();
        std::vector<float> d(sb.depth.pixels.size()), n(sb.normal.pixels.size());
        double best = 1e30;
        for (int i = 0; i < 20; ++i) {
            const auto t0 = std::chrono::steady_clock::now();
            std::memcpy(d.data(), sb.depth.pixels.data(), d.size() * sizeof(float));
            std::memcpy(n.data(), sb.normal.pixels.data(), n.size() * sizeof(float));
            benchmark::DoNotOptimize(d.data());
            benchmark::DoNotOptimize(n.data());
            benchmark::ClobberMemory();
            best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
        }
        return best;
    }();
    return t;
}

double gBaseSeconds = 0;                   // seconds per frame of the first (baseline) run
std::map<std::string, double> gCpuSeconds; // all-threads CPU seconds per frame, by case

void BM_Hbao(benchmark::State& state, Weighting w, Falloff f, int threads, std::string device, std::string caseName) {
    const SceneBuffers& sb = scene();
    const OperatorInputs in = sb.inputs();
    const Settings s = settingsFor(w, f, threads, device);
    double seconds = 0;
    std::map<std::string, double> stages;
    for (auto _ : state) {
        const auto t0 = std::chrono::steady_clock::now();
        OperatorOutputs out = runOperator(in, s);
        seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        benchmark::DoNotOptimize(out.ao.pixels.data());
        for (const StageTiming& t : out.stats.timings) stages[t.name] += t.seconds;
    }
    const double n = (double)state.iterations();
    const double pixels = (double)sb.depth.width * sb.depth.height;
    const double perFrame = seconds / n;
    if (gBaseSeconds == 0) gBaseSeconds = perFrame;
    if (device == "cpu" && threads != 1) gCpuSeconds[caseName] = perFrame;
    state.SetItemsProcessed((int64_t)(state.iterations() * pixels));
    state.counters["MP/s"] = pixels * 1e-6 / perFrame;
    state.counters["xCopy"] = perFrame / copySeconds();
    state.counters["xBase"] = perFrame / gBaseSeconds;
    if (device != "cpu") {
        state.counters["upload_ms"] = stages["gl-upload"] / n * 1e3;
        state.counters["compute_ms"] = stages["gl-compute"] / n * 1e3;
        state.counters["readback_ms"] = stages["gl-readback"] / n * 1e3;
        if (gCpuSeconds.count(caseName)) state.counters["xCpu"] = perFrame / gCpuSeconds[caseName];
    }
}

// The GL devices that can be opened here, each with its renderer, printed once.
std::vector<std::string> glDevices() {
    std::vector<std::string> found;
    for (const char* d : {"gl-osmesa", "gl-egl"}) {
        Settings s;
        s.device = d;
        try {
            std::printf("%-9s %s\n", d, describeDevice(s).c_str());
            found.push_back(d);
        } catch (const std::exception& e) {
            std::printf("%-9s unavailable: %s\n", d, e.what());
        }
    }
    return found;
}

} // namespace

int main(int argc, char** argv) {
    const int all = (int)std::max(1u, std::thread::hardware_concurrency());
    const SceneBuffers& sb = scene();
    long long sky = 0;
    for (float d : sb.depth.pixels) sky += d >= 1e9f;
    std::printf("frame %dx%d, %.1f%% sky, depth+normal copy %.3f ms\n", sb.depth.width, sb.depth.height,
                100.0 * sky / sb.depth.pixels.size(), copySeconds() * 1e3);

    const struct {
        Weighting w;
        Falloff f;
        const char* name;
    } cases[] = {{Weighting::Uniform, Falloff::Linear, "uniform/linear"},
                 {Weighting::Uniform, Falloff::None, "uniform/none"},
                 {Weighting::Cosine, Falloff::Linear, "cosine/linear"},
                 {Weighting::Cosine, Falloff::None, "cosine/none"}};
    // The first registered run is the xBase reference: 1 thread, uniform, linear. CPU runs come
    // first, so each GL run can be divided by the all-threads CPU time of its case.
    auto add = [](const std::string& device, int threads, const auto& c) {
        const std::string name = "hbao_8x8/" + std::string(c.name) + "/" + device +
                                 (device == "cpu" ? "/threads:" + std::to_string(threads) : "");
        benchmark::RegisterBenchmark(name.c_str(), BM_Hbao, c.w, c.f, threads, device, std::string(c.name))
            ->Unit(benchmark::kMillisecond)
            ->UseRealTime()
            ->MinTime(0.5);
    };
    for (int threads : {1, all}) {
        if (threads == all && all == 1) break;
        for (const auto& c : cases) add("cpu", threads, c);
    }
    for (const std::string& device : glDevices())
        for (const auto& c : cases) add(device, all, c);
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
