// Disc AO against HBAO `high` on the same 1920x1080 frame (tests/support/scenes.h's bench
// room, R 0.5, cosine weighting, binary visibility), the operator's compute stage on all
// threads of the CPU. The first run is HBAO high; every run reports
//   "xHbaoHigh"  its frame time / HBAO high's frame time, measured in this process;
//   "xHbaoHighCpu" the same for the process's CPU time (all threads), steadier than the
//                frame time when other jobs share the cores;
//   "pyramid_ms" (discs) the part spent building the pyramid on the host.
// Then discs at each preset, and the default preset with each correction or option switched
// (sum: without the union per slice; border-open: without the continuation past the edge).
// Environment: OBSCURA_BENCH_WIDTH / OBSCURA_BENCH_HEIGHT, OBSCURA_BENCH_RADIUS (0.5),
// OBSCURA_BENCH_GL=1 adds the discs default preset on gl-osmesa.
#include "bench_env.h"
#include "core/methods.h"
#include "core/operator.h"
#include "support/scenes.h"

#include <benchmark/benchmark.h>

#include <chrono>
#include <ctime>
#include <cstdlib>
#include <map>
#include <string>
#include <utility>

using namespace obscura;
using namespace obscura::test;
using obscura::bench::envFloat;
using obscura::bench::envInt;

namespace {

const SceneBuffers& scene() {
    static const SceneBuffers sb = [] {
        const int w = envInt("OBSCURA_BENCH_WIDTH", 1920), h = envInt("OBSCURA_BENCH_HEIGHT", 1080);
        return renderScene(benchRoomScene(), benchRoomCamera(w, h), w, h);
    }();
    return sb;
}

double gHbaoHighSeconds = 0, gHbaoHighCpu = 0;

void BM_Run(benchmark::State& state, Settings s, bool reference) {
    const OperatorInputs in = scene().inputs();
    double seconds = 0, cpu = 0;
    std::map<std::string, double> stages;
    for (auto _ : state) {
        const auto t0 = std::chrono::steady_clock::now();
        const std::clock_t c0 = std::clock();
        OperatorOutputs out = runOperator(in, s);
        cpu += (double)(std::clock() - c0) / CLOCKS_PER_SEC;
        seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        benchmark::DoNotOptimize(out.ao.pixels.data());
        for (const StageTiming& t : out.stats.timings) stages[t.name] += t.seconds;
    }
    const double n = (double)state.iterations(), perFrame = seconds / n;
    if (reference) gHbaoHighSeconds = perFrame, gHbaoHighCpu = cpu / n;  // its last (longest) run
    const double pixels = (double)scene().depth.width * scene().depth.height;
    state.counters["MP/s"] = pixels * 1e-6 / perFrame;
    state.counters["xHbaoHigh"] = perFrame / gHbaoHighSeconds;
    state.counters["xHbaoHighCpu"] = cpu / n / gHbaoHighCpu;
    if (stages.count("discs-pyramid")) state.counters["pyramid_ms"] = stages["discs-pyramid"] / n * 1e3;
}

Settings base(const char* method, const char* quality) {
    Settings s;
    s.method = method;
    s.radius = envFloat("OBSCURA_BENCH_RADIUS", 0.5f);
    s.weighting = Weighting::Cosine;
    s.falloff = Falloff::None;
    applyMethodPresets(quality, s);
    s.blur = 0;  // the methods alone
    return s;
}

} // namespace

int main(int argc, char** argv) {
    std::printf("frame %dx%d (bench room)\n", scene().depth.width, scene().depth.height);
    auto add = [](const std::string& name, const Settings& s) {
        benchmark::RegisterBenchmark(name.c_str(), BM_Run, s, name == "hbao_high")->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(1.0);
    };
    add("hbao_high", base("hbao", "high"));  // first: the reference of xHbaoHigh
    for (const char* q : {"low", "medium", "high", "ultra"}) add(std::string("discs_") + q, base("discs", q));
    // The default preset with one correction or option switched.
    const std::pair<const char*, void (*)(Settings&)> variants[] = {
        {"passes:2", [](Settings& s) { s.discsPasses = 2; }},
        {"no-polygon", [](Settings& s) { s.discsNoPolygon = true; }},
        {"blend-levels", [](Settings& s) { s.discsBlendLevels = true; }},
        {"sum", [](Settings& s) { s.discsSum = true; }},
        {"border-open", [](Settings& s) { s.border = kBorderOpen; }}};
    for (const auto& [name, set] : variants) {
        Settings v = base("discs", "medium");
        set(v);
        add(std::string("discs_medium/") + name, v);
    }
    if (std::getenv("OBSCURA_BENCH_GL")) {
        Settings s = base("discs", "medium");
        s.device = "gl-osmesa";
        add("discs_medium/gl-osmesa", s);
    }
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
