// Scene description shared by the builders, the tracer and the integrators.
// World space is Blender's (+Z up); the camera uses the OpenGL convention
// (looks down its -Z, +Y up).
#pragma once
#include <glm/glm.hpp>

#include <string>
#include <vector>

namespace reference {

struct Mesh {
    std::vector<glm::vec3> vertices;
    std::vector<glm::uvec3> triangles;
    glm::vec3 albedo{0.7f};
    std::vector<glm::vec3> triangleAlbedo;  // per triangle (OBJ materials); empty: `albedo`
};

struct Sphere {
    glm::dvec3 centre;
    double radius;
    glm::vec3 albedo;
};

struct PointLight {
    glm::dvec3 position;
    glm::vec3 intensity;  // DiffDir at distance 1 facing the light
};

// Light values are DiffDir units (irradiance / pi): a surface facing the sun
// gets `sunColour` in its DiffDir pass.
struct Lighting {
    glm::dvec3 sunDirection{0, 0, 1};  // towards the sun
    glm::vec3 sunColour{0.0f};
    glm::vec3 skyZenith{0.30f, 0.50f, 0.95f}, skyHorizon{0.75f, 0.85f, 1.00f};
    float skyStrength = 0.6f;
    std::vector<PointLight> points;

    glm::vec3 sky(const glm::dvec3& direction) const;  // radiance of the sky seen along `direction`
};

struct CameraSpec {
    glm::dvec3 eye{0, -5, 2}, target{0, 0, 0};
    double horizontalFovRad = 0.9;
};

struct Scene {
    std::string name;
    std::vector<Mesh> meshes;
    std::vector<Sphere> spheres;
    CameraSpec camera;
    Lighting lighting;
    double defaultRadius = 1.0;
    int groundMesh = -1;  // index of a ground at z = 0 (for the open-plane check), -1 if none
};

// "corner", "sphere-plane", "cornell", "stairs", "poles", "city", "terrain",
// "studio" or "obj:PATH". Throws std::runtime_error for an unknown name.
Scene makeScene(const std::string& spec);
const std::vector<std::string>& sceneNames();

// OBJ file (Y up, converted to Z up), camera framing its bounding box.
Scene loadObjScene(const std::string& path);

} // namespace reference
