#include "render.h"

#include <algorithm>
#include <atomic>
#include <thread>

namespace reference {

void forEachRow(int height, int threads, const std::function<void(int y)>& row) {
    std::atomic<int> nextRow{0};
    auto work = [&] {
        for (int y; (y = nextRow.fetch_add(1)) < height;) row(y);
    };
    const int n = threads > 0 ? threads : int(std::max(1u, std::thread::hardware_concurrency()));
    std::vector<std::thread> pool;
    for (int i = 1; i < n; ++i) pool.emplace_back(work);
    work();
    for (std::thread& t : pool) t.join();
}

Frame render(const Integrator& integrator, const RenderSettings& settings) {
    Frame f;
    f.width = settings.width + 2 * settings.overscan;
    f.height = settings.height + 2 * settings.overscan;
    f.originX = f.originY = -settings.overscan;
    f.pixels.resize(size_t(f.width) * f.height);
    forEachRow(f.height, settings.threads, [&](int y) {
        for (int x = 0; x < f.width; ++x) f.pixels[size_t(y) * f.width + x] = integrator.shade(x + f.originX, y + f.originY);
    });
    return f;
}

Convergence summarise(const Frame& frame) {
    Convergence c;
    for (const PixelResult& p : frame.pixels) {
        if (p.sky) continue;
        ++c.surfacePixels;
        for (int l = 0; l < kAoLayers; ++l) {
            c.aoMean[l] += p.ao[l];
            c.aoStdErrMean[l] += p.aoStdErr[l];
            c.aoStdErrMax[l] = std::max(c.aoStdErrMax[l], p.aoStdErr[l]);
        }
        auto luminance = [](const glm::vec3& v) { return 0.2126 * v.r + 0.7152 * v.g + 0.0722 * v.b; };
        c.indirectMean += luminance(p.indirect);
        c.giNearMean += luminance(p.giNear);
        c.giFullMean += luminance(p.giFull);
        c.directionalMean += luminance(p.directionalOcclusion);
        c.indirectStdErrMean += p.indirectStdErr;
        c.indirectStdErrMax = std::max(c.indirectStdErrMax, p.indirectStdErr);
    }
    if (c.surfacePixels > 0) {
        const double n = double(c.surfacePixels);
        for (int l = 0; l < kAoLayers; ++l) c.aoMean[l] /= n, c.aoStdErrMean[l] /= n;
        c.indirectMean /= n;
        c.giNearMean /= n;
        c.giFullMean /= n;
        c.directionalMean /= n;
        c.indirectStdErrMean /= n;
    }
    return c;
}

} // namespace reference
