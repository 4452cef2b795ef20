#include "shapes.h"

#include <cmath>

namespace reference {
namespace {
constexpr double kPi = 3.14159265358979323846;

unsigned addVertex(Mesh& m, glm::dvec3 p) {
    m.vertices.emplace_back(p);
    return static_cast<unsigned>(m.vertices.size() - 1);
}
} // namespace

void addQuad(Mesh& m, glm::dvec3 p0, glm::dvec3 p1, glm::dvec3 p2, glm::dvec3 p3) {
    const unsigned a = addVertex(m, p0), b = addVertex(m, p1), c = addVertex(m, p2), d = addVertex(m, p3);
    m.triangles.push_back({a, b, c});
    m.triangles.push_back({a, c, d});
}

Mesh groundPlane(double x0, double x1, double y0, double y1, double height, glm::vec3 albedo) {
    Mesh m;
    m.albedo = albedo;
    addQuad(m, {x0, y0, height}, {x1, y0, height}, {x1, y1, height}, {x0, y1, height});
    return m;
}

Mesh box(glm::dvec3 centre, glm::dvec3 half, double yaw, glm::vec3 albedo) {
    Mesh m;
    m.albedo = albedo;
    const double c = std::cos(yaw), s = std::sin(yaw);
    auto corner = [&](int i) {
        const glm::dvec3 l((i & 1 ? 1 : -1) * half.x, (i & 2 ? 1 : -1) * half.y, (i & 4 ? 1 : -1) * half.z);
        return centre + glm::dvec3(c * l.x - s * l.y, s * l.x + c * l.y, l.z);
    };
    // Faces as corner indices (bit 0 = +x, bit 1 = +y, bit 2 = +z), wound outwards.
    const int faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& f : faces) addQuad(m, corner(f[0]), corner(f[1]), corner(f[2]), corner(f[3]));
    return m;
}

Mesh cylinder(glm::dvec3 base, double radius, double height, int sides, glm::vec3 albedo) {
    Mesh m;
    m.albedo = albedo;
    auto rim = [&](int i, double z) {
        const double a = 2 * kPi * i / sides;
        return base + glm::dvec3(radius * std::cos(a), radius * std::sin(a), z);
    };
    const glm::dvec3 top = base + glm::dvec3(0, 0, height);
    for (int i = 0; i < sides; ++i) {
        addQuad(m, rim(i, 0), rim(i + 1, 0), rim(i + 1, height), rim(i, height));
        const unsigned t = addVertex(m, top), a = addVertex(m, rim(i, height)), b = addVertex(m, rim(i + 1, height));
        m.triangles.push_back({t, a, b});
    }
    return m;
}

Mesh polarHeightfield(double cx, double cy, double rMin, double rMax, int rings, int sectors,
                      const std::function<double(double, double)>& height, glm::vec3 albedo) {
    Mesh m;
    m.albedo = albedo;
    auto at = [&](double x, double y) { return glm::dvec3(x, y, height(x, y)); };
    const unsigned centre = addVertex(m, at(cx, cy));
    for (int r = 0; r <= rings; ++r) {
        const double radius = rMin * std::pow(rMax / rMin, double(r) / rings);
        for (int s = 0; s < sectors; ++s) {
            const double a = 2 * kPi * s / sectors;
            addVertex(m, at(cx + radius * std::cos(a), cy + radius * std::sin(a)));
        }
    }
    auto idx = [&](int r, int s) { return 1u + unsigned(r * sectors + (s % sectors)); };
    for (int s = 0; s < sectors; ++s) m.triangles.push_back({centre, idx(0, s), idx(0, s + 1)});
    for (int r = 0; r < rings; ++r)
        for (int s = 0; s < sectors; ++s) {
            m.triangles.push_back({idx(r, s), idx(r + 1, s), idx(r + 1, s + 1)});
            m.triangles.push_back({idx(r, s), idx(r + 1, s + 1), idx(r, s + 1)});
        }
    return m;
}

} // namespace reference
