// Triangle-mesh builders for the procedural scenes.
#pragma once
#include "scene.h"

#include <functional>

namespace reference {

// Quad p0 p1 p2 p3 (in order around its edge) as two triangles.
void addQuad(Mesh& m, glm::dvec3 p0, glm::dvec3 p1, glm::dvec3 p2, glm::dvec3 p3);
// Axis-aligned rectangle in the plane z = height, [x0, x1] x [y0, y1].
Mesh groundPlane(double x0, double x1, double y0, double y1, double height, glm::vec3 albedo);
// Box around `centre` with half extents `half`, turned by `yaw` radians about +Z.
Mesh box(glm::dvec3 centre, glm::dvec3 half, double yaw, glm::vec3 albedo);
// Closed prism (a faceted cylinder) standing on `base`, axis +Z.
Mesh cylinder(glm::dvec3 base, double radius, double height, int sides, glm::vec3 albedo);
// Heightfield z = height(x, y) on a polar grid around (cx, cy): rings spaced
// geometrically from rMin to rMax, so triangles stay small near the centre and
// large far away (one mesh spans centimetres to kilometres).
Mesh polarHeightfield(double cx, double cy, double rMin, double rMax, int rings, int sectors,
                      const std::function<double(double, double)>& height, glm::vec3 albedo);

} // namespace reference
