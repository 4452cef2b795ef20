#include "core/fit_linear_algebra.h"

#include <algorithm>
#include <cmath>

namespace obscura::fitmath {

// Eigen-decomposition of a symmetric n x n matrix (row-major) by cyclic Jacobi.
// Returns eigenvalues ascending; vectors[k] is the unit eigenvector of values[k].
void symmetricEigen(std::vector<double> a, int n, std::vector<double>& values,
                    std::vector<std::vector<double>>& vectors) {
    std::vector<double> v(n * n, 0.0);
    for (int i = 0; i < n; ++i) v[i * n + i] = 1.0;
    for (int sweep = 0; sweep < 100; ++sweep) {
        double off = 0, total = 0;
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < n; ++j) (i == j ? total : off) += a[i * n + j] * a[i * n + j];
        if (off <= 1e-30 * (total + off)) break;
        for (int p = 0; p < n; ++p)
            for (int q = p + 1; q < n; ++q) {
                const double apq = a[p * n + q];
                if (apq == 0.0) continue;
                const double theta = (a[q * n + q] - a[p * n + p]) / (2.0 * apq);
                const double t = (theta >= 0 ? 1.0 : -1.0) / (std::fabs(theta) + std::sqrt(theta * theta + 1.0));
                const double c = 1.0 / std::sqrt(t * t + 1.0), s = t * c;
                for (int k = 0; k < n; ++k) {  // A <- A J
                    const double akp = a[k * n + p], akq = a[k * n + q];
                    a[k * n + p] = c * akp - s * akq;
                    a[k * n + q] = s * akp + c * akq;
                }
                for (int k = 0; k < n; ++k) {  // A <- J^T A
                    const double apk = a[p * n + k], aqk = a[q * n + k];
                    a[p * n + k] = c * apk - s * aqk;
                    a[q * n + k] = s * apk + c * aqk;
                }
                for (int k = 0; k < n; ++k) {  // V <- V J
                    const double vkp = v[k * n + p], vkq = v[k * n + q];
                    v[k * n + p] = c * vkp - s * vkq;
                    v[k * n + q] = s * vkp + c * vkq;
                }
            }
    }
    std::vector<int> order(n);
    for (int i = 0; i < n; ++i) order[i] = i;
    std::sort(order.begin(), order.end(), [&](int i, int j) { return a[i * n + i] < a[j * n + j]; });
    values.assign(n, 0.0);
    vectors.assign(n, std::vector<double>(n));
    for (int k = 0; k < n; ++k) {
        values[k] = a[order[k] * n + order[k]];
        for (int i = 0; i < n; ++i) vectors[k][i] = v[i * n + order[k]];
    }
}

// Solves A x = b (n x n, row-major) by Gaussian elimination with partial pivoting.
bool solveLinear(std::vector<double> a, std::vector<double> b, int n, std::vector<double>& x) {
    for (int col = 0; col < n; ++col) {
        int pivot = col;
        for (int r = col + 1; r < n; ++r)
            if (std::fabs(a[r * n + col]) > std::fabs(a[pivot * n + col])) pivot = r;
        if (std::fabs(a[pivot * n + col]) < 1e-300) return false;
        for (int k = 0; k < n; ++k) std::swap(a[col * n + k], a[pivot * n + k]);
        std::swap(b[col], b[pivot]);
        for (int r = col + 1; r < n; ++r) {
            const double m = a[r * n + col] / a[col * n + col];
            for (int k = col; k < n; ++k) a[r * n + k] -= m * a[col * n + k];
            b[r] -= m * b[col];
        }
    }
    x.assign(n, 0.0);
    for (int r = n - 1; r >= 0; --r) {
        double s = b[r];
        for (int k = r + 1; k < n; ++k) s -= a[r * n + k] * x[k];
        x[r] = s / a[r * n + r];
    }
    return true;
}

// glm matrices are built from columns; the maths below reads more easily in rows.
glm::dmat3 fromRows(const glm::dvec3& r0, const glm::dvec3& r1, const glm::dvec3& r2) {
    return glm::transpose(glm::dmat3(r0, r1, r2));
}
glm::dvec3 row(const glm::dmat3& m, int i) { return {m[0][i], m[1][i], m[2][i]}; }

// Nearest rotation (polar decomposition by Newton iteration); needs det > 0.
glm::dmat3 nearestRotation(glm::dmat3 m) {
    for (int i = 0; i < 30; ++i) m = 0.5 * (m + glm::transpose(glm::inverse(m)));
    return m;
}

glm::dmat3 rotationFromVector(const glm::dvec3& w) {
    const double theta = glm::length(w);
    const glm::dmat3 k = fromRows({0, -w.z, w.y}, {w.z, 0, -w.x}, {-w.y, w.x, 0});
    if (theta < 1e-12) return glm::dmat3(1.0) + k;
    return glm::dmat3(1.0) + (std::sin(theta) / theta) * k + ((1 - std::cos(theta)) / (theta * theta)) * (k * k);
}

} // namespace obscura::fitmath
