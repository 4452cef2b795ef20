// The small dense linear algebra the camera fit (camera_fit.cpp) needs: a symmetric eigen
// solver, a linear solve, rotations, and the normalising similarity of a point set.
#pragma once
#include <glm/glm.hpp>

#include <cmath>
#include <cstddef>
#include <vector>

namespace obscura::fitmath {

// Eigen-decomposition of a symmetric n x n matrix (row-major) by cyclic Jacobi.
// Returns eigenvalues ascending; vectors[k] is the unit eigenvector of values[k].
void symmetricEigen(std::vector<double> a, int n, std::vector<double>& values,
                    std::vector<std::vector<double>>& vectors);
// Solves the n x n system a x = b (row-major) by Gaussian elimination with partial
// pivoting; false when it is singular.
bool solveLinear(std::vector<double> a, std::vector<double> b, int n, std::vector<double>& x);

// glm matrices are built from columns; the fit reads more easily in rows.
glm::dmat3 fromRows(const glm::dvec3& r0, const glm::dvec3& r1, const glm::dvec3& r2);
glm::dvec3 row(const glm::dmat3& m, int i);
// Nearest rotation (polar decomposition by Newton iteration); needs det > 0.
glm::dmat3 nearestRotation(glm::dmat3 m);
// The rotation of axis-angle vector w (Rodrigues).
glm::dmat3 rotationFromVector(const glm::dvec3& w);

// Similarity that moves points to their centroid and scales them to a mean distance sqrt(dim).
struct Normaliser {
    glm::dvec3 centre{0.0};
    double scale = 1.0;
};
template <class GetPoint>
Normaliser normaliser(std::size_t count, int dim, GetPoint get) {
    Normaliser n;
    for (std::size_t i = 0; i < count; ++i) n.centre += get(i);
    n.centre /= double(count);
    double meanDistance = 0;
    for (std::size_t i = 0; i < count; ++i) meanDistance += glm::length(get(i) - n.centre);
    meanDistance /= double(count);
    n.scale = meanDistance > 0 ? std::sqrt(double(dim)) / meanDistance : 1.0;
    return n;
}

} // namespace obscura::fitmath
