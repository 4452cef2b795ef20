// Error of a result against a reference over the pixels a mask selects
// (non-sky pixels): the figures docs/accuracy.md's error report publishes.
#pragma once
#include "base/image.h"

#include <vector>

namespace obscura {

struct ErrorMetrics {
    long long pixels = 0;  // pixels compared
    double mae = 0;        // mean absolute error
    double rmse = 0;       // root mean square error
    double psnr = 0;       // dB, signal peak 1; +inf when identical
    double p99 = 0;        // 99th percentile of the absolute error
    double maxAbs = 0;
};

// Channel `channel` of `result` against channel `refChannel` of `reference` at pixels where
// mask(x, y) holds. Pixels where either value is not finite are skipped.
template <class Mask>
ErrorMetrics compareChannels(ConstPlane result, int channel, ConstPlane reference, int refChannel, Mask&& mask);

ErrorMetrics metricsFromErrors(std::vector<double>& absErrors); // sorts in place

template <class Mask>
ErrorMetrics compareChannels(ConstPlane result, int channel, ConstPlane reference, int refChannel, Mask&& mask) {
    std::vector<double> errors;
    for (int y = 0; y < result.height; ++y)
        for (int x = 0; x < result.width; ++x) {
            if (!mask(x, y)) continue;
            const double a = result.at(x, y)[channel], b = reference.at(x, y)[refChannel];
            if (!(a - a == 0.0 && b - b == 0.0)) continue; // NaN or inf
            errors.push_back(a > b ? a - b : b - a);
        }
    return metricsFromErrors(errors);
}

} // namespace obscura
