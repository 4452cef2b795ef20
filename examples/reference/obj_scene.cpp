// Any OBJ file as a scene: Y-up converted to our Z-up, diffuse colour (Kd) as
// albedo, camera and AO radius derived from the bounding box.
#include "scene.h"

#include <tiny_obj_loader.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace reference {

Scene loadObjScene(const std::string& path) {
    tinyobj::ObjReaderConfig config;
    config.triangulate = true;
    config.vertex_color = false;
    tinyobj::ObjReader reader;
    if (!reader.ParseFromFile(path, config))
        throw std::runtime_error("cannot read OBJ " + path + ": " + reader.Error());
    const auto& attrib = reader.GetAttrib();
    const auto& materials = reader.GetMaterials();

    Mesh mesh;
    for (size_t i = 0; i + 2 < attrib.vertices.size(); i += 3)  // OBJ is Y up, the world Z up
        mesh.vertices.emplace_back(attrib.vertices[i], -attrib.vertices[i + 2], attrib.vertices[i + 1]);
    if (mesh.vertices.empty()) throw std::runtime_error("OBJ " + path + " has no vertices");
    bool anyMaterial = false;
    for (const auto& shape : reader.GetShapes()) {
        const auto& idx = shape.mesh.indices;
        for (size_t f = 0; f + 2 < idx.size(); f += 3) {
            const int a = idx[f].vertex_index, b = idx[f + 1].vertex_index, c = idx[f + 2].vertex_index;
            if (a < 0 || b < 0 || c < 0) continue;
            mesh.triangles.push_back({unsigned(a), unsigned(b), unsigned(c)});
            const int m = shape.mesh.material_ids[f / 3];
            glm::vec3 albedo(0.7f);
            if (m >= 0 && m < int(materials.size())) {
                const auto& kd = materials[m].diffuse;
                albedo = glm::clamp(glm::vec3(kd[0], kd[1], kd[2]), 0.0f, 0.95f);
                anyMaterial = true;
            }
            mesh.triangleAlbedo.push_back(albedo);
        }
    }
    if (mesh.triangles.empty()) throw std::runtime_error("OBJ " + path + " has no faces");
    if (!anyMaterial) mesh.triangleAlbedo.clear();

    glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    for (const auto& v : mesh.vertices) {
        lo = glm::min(lo, glm::dvec3(v));
        hi = glm::max(hi, glm::dvec3(v));
    }
    const glm::dvec3 centre = 0.5 * (lo + hi);
    const double radius = std::max(0.5 * glm::length(hi - lo), 1e-6);

    Scene s;
    s.name = "obj:" + path;
    s.meshes.push_back(std::move(mesh));
    // The bounding sphere fits a 4:3 frame's height with some margin.
    const double hfov = 50.0 * 3.14159265358979323846 / 180.0;
    const double vfovHalf = std::atan(std::tan(hfov / 2) * 0.75);
    const glm::dvec3 viewDir = glm::normalize(glm::dvec3(0.55, -1.0, 0.45));
    s.camera = {centre + viewDir * (1.1 * radius / std::sin(vfovHalf)), centre, hfov};
    Lighting l;
    l.sunDirection = glm::normalize(glm::dvec3(0.4, -0.5, 0.75));
    l.sunColour = {1.45f, 1.38f, 1.25f};
    s.lighting = l;
    s.defaultRadius = 0.1 * radius;
    return s;
}

} // namespace reference
