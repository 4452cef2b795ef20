#include "metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace obscura {

ErrorMetrics metricsFromErrors(std::vector<double>& e) {
    ErrorMetrics m;
    m.pixels = (long long)e.size();
    if (e.empty()) return m;
    double sum = 0, sum2 = 0;
    for (double v : e) {
        sum += v;
        sum2 += v * v;
    }
    m.mae = sum / e.size();
    m.rmse = std::sqrt(sum2 / e.size());
    m.psnr = m.rmse > 0 ? 20.0 * std::log10(1.0 / m.rmse) : std::numeric_limits<double>::infinity();
    // Nearest-rank percentile: the smallest error that at least 99% of pixels do not exceed.
    const size_t rank = (size_t)std::ceil(0.99 * e.size());
    std::nth_element(e.begin(), e.begin() + (rank - 1), e.end());
    m.p99 = e[rank - 1];
    m.maxAbs = *std::max_element(e.begin(), e.end());
    return m;
}

} // namespace obscura
