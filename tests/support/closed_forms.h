// Closed forms the analytic tests compare against.
#pragma once
#include "core/settings.h"

#include <algorithm>
#include <cmath>

namespace obscura::test {

// AO of a point on a floor at distance d from an infinite wall (a 90-degree corner), c = d / R.
// Derived by integrating over the cap of directions with w_x > c, which hit the wall at
// distance d / w_x: binary visibility counts them whole, linear falloff by 1 - c / w_x.
inline double cornerAo(Weighting w, Falloff f, double c) {
    c = std::min(std::max(c, 0.0), 1.0);
    const double s = std::sqrt(1 - c * c);
    if (w == Weighting::Uniform) {
        if (f == Falloff::None) return 0.5 * (1 + c);                    // 1 - (1 - c) / 2
        return 1 - 0.5 * ((1 - c) + (c > 0 ? c * std::log(c) : 0.0));   // W = 1 - c / w_x
    }
    const double capCos = M_PI / 4 - 0.5 * (c * s + std::asin(c));       // integral_c^1 sqrt(1-u^2) du
    if (f == Falloff::None) return 1 - (2 / M_PI) * capCos;
    const double capCosOverU = (c > 0 ? std::log((1 + s) / c) : 0.0) - s; // integral_c^1 sqrt(1-u^2)/u du
    return 1 - (2 / M_PI) * (capCos - c * capCosOverU);
}

// Form factor from a point to a parallel a x b rectangle at height h with one corner above it.
inline double cornerRectFormFactor(double a, double b, double h) {
    const double A = a / h, B = b / h, sa = std::sqrt(1 + A * A), sb = std::sqrt(1 + B * B);
    return (A / sa * std::atan(B / sa) + B / sb * std::atan(A / sb)) / (2 * M_PI);
}

// Irradiance at the bottom centre of wellScene(a, h) whose every surface radiates L: pi L less
// what leaves through the opening, four quarter-rectangles at height h.
inline double wellIrradiance(double L, double a, double h) { return M_PI * L * (1.0 - 4.0 * cornerRectFormFactor(a, a, h)); }

} // namespace obscura::test
