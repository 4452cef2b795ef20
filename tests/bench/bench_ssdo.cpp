// Throughput of SSDO and of the geometry-aware blur on the CPU, on a 1920x1080 frame of
// the studio scene (tests/support/scenes.h), in megapixels per second of the kernel
// (wall clock, "MP/s", and per CPU-second, "MP/cpu-s", steadier on a shared machine):
//   ssdo/default  the Settings defaults (64 samples, interleave 2: 16 per pixel), constant sky;
//   ssdo/envmap   the same with a lat-long environment map (its lookup per open sample);
//   ssdo/bounce   environment map, one bounce with albedo (--bounce);
//   blur/rgb      the blur alone, radius 2 (what interleave 2 runs), on a 3-channel signal.
// The environment is prefiltered as the operator does. Each case runs with the scalar (pixel-at-a-time) build at 1 thread, then the widest lane
// build this CPU runs at 1 and at all threads. "xScalar" is the scalar run's time over
// this run's, measured in this process, so it stays comparable on noisy machines.
//
// Environment: OBSCURA_BENCH_WIDTH / OBSCURA_BENCH_HEIGHT override the frame size.
#include "bench_env.h"
#include "core/operator.h"
#include "core/environment.h"
#include "cpu/blur_cpu.h"
#include "cpu/isa.h"
#include "cpu/ssdo_cpu.h"
#include "support/scenes.h"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <map>
#include <string>
#include <thread>

using namespace obscura;
using namespace obscura::test;
using obscura::bench::envInt;

namespace {

struct Frame {
    SceneBuffers sb;
    Image radiance, albedo, environment;
};

// The studio scene, lit by a sun for the bounce source, albedo by facing direction,
// and a sky-to-ground gradient with a bright spot as the environment.
const Frame& frame() {
    static const Frame f = [] {
        const int w = envInt("OBSCURA_BENCH_WIDTH", 1920), h = envInt("OBSCURA_BENCH_HEIGHT", 1080);
        Frame r{renderScene(studioScene(), studioCamera(w, h), w, h), Image(w, h, 3), Image(w, h, 3), Image(256, 128, 3)};
        const glm::vec3 sun = glm::normalize(glm::vec3(0.4f, 1.0f, 0.3f));
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const float* n = r.sb.normal.view().at(x, y);
                const glm::vec3 nv(n[0], n[1], n[2]);
                const glm::vec3 a = 0.5f + 0.4f * glm::abs(nv);
                const float lit = std::max(glm::dot(nv, sun), 0.0f);
                for (int c = 0; c < 3; ++c) {
                    r.albedo.view().at(x, y)[c] = a[c];
                    r.radiance.view().at(x, y)[c] = a[c] * lit * 3.0f;
                }
            }
        for (int y = 0; y < r.environment.height; ++y)
            for (int x = 0; x < r.environment.width; ++x) {
                const float up = 1.0f - (float)y / r.environment.height;
                const bool spot = std::abs(x - 60) < 4 && std::abs(y - 30) < 4;
                for (int c = 0; c < 3; ++c) r.environment.view().at(x, y)[c] = spot ? 50.0f : 0.2f + up * (0.3f + 0.2f * c);
            }
        return r;
    }();
    return f;
}

enum class Case { Default, EnvMap, Bounce, Blur };

std::map<std::string, double> gScalarSeconds; // per case: the scalar build's seconds per frame

struct Seconds {
    double wall = 0, cpu = 0;
};

double processCpuSeconds() {
    timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

// Wall and CPU seconds of one run of the case's kernel (cpu::runSsdo or cpu::runBlur, as
// the operator calls them, without the operator's allocations around them).
Seconds runOnce(Case c, int threads) {
    const Frame& f = frame();
    OperatorInputs in = f.sb.inputs();
    Settings s;
    s.method = "ssdo";
    s.radius = 0.5f;
    s.bounce = c == Case::Bounce;
    static const Image level = prefilterLatLong(f.environment, 16); // as the operator does for 16 samples a pixel
    static Image directional(f.sb.depth.width, f.sb.depth.height, 3), indirect = directional, ao(f.sb.depth.width, f.sb.depth.height, 1);
    static Image signal = [&] {
        Image img(f.sb.depth.width, f.sb.depth.height, 3);
        for (size_t i = 0; i < img.pixels.size(); ++i) img.pixels[i] = (float)((i * 2654435761u) % 1000) * 1e-3f;
        return img;
    }();
    glsl::KernelParams p = makeKernelParams(in, s);
    p.bounce = c == Case::Bounce;
    p.senderAlbedo = c == Case::Bounce;
    if (c != Case::Default) {
        p.envWidth = level.width;
        p.envHeight = level.height;
    }
    const cpu::SsdoPlanes planes{in.depth, in.normal, f.radiance.view(), f.albedo.view(), level.view()};
    const auto t0 = std::chrono::steady_clock::now();
    const double c0 = processCpuSeconds();
    if (c == Case::Blur) cpu::runBlur(p, in.depth, in.normal, signal.view(), 2, threads);
    else cpu::runSsdo(p, planes, directional.view(), indirect.view(), ao.view(), threads);
    return {std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), processCpuSeconds() - c0};
}

void BM_Case(benchmark::State& state, Case c, std::string caseName, std::string isa, int threads) {
    if (!cpu::forceCpuIsa(isa)) {
        state.SkipWithError(("this CPU cannot run " + isa).c_str());
        return;
    }
    double seconds = 0, cpuSeconds = 0;
    for (auto _ : state) {
        const Seconds t = runOnce(c, threads);
        seconds += t.wall;
        cpuSeconds += t.cpu;
    }
    cpu::forceCpuIsa("");
    const double pixels = (double)frame().sb.depth.width * frame().sb.depth.height;
    const double perFrame = seconds / (double)state.iterations();
    if (isa == "scalar") gScalarSeconds[caseName] = perFrame;
    state.SetItemsProcessed((int64_t)(state.iterations() * pixels));
    state.counters["MP/s"] = pixels * 1e-6 / perFrame;
    // Per CPU-second: what one core delivers, also when other processes share the machine.
    state.counters["MP/cpu-s"] = pixels * 1e-6 * (double)state.iterations() / cpuSeconds;
    if (gScalarSeconds.count(caseName)) state.counters["xScalar"] = gScalarSeconds[caseName] / perFrame;
}

} // namespace

int main(int argc, char** argv) {
    const int all = (int)std::max(1u, std::thread::hardware_concurrency());
    const Frame& f = frame();
    std::printf("frame %dx%d, studio scene; widest CPU build here: %s\n", f.sb.depth.width, f.sb.depth.height,
                cpu::cpuIsa());
    const struct {
        Case c;
        const char* name;
    } cases[] = {{Case::Default, "ssdo/default"}, {Case::EnvMap, "ssdo/envmap"}, {Case::Bounce, "ssdo/bounce"},
                 {Case::Blur, "blur/rgb"}};
    const std::string widest = cpu::cpuIsa();
    for (const auto& c : cases) {
        auto add = [&](const std::string& isa, int threads) {
            const std::string name = std::string(c.name) + "/" + isa + "/threads:" + std::to_string(threads);
            benchmark::RegisterBenchmark(name.c_str(), BM_Case, c.c, std::string(c.name), isa, threads)
                ->Unit(benchmark::kMillisecond)
                ->UseRealTime()
                ->MinTime(0.5);
        };
        add("scalar", 1);
        add(widest, 1);
        if (all > 1) add(widest, all);
    }
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
