// Deep elements merged against the --flat deep path (docs/deep.md, issue 28's target): three
// 1024 x 576 deep elements (tests/support/deep_elements.h: a ball, a tree, the ground) are
// generated, then in the same process, interleaved, timed end to end (read, merge, HBAO, write):
//   baseline: the ball's deep file with --flat (its flattened image, written once beforehand), as
//             obscura ran deep input before deep elements;
//   merged:   the three elements, merged and flattened, with the merge's layers;
//   merged + per-element AO: the same with --per-element-ao (three more HBAO runs).
// Same settings and --deep-layers for all. Not a ctest.
// Usage: bench_deep [runs (5)] [deep layers (4)] [quality (medium)] [work dir]
#include "io/frame_job.h"
#include "support/deep_elements.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
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

double timed(const FrameJob& job) {
    const auto t0 = std::chrono::steady_clock::now();
    runFrameJob(job);
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

} // namespace

int main(int argc, char** argv) {
    const int runs = argc > 1 ? std::max(1, std::atoi(argv[1])) : 5;
    const int layers = argc > 2 ? std::atoi(argv[2]) : 4;
    const std::string quality = argc > 3 ? argv[3] : "medium";
    const fs::path dir = argc > 4 ? fs::path(argv[4]) : fs::temp_directory_path() / "obscura_bench_deep";
    fs::create_directories(dir);
    const std::string ball = (dir / "ball.exr").string(), tree = (dir / "tree.exr").string(),
                      ground = (dir / "ground.exr").string(), flat = (dir / "ball_flat.exr").string();
    test::writeDeepElement(ball, test::deepBall, kWidth, kHeight);
    test::writeDeepElement(tree, test::deepTree, kWidth, kHeight);
    test::writeDeepElement(ground, test::deepGround, kWidth, kHeight);

    FrameJob base;
    base.camera.fovDeg = test::kDeepFovDeg;
    if (!applyQualityPreset(quality, base.settings)) return std::fprintf(stderr, "unknown quality %s\n", quality.c_str()), 2;
    base.settings.deepLayers = layers;
    base.settings.radius = 1.0f;
    FrameJob flatten = base;  // the ball's flat passes, as the --flat path reads them
    flatten.input = ball;
    flatten.output = flat;
    runFrameJob(flatten);
    FrameJob one = base;
    one.input = flat;
    one.deepInput = ball;
    one.output = (dir / "one.exr").string();
    FrameJob merged = base;
    merged.input = ball;
    merged.deepElements = {ball, tree, ground};
    merged.output = (dir / "merged.exr").string();
    FrameJob perElement = merged;
    perElement.perElementAo = true;
    perElement.output = (dir / "per_element.exr").string();

    std::vector<double> tOne, tMerged, tPer;
    for (int r = 0; r < runs; ++r) {  // interleaved, so drift in the machine's load hits each alike
        tOne.push_back(timed(one));
        tMerged.push_back(timed(merged));
        tPer.push_back(timed(perElement));
    }
    const double b = median(tOne);
    std::printf("%dx%d, quality %s, --deep-layers %d, radius 1, median of %d runs (end to end: read, HBAO, write)\n",
                kWidth, kHeight, quality.c_str(), layers, runs);
    std::printf("%-44s %8.3f s  1.00x\n", "one element, --flat (baseline)", b);
    std::printf("%-44s %8.3f s  %.2fx\n", "three elements merged", median(tMerged), median(tMerged) / b);
    std::printf("%-44s %8.3f s  %.2fx\n", "three elements merged, --per-element-ao", median(tPer), median(tPer) / b);
    return 0;
}
