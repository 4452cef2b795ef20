// Throughput of HBAO on a realistic 1920x1080 frame (floor, walls, boxes, some sky), in
// megapixels per second:
//   isa:NAME    the CPU kernel alone, 1 thread, built for each instruction set this CPU runs
//               (scalar = a pixel at a time, the reference; then 4, 8, 16 pixels per register);
//   cpu         the operator's whole compute stage on the widest build, 1 thread and all;
//   sched:NAME  the widest kernel alone on all threads, scheduled by obscura's tile pool
//               ("pool", what runHbao uses) or by oneTBB's parallel_for over the same tiles;
//   PRESET      the quality presets, to show that time follows the sample count (ns/sample);
//               each as the horizon (--thickness inf --border open), the defaults, and the
//               defaults with one option back at the horizon's (border:open, thickness:inf);
//   PRESET/bounce  the defaults with the indirect light (--bounce, a uniform source times an albedo),
//               each iteration also running the AO alone: "xAo" = its time / AO's, same process;
//   PRESET/deep:K  the same with deep input of K layers (synthetic: the visible surface as a
//               slab, then surfaces and slabs behind it), the cost of reading and testing them;
//   PRESET/deep:4/bounce  the light with those layers, each hidden one coloured, against the
//               deep AO alone ("xAo", as /bounce's);
//   METHOD_PRESET  the other AO methods of the method table at their quality levels;
//   gl-*        every OpenGL device this machine can open, with the upload/compute/readback split.
//
// Every run also reports ratios measured in this process, so numbers from noisy machines
// stay comparable:
//   "xBase"  frame time / frame time of the first run (the scalar build, 1 thread, uniform, linear);
//   "xCopy"  frame time / time to memcpy the depth + normal planes once;
//   "xCpu"   (GL runs) frame time / the all-threads CPU frame time of the same case.
//
// Environment: OBSCURA_BENCH_EXR=FILE.exr runs on a render instead (its passes and camera
// found as the CLI finds them); OBSCURA_BENCH_WIDTH / OBSCURA_BENCH_HEIGHT set the size of
// the built-in frame; OBSCURA_BENCH_DIRECTIONS / OBSCURA_BENCH_STEPS the sample counts (8 x 8),
// OBSCURA_BENCH_RADIUS the radius (0.5), OBSCURA_BENCH_THREADS the "all threads" count (the cores;
// 1 keeps a shared machine's other load out of the ratios).
#include "bench_env.h"
#include "core/methods.h"
#include "core/operator.h"
#include "io/frame_job.h"
#include "cpu/lane_cpu.h"
#include "support/scenes.h"

#include <benchmark/benchmark.h>
#if defined(OBSCURA_BENCH_HAVE_TBB)
#include <tbb/blocked_range2d.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#endif

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
using obscura::bench::envFloat;
using obscura::bench::envInt;
using glm::dvec3;

namespace {

// A render's depth, normals and camera, as the CLI would read them.
SceneBuffers loadRender(const std::string& path) {
    FrameJob job;
    job.input = path;
    FramePasses p = loadFramePasses(job, {});
    SceneBuffers sb;
    sb.display = p.display;
    sb.data = p.data;
    sb.camera = resolveFrameCamera(job, p);
    sb.depthKind = p.plan.depthKind;
    sb.normalSpace = p.plan.normalSpace;
    sb.depth = std::move(p.depth);
    sb.normal = std::move(p.normal);
    if (p.plan.normalsLeftHanded && sb.normalSpace == NormalSpace::Camera) // as the frame job does
        for (size_t i = 2; i < sb.normal.pixels.size(); i += 3) sb.normal.pixels[i] = -sb.normal.pixels[i];
    return sb;
}

SceneBuffers& scene() {
    static SceneBuffers sb = [] {
        if (const char* exr = std::getenv("OBSCURA_BENCH_EXR")) return loadRender(exr);
        const int w = envInt("OBSCURA_BENCH_WIDTH", 1920), h = envInt("OBSCURA_BENCH_HEIGHT", 1080);
        return renderScene(benchRoomScene(), benchRoomCamera(w, h), w, h);
    }();
    return sb;
}

Settings settingsFor(Weighting w, Falloff f, int threads, const std::string& device) {
    Settings s;
    s.device = device;
    s.radius = envFloat("OBSCURA_BENCH_RADIUS", 0.5f);
    s.directions = envInt("OBSCURA_BENCH_DIRECTIONS", 8);
    s.steps = envInt("OBSCURA_BENCH_STEPS", 8);
    s.weighting = w;
    s.falloff = f;
    s.blur = 0;  // the kernel alone (and what builds before the default blur ran)
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

// Shared by every run: seconds per frame -> the counters described at the top.
void report(benchmark::State& state, double perFrame, double samplesPerPixel) {
    const SceneBuffers& sb = scene();
    const double pixels = (double)sb.depth.width * sb.depth.height;
    if (gBaseSeconds == 0) gBaseSeconds = perFrame;
    state.SetItemsProcessed((int64_t)(state.iterations() * pixels));
    state.counters["MP/s"] = pixels * 1e-6 / perFrame;
    state.counters["xCopy"] = perFrame / copySeconds();
    state.counters["xBase"] = perFrame / gBaseSeconds;
    state.counters["ns/sample"] = perFrame * 1e9 / (pixels * samplesPerPixel);
}

// The kernel alone, on one named instruction set.
void BM_HbaoIsa(benchmark::State& state, Weighting w, Falloff f, std::string isa) {
    const SceneBuffers& sb = scene();
    const Settings s = settingsFor(w, f, 1, "cpu");
    const KernelParams p = makeKernelParams(sb.inputs(), s);
    Image ao(sb.depth.width, sb.depth.height, 1);
    double seconds = 0;
    for (auto _ : state) {
        const auto t0 = std::chrono::steady_clock::now();
        cpu::runHbao(p, sb.depth.view(), sb.normal.view(), ao.view(), 1, isa);
        seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        benchmark::DoNotOptimize(ao.pixels.data());
    }
    report(state, seconds / (double)state.iterations(), (double)s.directions * s.steps);
}

// The widest kernel alone on `threads` threads, tiles handed out by `scheduler`.
void BM_Scheduler(benchmark::State& state, Weighting w, Falloff f, int threads, std::string scheduler) {
    const SceneBuffers& sb = scene();
    const Settings s = settingsFor(w, f, threads, "cpu");
    const KernelParams p = makeKernelParams(sb.inputs(), s);
    Image ao(sb.depth.width, sb.depth.height, 1);
    const std::string isa = cpu::laneIsas().back();
    const cpu::HbaoTileFn tile = cpu::hbaoTileFor(isa);
    const Image edges = cpu::hbaoEdgeTexels(sb.depth.view(), sb.normal.view());
    double seconds = 0;
    for (auto _ : state) {
        const auto t0 = std::chrono::steady_clock::now();
        if (scheduler == "pool") {
            cpu::runHbao(p, sb.depth.view(), sb.normal.view(), ao.view(), threads, isa);
        } else {
#if defined(OBSCURA_BENCH_HAVE_TBB)
            tbb::task_arena arena(threads);
            arena.execute([&] {
                tbb::parallel_for(tbb::blocked_range2d<int>(0, p.height, cpu::kLaneTileHeight, 0, p.width,
                                                            cpu::kLaneTileWidth),
                                  [&](const tbb::blocked_range2d<int>& r) {
                                      tile(p, sb.depth.view(), sb.normal.view(), edges.view(), ao.view(),
                                           Box2i{r.cols().begin(), r.rows().begin(), r.cols().end(), r.rows().end()});
                                  });
            });
#endif
        }
        seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        benchmark::DoNotOptimize(ao.pixels.data());
    }
    report(state, seconds / (double)state.iterations(), (double)s.directions * s.steps);
}

// K (front, back) layers per texel: the visible surface 0.2 deep, then alternately a point
// surface and a 0.5-deep slab, 0.4 apart (docs/deep.md).
Image syntheticDeepLayers(int layers) {
    std::vector<std::pair<float, float>> offsets = {{0.0f, 0.2f}};
    for (int k = 1; k < layers; ++k) offsets.emplace_back(0.4f * k, 0.4f * k + (k % 2 == 0 ? 0.5f : 0.0f));
    return deepLayersFromDepth(scene().depth, offsets);
}

void runHbaoBench(benchmark::State& state, const Settings& s, const std::string& caseName, int deepLayers) {
    const SceneBuffers& sb = scene();
    OperatorInputs in = sb.inputs();
    const Image deep = deepLayers > 0 ? syntheticDeepLayers(deepLayers) : Image();
    if (deepLayers > 0) in.deepLayers = deep.view();
    double seconds = 0;
    std::map<std::string, double> stages;
    if (s.device != "cpu") runOperator(in, s); // compiles the device's shaders outside the timing
    for (auto _ : state) {
        const auto t0 = std::chrono::steady_clock::now();
        OperatorOutputs out = runOperator(in, s);
        seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        benchmark::DoNotOptimize(out.ao.pixels.data());
        for (const StageTiming& t : out.stats.timings) stages[t.name] += t.seconds;
    }
    const double n = (double)state.iterations();
    const double perFrame = seconds / n;
    report(state, perFrame, (double)findMethod(s.method)->samplesPerPixel(s));
    if (s.device == "cpu" && s.threads != 1) gCpuSeconds[caseName] = perFrame;
    if (s.device != "cpu") {
        state.counters["upload_ms"] = stages["gl-upload"] / n * 1e3;
        state.counters["compute_ms"] = stages["gl-compute"] / n * 1e3;
        state.counters["readback_ms"] = stages["gl-readback"] / n * 1e3;
        if (gCpuSeconds.count(caseName)) state.counters["xCpu"] = perFrame / gCpuSeconds[caseName];
    }
}

void BM_Hbao(benchmark::State& state, Settings s, std::string caseName) { runHbaoBench(state, s, caseName, 0); }

// --bounce against AO alone at the same settings (with `deepLayers` synthetic layers each, the
// hidden ones coloured), alternating in one loop so that both see the same load: "xAo" is the
// ratio the target (1.5) is about.
void BM_HbaoBounce(benchmark::State& state, Settings s, int deepLayers) {
    const SceneBuffers& sb = scene();
    const int w = sb.depth.width, h = sb.depth.height;
    const Image radiance(w, h, 3, 1.0f), albedo(w, h, 3, 0.5f), colour(w, h, 3 * std::max(deepLayers, 1), 0.8f);
    const Image deep = deepLayers > 0 ? syntheticDeepLayers(deepLayers) : Image();
    OperatorInputs aoIn = sb.inputs();
    if (deepLayers > 0) aoIn.deepLayers = deep.view();
    OperatorInputs in = aoIn;
    in.radiance = radiance.view();
    in.albedo = albedo.view();
    if (deepLayers > 0) in.deepColour = colour.view();
    Settings ao = s;
    s.bounce = true;
    double giSeconds = 0, aoSeconds = 0;
    std::map<std::string, double> giStages, aoStages;
    if (s.device != "cpu") runOperator(in, s), runOperator(aoIn, ao); // shaders compiled untimed
    for (auto _ : state) {
        auto t0 = std::chrono::steady_clock::now();
        OperatorOutputs out = runOperator(in, s);
        giSeconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        benchmark::DoNotOptimize(out.indirect.pixels.data());
        for (const StageTiming& t : out.stats.timings) giStages[t.name] += t.seconds;
        t0 = std::chrono::steady_clock::now();
        out = runOperator(aoIn, ao);
        aoSeconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        benchmark::DoNotOptimize(out.ao.pixels.data());
        for (const StageTiming& t : out.stats.timings) aoStages[t.name] += t.seconds;
    }
    const double n = (double)state.iterations();
    report(state, giSeconds / n, (double)s.directions * s.steps);
    state.counters["xAo"] = giSeconds / aoSeconds;
    state.counters["source_ms"] = giStages["gi-source"] / n * 1e3;
    // On a GL device, the shaders' time alone: the light's against AO's.
    if (s.device != "cpu") state.counters["xAoCompute"] = giStages["gl-compute"] / aoStages["gl-compute"];
}

void BM_HbaoDeep(benchmark::State& state, Settings s, int layers) { runHbaoBench(state, s, "preset", layers); }

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
    const int all = envInt("OBSCURA_BENCH_THREADS", (int)std::max(1u, std::thread::hardware_concurrency()));
    const SceneBuffers& sb = scene();
    long long sky = 0;
    for (float d : sb.depth.pixels) sky += d >= 1e9f;
    std::printf("frame %s: ", std::getenv("OBSCURA_BENCH_EXR") ? std::getenv("OBSCURA_BENCH_EXR") : "built-in scene");
    std::printf("%dx%d, %.1f%% sky, depth+normal copy %.3f ms\n", sb.depth.width, sb.depth.height,
                100.0 * sky / sb.depth.pixels.size(), copySeconds() * 1e3);

    const struct {
        Weighting w;
        Falloff f;
        const char* name;
    } cases[] = {{Weighting::Uniform, Falloff::Linear, "uniform/linear"},
                 {Weighting::Uniform, Falloff::None, "uniform/none"},
                 {Weighting::Cosine, Falloff::Linear, "cosine/linear"},
                 {Weighting::Cosine, Falloff::None, "cosine/none"}};
    auto options = [](benchmark::internal::Benchmark* b) {
        b->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(0.5);
    };
    // The first registered run is the xBase reference: the scalar build, 1 thread, uniform, linear.
    for (const std::string& isa : cpu::laneIsas())
        for (const auto& c : cases) {
            const std::string name = "hbao_8x8/" + std::string(c.name) + "/isa:" + isa;
            options(benchmark::RegisterBenchmark(name.c_str(), BM_HbaoIsa, c.w, c.f, isa));
        }
    // CPU runs come before GL ones, so each GL run can be divided by the CPU time of its case.
    auto add = [&](const std::string& device, int threads, const auto& c) {
        const std::string name = "hbao_8x8/" + std::string(c.name) + "/" + device +
                                 (device == "cpu" ? "/threads:" + std::to_string(threads) : "");
        options(benchmark::RegisterBenchmark(name.c_str(), BM_Hbao, settingsFor(c.w, c.f, threads, device),
                                             std::string(c.name)));
    };
    for (int threads : {1, all}) {
        if (threads == all && all == 1) break;
        for (const auto& c : cases) add("cpu", threads, c);
    }
    std::vector<std::string> schedulers = {"pool"};
#if defined(OBSCURA_BENCH_HAVE_TBB)
    schedulers.push_back("tbb");
#endif
    for (const std::string& scheduler : schedulers)
        for (const auto& c : cases) {
            const std::string name = "hbao_8x8/" + std::string(c.name) + "/sched:" + scheduler + "/threads:" +
                                     std::to_string(all);
            options(benchmark::RegisterBenchmark(name.c_str(), BM_Scheduler, c.w, c.f, all, scheduler));
        }
    // Presets: ns/sample stays put when time follows the sample count.
    for (const QualityPreset& q : qualityPresets()) {
        Settings s = settingsFor(Weighting::Cosine, Falloff::None, all, "cpu");
        applyQualityPreset(q.name, s);
        s.blur = 0; // the sample count alone
        const std::string name = "hbao_" + std::string(q.name) + "_" + std::to_string(q.directions) + "x" +
                                 std::to_string(q.steps) + "/cosine/none/cpu/threads:" + std::to_string(all);
        // The horizon alone (infinite thickness, open sky past the edge: HBAO before --thickness and
        // --border), then the defaults (the visibility bitmask at thickness auto, tangent border) and
        // each of their two options alone over the horizon: their cost over it at the same level.
        const auto registerSplit = [&](const std::string& prefix, const Settings& defaults, const std::string& defaultsCase) {
            Settings horizon = defaults;
            horizon.thickness = kThicknessInfinite;
            horizon.border = kBorderOpen;
            Settings openBorder = defaults;
            openBorder.border = kBorderOpen;
            Settings tangentOnly = horizon;
            tangentOnly.border = defaults.border;
            for (const auto& [variant, settings] : {std::pair<const char*, const Settings&>{"horizon", horizon},
                                                    {"defaults", defaults},
                                                    {"border:open", openBorder},
                                                    {"thickness:inf", tangentOnly}})
                options(benchmark::RegisterBenchmark((prefix + "/" + variant).c_str(), BM_Hbao, settings,
                                                     std::string(variant) == "defaults" ? defaultsCase : "preset"));
        };
        registerSplit(name, s, "preset/" + std::string(q.name)); // GL's presets divide by its time
        options(benchmark::RegisterBenchmark((name + "/bounce").c_str(), BM_HbaoBounce, s, 0));
        Settings thin = s;
        thin.thickness = 0.1f;
        options(benchmark::RegisterBenchmark((name + "/thickness:0.1").c_str(), BM_Hbao, thin, std::string("preset")));
        for (int layers : {1, 4})
            options(benchmark::RegisterBenchmark((name + "/deep:" + std::to_string(layers)).c_str(), BM_HbaoDeep, s,
                                                 layers));
        options(benchmark::RegisterBenchmark((name + "/deep:4/bounce").c_str(), BM_HbaoBounce, s, 4));
        // The same under the flags' own defaults, uniform weighting and linear falloff (runs also
        // weight the falloff).
        Settings paper = settingsFor(Weighting::Uniform, Falloff::Linear, all, "cpu");
        applyQualityPreset(q.name, paper);
        paper.blur = 0;
        registerSplit("hbao_" + std::string(q.name) + "_" + std::to_string(q.directions) + "x" +
                          std::to_string(q.steps) + "/uniform/linear/cpu/threads:" + std::to_string(all),
                      paper, "preset");
    }
    // The other AO methods' levels on the same frame (ssao: Crytek's sphere form), to set
    // against HBAO's: the error-against-time report pairs these times with accuracy.
    for (const MethodInfo& m : methods()) {
        if (std::string(m.name) == "hbao" || !methodOutputs(m.name, "ao") || m.presets.empty()) continue;
        for (const MethodPreset& q : m.presets) {
            Settings s = settingsFor(Weighting::Cosine, Falloff::None, all, "cpu");
            s.method = m.name;
            q.apply(s);
            s.blur = 0;
            const std::string name = std::string(m.name) + "_" + q.quality +
                                     "/cosine/none/cpu/threads:" + std::to_string(all);
            options(benchmark::RegisterBenchmark(name.c_str(), BM_Hbao, s, std::string("preset")));
        }
    }
    for (const std::string& device : glDevices()) {
        for (const auto& c : cases) add(device, all, c);
        // The presets on this device: AO, then --bounce against AO on the same device ("xAo").
        for (const QualityPreset& q : qualityPresets()) {
            Settings s = settingsFor(Weighting::Cosine, Falloff::None, all, device);
            applyQualityPreset(q.name, s);
            s.blur = 0;
            const std::string name = "hbao_" + std::string(q.name) + "/cosine/none/" + device;
            options(benchmark::RegisterBenchmark(name.c_str(), BM_Hbao, s, "preset/" + std::string(q.name)));
            options(benchmark::RegisterBenchmark((name + "/bounce").c_str(), BM_HbaoBounce, s, 0));
        }
    }
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
