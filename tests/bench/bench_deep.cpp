// Deep elements merged against the --flat deep path (docs/deep.md, issue 28's target): three
// 1024 x 576 deep elements (tests/support/deep_elements.h: a ball, a tree, the ground) are
// generated, then in the same process, interleaved, timed end to end (read, merge, HBAO, write):
//   baselines: each element's deep file with --flat (its flattened image, written once
//              beforehand), as obscura ran deep input before deep elements;
//   merged:    the three elements, merged and flattened, with the merge's layers;
//   merged + per-element AO: the same with --per-element-ao (three more HBAO runs);
//   merged + bounce: the merge with hbao's light (--bounce-source beauty, the GI layer alone),
//              every hidden layer radiating its element's colour: its cost against the merge's
//              AO alone is the last line.
// Same settings and --deep-layers for all; ratios to the ball's and to the ground's baseline (the
// ground covers half the frame, the ball a few percent: HBAO's work follows the surface pixels).
// Not a ctest.
// Usage: bench_deep [runs (5)] [deep layers (4)] [quality (medium)] [work dir]
#include "io/frame_job.h"
#include "support/deep_elements.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace obscura;

namespace {

constexpr int kWidth = 1024, kHeight = 576;

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
}

double timed(const FrameJob& job, std::map<std::string, std::vector<double>>& stages) {
    const auto t0 = std::chrono::steady_clock::now();
    const FrameReport report = runFrameJob(job);
    for (const StageTiming& t : report.stages) stages[t.name].push_back(t.seconds);
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

std::string stageText(const std::map<std::string, std::vector<double>>& stages) {
    std::string text;
    char one[64];
    for (const auto& [name, secs] : stages) {
        std::snprintf(one, sizeof one, "%s%s %.3f", text.empty() ? "" : ", ", name.c_str(), median(secs));
        text += one;
    }
    return text;
}

} // namespace

int main(int argc, char** argv) {
    const int runs = argc > 1 ? std::max(1, std::atoi(argv[1])) : 5;
    const int layers = argc > 2 ? std::atoi(argv[2]) : 4;
    const std::string quality = argc > 3 ? argv[3] : "medium";
    const fs::path dir = argc > 4 ? fs::path(argv[4]) : fs::temp_directory_path() / "obscura_bench_deep";
    fs::create_directories(dir);
    const std::vector<std::pair<std::string, test::DeepHit>> elements = {
        {"ball", test::deepBall}, {"tree", test::deepTree}, {"ground", test::deepGround}};
    FrameJob base;
    base.camera.fovDeg = test::kDeepFovDeg;
    if (!applyQualityPreset(quality, base.settings)) return std::fprintf(stderr, "unknown quality %s\n", quality.c_str()), 2;
    base.settings.deepLayers = layers;
    base.settings.radius = 1.0f;
    base.settings.falloff = Falloff::None;  // linear falloff ignores deep layers: nothing deep would be timed
    struct Case {
        std::string label;
        FrameJob job;
        std::vector<double> wall;
        std::map<std::string, std::vector<double>> stages;
    };
    std::vector<Case> cases;
    FrameJob merged = base;
    for (const auto& [name, hit] : elements) {
        const std::string deep = (dir / (name + ".exr")).string(), flat = (dir / (name + "_flat.exr")).string();
        test::writeDeepElement(deep, hit, kWidth, kHeight);
        FrameJob flatten = base;  // the element's flat passes, as the --flat path reads them
        flatten.input = deep;
        flatten.output = flat;
        runFrameJob(flatten);
        FrameJob one = base;
        one.input = flat;
        one.deepInput = deep;
        one.output = (dir / (name + "_one.exr")).string();
        cases.push_back({name + " alone, --flat (today's path)", one, {}, {}});
        merged.deepElements.push_back(deep);
    }
    merged.input = merged.deepElements[0];
    merged.output = (dir / "merged.exr").string();
    cases.push_back({"three elements merged", merged, {}, {}});
    merged.perElementAo = true;
    merged.output = (dir / "per_element.exr").string();
    cases.push_back({"three merged, --per-element-ao", merged, {}, {}});
    merged.perElementAo = false;
    merged.writeIndirect = true;
    merged.bounceSource = "beauty";
    merged.output = (dir / "bounce.exr").string();
    cases.push_back({"three merged, --bounce", merged, {}, {}});
    for (int r = 0; r < runs; ++r)  // interleaved, so drift in the machine's load hits each alike
        for (Case& c : cases) c.wall.push_back(timed(c.job, c.stages));
    std::printf("%dx%d, quality %s, --deep-layers %d, radius 1, falloff none, median of %d runs (end to end)\n", kWidth,
                kHeight, quality.c_str(), layers, runs);
    for (const Case& c : cases) {
        std::printf("%-34s %7.3f s  x ball %.2f  x ground %.2f  (%s)\n", c.label.c_str(), median(c.wall),
                    median(c.wall) / median(cases[0].wall), median(c.wall) / median(cases[2].wall), stageText(c.stages).c_str());
    }
    const Case &ao = cases[3], &bounce = cases[5];
    const auto stage = [](const Case& c, const char* name) { return median(c.stages.at(name)); };
    std::printf("bounce / AO alone (three merged): end to end %.2f, compute %.2f\n", median(bounce.wall) / median(ao.wall),
                stage(bounce, "compute") / stage(ao, "compute"));
    return 0;
}
