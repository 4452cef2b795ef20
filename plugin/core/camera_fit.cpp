// Camera from pixel <-> world correspondences.
// Work is done in the OpenCV camera frame (x right, y down, z forward), where the
// pixel model is px = cx + f X/Z, py = cy + f a Y/Z (a = pixel aspect), and
// converted to the OpenGL frame (y, z negated) only at the end.
// Pipeline: linear initial guesses (DLT for 3D scenes, homography or affine for
// planar ones) -> Levenberg-Marquardt on the constrained model -> reject outliers
// by residual, refit -> pick perspective or orthographic by RMS.
#include "camera_fit.h"

#include "base/error.h"
#include "core/fit_linear_algebra.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <vector>

namespace obscura {
namespace {

using namespace fitmath;

struct Sample {
    glm::dvec3 world;
    glm::dvec2 pixel;
};

// ---------------------------------------------------------------- the camera model

struct Model {
    bool ortho = false;
    double f = 0;        // focal length in pixels, or pixels per world unit
    double cx = 0, cy = 0, aspect = 1;
    glm::dmat3 R{1.0};   // world -> OpenCV camera
    glm::dvec3 t{0.0};

    glm::dvec2 project(const glm::dvec3& world) const {
        const glm::dvec3 c = R * world + t;
        if (ortho) return {cx + f * c.x, cy + f * aspect * c.y};
        return {cx + f * c.x / c.z, cy + f * aspect * c.y / c.z};
    }
};

double residual(const Model& m, const Sample& s) { return glm::length(m.project(s.world) - s.pixel); }

// Parameters refined by Levenberg-Marquardt: f, rotation increment (3), t (3), cx, cy.
enum { kF, kWx, kWy, kWz, kTx, kTy, kTz, kCx, kCy, kParams };

Model applyStep(const Model& m, const double* p) {
    Model out = m;
    out.f = m.f + p[kF];
    out.R = rotationFromVector({p[kWx], p[kWy], p[kWz]}) * m.R;
    out.t = m.t + glm::dvec3(p[kTx], p[kTy], p[kTz]);
    out.cx = m.cx + p[kCx];
    out.cy = m.cy + p[kCy];
    return out;
}

double sumSquares(const Model& m, const std::vector<Sample>& samples) {
    double sum = 0;
    for (const Sample& s : samples) {
        if (!m.ortho && glm::dot(row(m.R, 2), s.world) + m.t.z <= 0) return INFINITY;  // behind the eye
        const glm::dvec2 d = m.project(s.world) - s.pixel;
        sum += glm::dot(d, d);
    }
    return sum;
}

Model refine(Model m, const std::vector<Sample>& samples, bool freePrincipalPoint, double sceneScale) {
    std::vector<int> free = {kF, kWx, kWy, kWz, kTx, kTy};
    if (!m.ortho) free.push_back(kTz);
    if (freePrincipalPoint) {
        free.push_back(kCx);
        free.push_back(kCy);
    }
    const int n = (int)free.size();
    double cost = sumSquares(m, samples);
    if (!std::isfinite(cost)) return m;
    double lambda = 1e-3;
    for (int iter = 0; iter < 100; ++iter) {
        // Central-difference Jacobian: cheap at a few thousand samples and free of algebra slips.
        std::vector<double> jtj(n * n, 0.0), jtr(n, 0.0);
        std::vector<glm::dvec2> columns(n);
        std::vector<double> steps(n);
        std::vector<Model> plus(n), minus(n);
        for (int k = 0; k < n; ++k) {
            const int p = free[k];
            steps[k] = p == kF ? 1e-6 * m.f : (p >= kTx && p <= kTz) ? 1e-7 * sceneScale : p >= kCx ? 1e-4 : 1e-7;
            double step[kParams] = {};
            step[p] = steps[k];
            plus[k] = applyStep(m, step);
            step[p] = -steps[k];
            minus[k] = applyStep(m, step);
        }
        for (const Sample& s : samples) {
            const glm::dvec2 r = m.project(s.world) - s.pixel;
            for (int k = 0; k < n; ++k)
                columns[k] = (plus[k].project(s.world) - minus[k].project(s.world)) / (2 * steps[k]);
            for (int i = 0; i < n; ++i) {
                jtr[i] += glm::dot(columns[i], r);
                for (int j = 0; j < n; ++j) jtj[i * n + j] += glm::dot(columns[i], columns[j]);
            }
        }
        bool improved = false;
        for (int attempt = 0; attempt < 10 && !improved; ++attempt) {
            std::vector<double> a = jtj, b(n), x;
            for (int i = 0; i < n; ++i) {
                a[i * n + i] += lambda * (jtj[i * n + i] + 1e-12);
                b[i] = -jtr[i];
            }
            if (!solveLinear(a, b, n, x)) { lambda *= 10; continue; }
            double step[kParams] = {};
            for (int k = 0; k < n; ++k) step[free[k]] = x[k];
            Model candidate = applyStep(m, step);
            candidate.R = nearestRotation(candidate.R);
            const double candidateCost = sumSquares(candidate, samples);
            if (candidateCost < cost) {
                const double gain = (cost - candidateCost) / cost;
                m = candidate;
                cost = candidateCost;
                lambda = std::max(lambda * 0.1, 1e-12);
                improved = true;
                if (gain < 1e-12) return m;
            } else {
                lambda *= 10;
            }
        }
        if (!improved) break;
    }
    return m;
}

// ---------------------------------------------------------------- initial guesses

// Direct linear transform for a general 3D scene: P (3x4) with pixel ~ P [X; 1],
// then split into f, R, t. Principal-point and skew terms found by the DLT are
// dropped; refinement restores the constrained model.
std::optional<Model> initPerspectiveDLT(const std::vector<Sample>& samples, const Model& base) {
    const Normaliser nw = normaliser(samples.size(), 3, [&](std::size_t i) { return samples[i].world; });
    const Normaliser np = normaliser(samples.size(), 2, [&](std::size_t i) {
        return glm::dvec3(samples[i].pixel - glm::dvec2(base.cx, base.cy), 0.0);
    });
    std::vector<double> ata(144, 0.0);
    for (const Sample& s : samples) {
        const glm::dvec3 X = (s.world - nw.centre) * nw.scale;
        const glm::dvec2 uv = (s.pixel - glm::dvec2(base.cx, base.cy) - glm::dvec2(np.centre)) * np.scale;
        const double h[4] = {X.x, X.y, X.z, 1.0};
        double r1[12] = {}, r2[12] = {};
        for (int k = 0; k < 4; ++k) {
            r1[k] = h[k];
            r1[8 + k] = -uv.x * h[k];
            r2[4 + k] = h[k];
            r2[8 + k] = -uv.y * h[k];
        }
        for (int i = 0; i < 12; ++i)
            for (int j = 0; j < 12; ++j) ata[i * 12 + j] += r1[i] * r1[j] + r2[i] * r2[j];
    }
    std::vector<double> values;
    std::vector<std::vector<double>> vectors;
    symmetricEigen(ata, 12, values, vectors);
    if (values[1] <= 1e-9 * values[11]) return std::nullopt;  // a family of solutions: planar or collinear
    // Undo the normalisations: P = T2^-1 Pn T3 (rows of Pn: vectors[0] in blocks of 4).
    double P[3][4];
    const double* pn = vectors[0].data();
    for (int r = 0; r < 3; ++r) {
        double rowN[4];
        for (int k = 0; k < 4; ++k) rowN[k] = pn[r * 4 + k];
        // Pn T3: T3 = [s I, -s c; 0 1]
        for (int k = 0; k < 3; ++k) P[r][k] = rowN[k] * nw.scale;
        P[r][3] = rowN[3] - nw.scale * (rowN[0] * nw.centre.x + rowN[1] * nw.centre.y + rowN[2] * nw.centre.z);
    }
    // T2^-1 = [1/s I, c; 0 1]: row0 = row0/s + c.x row2, row1 = row1/s + c.y row2.
    for (int k = 0; k < 4; ++k) {
        P[0][k] = P[0][k] / np.scale + np.centre.x * P[2][k];
        P[1][k] = P[1][k] / np.scale + np.centre.y * P[2][k];
    }
    glm::dvec3 m1(P[0][0], P[0][1], P[0][2]), m2(P[1][0], P[1][1], P[1][2]), m3(P[2][0], P[2][1], P[2][2]);
    double norm3 = glm::length(m3);
    if (norm3 <= 0) return std::nullopt;
    double sign = (glm::dot(m3, nw.centre) + P[2][3]) > 0 ? 1.0 : -1.0;  // scene in front of the eye
    const double k = sign / norm3;
    m1 *= k, m2 *= k, m3 *= k;
    const double p14 = P[0][3] * k, p24 = P[1][3] * k, p34 = P[2][3] * k;
    const double u0 = glm::dot(m1, m3), v0 = glm::dot(m2, m3);  // principal-point offsets
    const glm::dvec3 a1 = m1 - u0 * m3, a2 = m2 - v0 * m3;
    Model m = base;
    m.f = 0.5 * (glm::length(a1) + glm::length(a2) / base.aspect);
    glm::dmat3 R = fromRows(glm::normalize(a1), glm::normalize(a2), m3);
    if (glm::determinant(R) <= 0 || !(m.f > 0)) return std::nullopt;  // a mirror image: not a camera
    m.R = nearestRotation(R);
    m.t = {(p14 - u0 * p34) / m.f, (p24 - v0 * p34) / (m.f * base.aspect), p34};
    return m;
}

// Orthonormal basis of the dominant plane of the samples: e0, e1 span it, e2 = e0 x e1.
struct PlaneFrame {
    glm::dvec3 centre, e0, e1, e2;
    double thickness2, extent2;  // smallest / largest variance
};
PlaneFrame planeFrame(const std::vector<Sample>& samples) {
    PlaneFrame pf;
    pf.centre = glm::dvec3(0.0);
    for (const Sample& s : samples) pf.centre += s.world;
    pf.centre /= double(samples.size());
    std::vector<double> cov(9, 0.0);
    for (const Sample& s : samples) {
        const glm::dvec3 d = s.world - pf.centre;
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) cov[i * 3 + j] += d[i] * d[j] / double(samples.size());
    }
    std::vector<double> values;
    std::vector<std::vector<double>> v;
    symmetricEigen(cov, 3, values, v);
    pf.e0 = {v[2][0], v[2][1], v[2][2]};
    pf.e1 = {v[1][0], v[1][1], v[1][2]};
    pf.e2 = glm::cross(pf.e0, pf.e1);
    pf.thickness2 = values[0];
    pf.extent2 = values[2];
    return pf;
}

// Homography from the dominant plane to the image; the principal point is known,
// so orthogonality of the plane's axes gives f (fails for a fronto-parallel plane,
// where f and distance trade off exactly).
std::optional<Model> initPerspectivePlanar(const std::vector<Sample>& samples, const PlaneFrame& pf,
                                           const Model& base) {
    auto planeCoords = [&](std::size_t i) {
        const glm::dvec3 d = samples[i].world - pf.centre;
        return glm::dvec3(glm::dot(d, pf.e0), glm::dot(d, pf.e1), 0.0);
    };
    auto imageCoords = [&](std::size_t i) {  // centred, aspect removed: K becomes diag(f, f, 1)
        const glm::dvec2 d = samples[i].pixel - glm::dvec2(base.cx, base.cy);
        return glm::dvec3(d.x, d.y / base.aspect, 0.0);
    };
    const Normaliser na = normaliser(samples.size(), 2, planeCoords);
    const Normaliser nb = normaliser(samples.size(), 2, imageCoords);
    std::vector<double> ata(81, 0.0);
    for (std::size_t i = 0; i < samples.size(); ++i) {
        const glm::dvec3 a = (planeCoords(i) - na.centre) * na.scale;
        const glm::dvec3 b = (imageCoords(i) - nb.centre) * nb.scale;
        const double h[3] = {a.x, a.y, 1.0};
        double r1[9] = {}, r2[9] = {};
        for (int k = 0; k < 3; ++k) {
            r1[k] = h[k];
            r1[6 + k] = -b.x * h[k];
            r2[3 + k] = h[k];
            r2[6 + k] = -b.y * h[k];
        }
        for (int r = 0; r < 9; ++r)
            for (int c = 0; c < 9; ++c) ata[r * 9 + c] += r1[r] * r1[c] + r2[r] * r2[c];
    }
    std::vector<double> values;
    std::vector<std::vector<double>> v;
    symmetricEigen(ata, 9, values, v);
    // H = Tb^-1 Hn Ta, with T = [s 0 -s cx; 0 s -s cy; 0 0 1].
    const glm::dmat3 hn = fromRows({v[0][0], v[0][1], v[0][2]}, {v[0][3], v[0][4], v[0][5]}, {v[0][6], v[0][7], v[0][8]});
    const glm::dmat3 ta = fromRows({na.scale, 0, -na.scale * na.centre.x}, {0, na.scale, -na.scale * na.centre.y}, {0, 0, 1});
    const glm::dmat3 tbInv = fromRows({1 / nb.scale, 0, nb.centre.x}, {0, 1 / nb.scale, nb.centre.y}, {0, 0, 1});
    const glm::dmat3 H = tbInv * hn * ta;
    const glm::dvec3 h1 = H[0], h2 = H[1], h3 = H[2];  // columns
    // (K^-1 h1).(K^-1 h2) = 0 and |K^-1 h1| = |K^-1 h2|, linear in w = 1/f^2.
    const double a0 = h1.x * h2.x + h1.y * h2.y, b0 = h1.z * h2.z;
    const double a1 = h1.x * h1.x + h1.y * h1.y - h2.x * h2.x - h2.y * h2.y, b1 = h1.z * h1.z - h2.z * h2.z;
    const double w = -(a0 * b0 + a1 * b1) / (a0 * a0 + a1 * a1);
    if (!(w > 0) || !std::isfinite(w)) return std::nullopt;
    Model m = base;
    m.f = 1.0 / std::sqrt(w);
    const glm::dvec3 kInv(1 / m.f, 1 / m.f, 1.0);
    glm::dvec3 g1 = h1 * kInv, g2 = h2 * kInv, g3 = h3 * kInv;
    double lambda = 2.0 / (glm::length(g1) + glm::length(g2));
    if (g3.z < 0) lambda = -lambda;  // the plane's centre is in front of the eye
    const glm::dvec3 r0 = lambda * g1, r1 = lambda * g2, r2 = glm::cross(r0, r1);
    // R [e0 e1 e2] = [r0 r1 r2]  =>  R = [r0 r1 r2] [e0 e1 e2]^T
    const glm::dmat3 image(r0, r1, r2), basis(pf.e0, pf.e1, pf.e2);
    m.R = nearestRotation(image * glm::transpose(basis));
    m.t = lambda * g3 - m.R * pf.centre;
    return m;
}

// Orthographic, general 3D scene: the affine map pixel = A X + b fixes s and two rows of R.
std::optional<Model> initOrthoAffine(const std::vector<Sample>& samples, const PlaneFrame& pf, const Model& base) {
    std::vector<double> ata(16, 0.0), atu(4, 0.0), atv(4, 0.0);
    for (const Sample& s : samples) {
        const glm::dvec3 d = s.world - pf.centre;
        const double h[4] = {d.x, d.y, d.z, 1.0};
        for (int i = 0; i < 4; ++i) {
            atu[i] += h[i] * (s.pixel.x - base.cx);
            atv[i] += h[i] * (s.pixel.y - base.cy);
            for (int j = 0; j < 4; ++j) ata[i * 4 + j] += h[i] * h[j];
        }
    }
    std::vector<double> xu, xv;
    if (!solveLinear(ata, atu, 4, xu) || !solveLinear(ata, atv, 4, xv)) return std::nullopt;
    const glm::dvec3 a1(xu[0], xu[1], xu[2]), a2(xv[0], xv[1], xv[2]);
    if (glm::length(a1) <= 0 || glm::length(a2) <= 0) return std::nullopt;
    Model m = base;
    m.ortho = true;
    m.f = 0.5 * (glm::length(a1) + glm::length(a2) / base.aspect);
    const glm::dvec3 r0 = glm::normalize(a1), r1 = glm::normalize(a2);
    m.R = nearestRotation(fromRows(r0, r1, glm::cross(r0, r1)));
    // px - cx = s (r0.(X - c) + r0.c + tx): the constant term is s (r0.c + tx).
    m.t = {xu[3] / m.f - glm::dot(row(m.R, 0), pf.centre),
           xv[3] / (m.f * base.aspect) - glm::dot(row(m.R, 1), pf.centre), 0.0};
    return m;
}

// Orthographic, planar scene: the 2D affine map gives the rows of sR inside the
// plane; their components along the normal (alpha, beta) follow from orthogonality
// and equal length: (alpha + i beta)^2 = |q1|^2 - |q0|^2 - 2i q0.q1. The sign is the
// classic reversal ambiguity of a planar orthographic view.
std::optional<Model> initOrthoPlanar(const std::vector<Sample>& samples, const PlaneFrame& pf, const Model& base) {
    std::vector<double> ata(9, 0.0), atu(3, 0.0), atv(3, 0.0);
    for (const Sample& s : samples) {
        const glm::dvec3 d = s.world - pf.centre;
        const double h[3] = {glm::dot(d, pf.e0), glm::dot(d, pf.e1), 1.0};
        for (int i = 0; i < 3; ++i) {
            atu[i] += h[i] * (s.pixel.x - base.cx);
            atv[i] += h[i] * (s.pixel.y - base.cy) / base.aspect;
            for (int j = 0; j < 3; ++j) ata[i * 3 + j] += h[i] * h[j];
        }
    }
    std::vector<double> xu, xv;
    if (!solveLinear(ata, atu, 3, xu) || !solveLinear(ata, atv, 3, xv)) return std::nullopt;
    const glm::dvec2 q0(xu[0], xu[1]), q1(xv[0], xv[1]);
    const double re = glm::dot(q1, q1) - glm::dot(q0, q0), im = -2.0 * glm::dot(q0, q1);
    const double mod = std::sqrt(re * re + im * im);
    const double alpha = std::sqrt(std::max(0.0, 0.5 * (mod + re)));
    const double beta = (im >= 0 ? 1.0 : -1.0) * std::sqrt(std::max(0.0, 0.5 * (mod - re)));
    const glm::dvec3 s0 = q0.x * pf.e0 + q0.y * pf.e1 + alpha * pf.e2;
    const glm::dvec3 s1 = q1.x * pf.e0 + q1.y * pf.e1 + beta * pf.e2;
    Model m = base;
    m.ortho = true;
    m.f = 0.5 * (glm::length(s0) + glm::length(s1));
    if (!(m.f > 0)) return std::nullopt;
    const glm::dvec3 r0 = glm::normalize(s0), r1 = glm::normalize(s1);
    m.R = nearestRotation(fromRows(r0, r1, glm::cross(r0, r1)));
    m.t = {xu[2] / m.f - glm::dot(row(m.R, 0), pf.centre), xv[2] / m.f - glm::dot(row(m.R, 1), pf.centre), 0.0};
    return m;
}

// ---------------------------------------------------------------- robust fitting

struct FitResult {
    Model model;
    double rms = INFINITY;
    double inlierFraction = 0;
};

double median(std::vector<double> v) {
    if (v.empty()) return 0;
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    return v[v.size() / 2];
}

// Refine, drop samples far off the model (blended silhouette and sky pixels), refine again.
FitResult robustFit(Model m, const std::vector<Sample>& samples, bool freePrincipalPoint, double sceneScale) {
    std::vector<Sample> inliers = samples;
    FitResult best;
    for (int round = 0; round < 4; ++round) {
        m = refine(m, inliers, freePrincipalPoint, sceneScale);
        std::vector<double> r(samples.size());
        for (std::size_t i = 0; i < samples.size(); ++i) r[i] = residual(m, samples[i]);
        const double threshold = std::max(0.25, 5.0 * 1.4826 * median(r));
        inliers.clear();
        double sum = 0;
        for (std::size_t i = 0; i < samples.size(); ++i)
            if (r[i] < threshold) {
                inliers.push_back(samples[i]);
                sum += r[i] * r[i];
            }
        if (inliers.size() < 8) break;
        best.model = m;
        best.rms = std::sqrt(sum / double(inliers.size()));
        best.inlierFraction = double(inliers.size()) / double(samples.size());
    }
    return best;
}

bool validPosition(const float* p) {
    for (int k = 0; k < 3; ++k)
        if (!std::isfinite(p[k]) || std::fabs(p[k]) >= 1e9f) return false;
    return p[0] != 0.0f || p[1] != 0.0f || p[2] != 0.0f;
}

// Up to maxPoints valid samples spread evenly over the plane.
std::vector<Sample> gatherSamples(ConstPlane position, Box2i dataWindow, int maxPoints) {
    std::vector<Sample> all;
    if (!position.valid() || position.channels < 3) return all;
    const int w = std::min(position.width, dataWindow.width()), h = std::min(position.height, dataWindow.height());
    if (w <= 0 || h <= 0) return all;
    // Over-sample the grid 4x: sky may cover much of the frame.
    const double cells = double(w) * h / (4.0 * std::max(1, maxPoints));
    const int stride = std::max(1, (int)std::floor(std::sqrt(cells)));
    for (int y = stride / 2; y < h; y += stride)
        for (int x = stride / 2; x < w; x += stride) {
            const float* p = position.at(x, y);
            if (validPosition(p))
                all.push_back({glm::dvec3(p[0], p[1], p[2]),
                               glm::dvec2(dataWindow.x0 + x + 0.5, dataWindow.y0 + y + 0.5)});
        }
    if ((int)all.size() <= maxPoints) return all;
    std::vector<Sample> picked;
    picked.reserve(maxPoints);
    for (int i = 0; i < maxPoints; ++i) picked.push_back(all[(std::size_t)((double)i * all.size() / maxPoints)]);
    return picked;
}

Camera toCamera(const Model& m, const std::vector<Sample>& samples, double sceneScale) {
    Model model = m;
    if (model.ortho) {  // place the eye one scene extent in front of the nearest sample
        double nearest = INFINITY;
        for (const Sample& s : samples) nearest = std::min(nearest, glm::dot(row(model.R, 2), s.world));
        model.t.z = sceneScale - nearest;
    }
    Camera c;
    c.projection = model.ortho ? Projection::Orthographic : Projection::Perspective;
    c.fx = model.f;
    c.fy = model.f * model.aspect;
    c.cx = model.cx;
    c.cy = model.cy;
    // OpenCV -> OpenGL camera frame: negate y and z.
    const glm::dmat3 flip = fromRows({1, 0, 0}, {0, -1, 0}, {0, 0, -1});
    glm::dmat4 worldToCamera(flip * model.R);
    worldToCamera[3] = glm::dvec4(flip * model.t, 1.0);
    c.cameraToWorld = glm::inverse(worldToCamera);
    c.hasPose = true;
    return c;
}

std::string describe(const FitResult& r, std::size_t samples) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "%s, rms %.3g px over %.0f%% of %zu samples",
                  r.model.ortho ? "orthographic" : "perspective", r.rms, 100.0 * r.inlierFraction, samples);
    return buf;
}

} // namespace

Camera fitCameraFromPosition(ConstPlane position, Box2i dataWindow, Box2i display, double pixelAspect,
                             const FitOptions& options) {
    const std::vector<Sample> samples = gatherSamples(position, dataWindow, options.maxPoints);
    if (samples.size() < 32)
        throw Error("cannot fit a camera to the position pass: only " + std::to_string(samples.size()) +
                    " valid pixels (need 32)");
    const PlaneFrame pf = planeFrame(samples);
    if (!(pf.extent2 > 0) || pf.extent2 < 1e-20)
        throw Error("cannot fit a camera to the position pass: all positions are the same point");
    const double sceneScale = std::sqrt(pf.extent2);

    Model base;
    base.cx = 0.5 * (display.x0 + display.x1);
    base.cy = 0.5 * (display.y0 + display.y1);
    base.aspect = pixelAspect > 0 ? pixelAspect : 1.0;

    std::vector<Model> starts;
    if (auto m = initPerspectiveDLT(samples, base)) starts.push_back(*m);
    if (auto m = initPerspectivePlanar(samples, pf, base)) starts.push_back(*m);
    const bool planar = pf.thickness2 < 1e-10 * pf.extent2;
    if (auto m = planar ? initOrthoPlanar(samples, pf, base) : initOrthoAffine(samples, pf, base)) starts.push_back(*m);

    FitResult bestPerspective, bestOrtho;
    for (const Model& start : starts) {
        FitResult r = robustFit(start, samples, false, sceneScale);
        // A shifted lens moves the principal point; free it only when needed (and seen in 3D).
        if (r.rms > 0.5 * options.maxResidualPx && !planar) {
            FitResult shifted = robustFit(r.model, samples, true, sceneScale);
            if (shifted.rms < r.rms) r = shifted;
        }
        FitResult& best = start.ortho ? bestOrtho : bestPerspective;
        if (r.rms < best.rms) best = r;
    }
    // Perspective with a huge focal length tends to orthographic and can beat it by
    // rounding noise; only a clear improvement counts as perspective.
    const FitResult& best =
        bestOrtho.rms <= 1.01 * bestPerspective.rms + 1e-4 ? bestOrtho : bestPerspective;
    if (!std::isfinite(best.rms))
        throw Error("cannot fit a camera to the position pass: the samples are degenerate (collinear or a plane seen edge-on)");
    if (best.rms > options.maxResidualPx || best.inlierFraction < options.minInlierFraction) {
        char buf[256];
        std::snprintf(buf, sizeof buf,
                      "camera fit from the position pass is poor (best: %s; limit %.3g px, %.0f%%): "
                      "give --fov-deg/--ortho-width and --camera-to-world, or a JSON sidecar",
                      describe(best, samples.size()).c_str(), options.maxResidualPx, 100.0 * options.minInlierFraction);
        throw Error(buf);
    }
    Camera c = toCamera(best.model, samples, sceneScale);
    c.fitResidualPx = best.rms;
    c.source = "fit:position (" + describe(best, samples.size()) + ")";
    return c;
}

double reprojectionRmsPx(const Camera& camera, ConstPlane position, Box2i dataWindow, int maxPoints) {
    const std::vector<Sample> samples = gatherSamples(position, dataWindow, maxPoints);
    if (samples.empty()) return -1;
    const glm::dmat4 worldToCamera = camera.worldToCamera();
    std::vector<double> r2;
    r2.reserve(samples.size());
    for (const Sample& s : samples) {
        const glm::dvec3 p(worldToCamera * glm::dvec4(s.world, 1.0));
        if (camera.projection == Projection::Perspective && p.z >= 0) {
            r2.push_back(INFINITY);  // behind the eye
            continue;
        }
        const glm::dvec3 q = camera.project(p);
        const glm::dvec2 d = glm::dvec2(q) - s.pixel;
        r2.push_back(glm::dot(d, d));
    }
    std::sort(r2.begin(), r2.end());
    const std::size_t kept = std::max<std::size_t>(1, r2.size() * 9 / 10);
    double sum = 0;
    for (std::size_t i = 0; i < kept; ++i) sum += r2[i];
    return std::sqrt(sum / double(kept));
}

} // namespace obscura
