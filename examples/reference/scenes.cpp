// The procedural scenes. Each picks a camera, a sun + sky, albedos and an AO
// radius that suits its scale.
#include "scene.h"
#include "shapes.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>

namespace reference {
namespace {

constexpr double kPi = 3.14159265358979323846;
using glm::dvec3;
using glm::vec3;

const vec3 kGrey{0.60f, 0.60f, 0.58f}, kWhite{0.73f, 0.73f, 0.73f};

double deg(double d) { return d * kPi / 180.0; }

// Small deterministic generator, so scenes are identical on every run.
struct Lcg {
    uint64_t state;
    double next() {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        return double(state >> 11) * (1.0 / 9007199254740992.0);
    }
    double range(double a, double b) { return a + (b - a) * next(); }
};

Lighting outdoor(dvec3 towardsSun, vec3 sun = {1.45f, 1.38f, 1.25f}) {
    Lighting l;
    l.sunDirection = glm::normalize(towardsSun);
    l.sunColour = sun;
    return l;
}

// A floor (z = 0, x >= 0) meeting a wall (x = 0) at 90 degrees; both are far
// larger than any radius, so AO near the crease has a closed form.
Scene corner() {
    Scene s;
    s.meshes.push_back(groundPlane(0, 200, -200, 200, 0, kGrey));
    Mesh wall;
    wall.albedo = {0.75f, 0.72f, 0.68f};
    addQuad(wall, {0, -200, 0}, {0, 200, 0}, {0, 200, 200}, {0, -200, 200});
    s.meshes.push_back(wall);
    s.camera = {{4.5, -4.0, 2.2}, {0.8, 1.0, 0.3}, deg(60)};
    s.lighting = outdoor({0.6, -0.45, 0.65});
    return s;
}

Scene spherePlane() {
    Scene s;
    s.meshes.push_back(groundPlane(-200, 200, -200, 200, 0, kGrey));
    s.spheres.push_back({{0, 0, 1}, 1.0, {0.80f, 0.30f, 0.25f}});
    s.camera = {{0, -5.5, 2.5}, {0, 0, 0.7}, deg(55)};
    s.lighting = outdoor({0.4, -0.3, 0.85});
    return s;
}

// Interior [0,2]^3, open towards the camera (y = 0).
Scene cornell() {
    Scene s;
    Mesh white, red, green;
    white.albedo = kWhite;
    red.albedo = {0.63f, 0.065f, 0.05f};
    green.albedo = {0.14f, 0.45f, 0.09f};
    addQuad(white, {0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0});  // floor
    addQuad(white, {0, 0, 2}, {0, 2, 2}, {2, 2, 2}, {2, 0, 2});  // ceiling
    addQuad(white, {0, 2, 0}, {2, 2, 0}, {2, 2, 2}, {0, 2, 2});  // back
    addQuad(red, {0, 0, 0}, {0, 2, 0}, {0, 2, 2}, {0, 0, 2});
    addQuad(green, {2, 0, 0}, {2, 0, 2}, {2, 2, 2}, {2, 2, 0});
    s.meshes = {white, red, green};
    s.meshes.push_back(box({1.32, 0.72, 0.3}, {0.3, 0.3, 0.3}, -0.3, kWhite));
    s.meshes.push_back(box({0.68, 1.30, 0.6}, {0.3, 0.3, 0.6}, 0.3, kWhite));
    s.camera = {{1, -3.7, 1}, {1, 1, 0.9}, deg(39.3)};  // the whole opening in a 4:3 frame
    s.lighting = outdoor({0.25, -0.8, 0.55}, {0.6f, 0.57f, 0.5f});
    s.lighting.skyStrength = 0.25f;
    s.lighting.points.push_back({{1.0, 1.0, 1.5}, {0.8f, 0.72f, 0.6f}});  // low enough that bounce noise stays tame
    s.defaultRadius = 0.5;
    return s;
}

Scene stairs() {
    Scene s;
    s.meshes.push_back(groundPlane(-100, 100, -100, 100, 0, kGrey));
    const double rise = 0.18, run = 0.28, half = 0.8;
    for (int i = 0; i < 12; ++i) {
        const double top = (i + 1) * rise;
        s.meshes.push_back(box({0, (i + 0.5) * run, top / 2}, {half, run / 2, top / 2}, 0, {0.70f, 0.66f, 0.60f}));
    }
    // A wall along one side and one at the top landing.
    s.meshes.push_back(box({-half - 0.1, 1.9, 1.5}, {0.1, 2.3, 1.5}, 0, {0.75f, 0.72f, 0.68f}));
    s.meshes.push_back(box({0, 12 * run + 0.1, 1.5}, {half, 0.1, 1.5}, 0, {0.75f, 0.72f, 0.68f}));
    s.camera = {{3.0, -2.2, 2.1}, {0, 1.4, 0.9}, deg(55)};
    s.lighting = outdoor({0.55, -0.35, 0.75});
    s.defaultRadius = 0.5;
    return s;
}

Scene poles() {
    Scene s;
    s.meshes.push_back(groundPlane(-100, 100, -100, 100, 0, kGrey));
    Lcg rng{7};
    for (int i = 0; i < 8; ++i)
        for (int j = 0; j < 8; ++j) {
            const dvec3 base((i - 3.5) * 0.7 + rng.range(-0.2, 0.2), (j - 3.5) * 0.7 + rng.range(-0.2, 0.2), 0);
            s.meshes.push_back(cylinder(base, rng.range(0.03, 0.06), rng.range(1.2, 3.0), 12,
                                        {float(rng.range(0.4, 0.8)), 0.55f, float(rng.range(0.3, 0.6))}));
        }
    s.camera = {{4.0, -4.8, 1.9}, {0, 0, 0.6}, deg(55)};
    s.lighting = outdoor({0.35, -0.6, 0.7});
    s.defaultRadius = 0.5;
    return s;
}

// A kilometre of city blocks: 100 m grid, buildings 20-80 m wide, 15-250 m tall.
Scene city() {
    Scene s;
    s.meshes.push_back(groundPlane(-3000, 3000, -3000, 3000, 0, {0.35f, 0.35f, 0.34f}));
    Lcg rng{11};
    for (int i = -5; i < 5; ++i)
        for (int j = -5; j < 5; ++j) {
            const double cx = (i + 0.5) * 100, cy = (j + 0.5) * 100;
            const int count = 1 + int(rng.next() * 3);
            for (int k = 0; k < count; ++k) {
                const double hw = rng.range(10, 40) / (count > 1 ? 1.6 : 1), hd = rng.range(10, 40) / (count > 1 ? 1.6 : 1);
                const double ox = count > 1 ? rng.range(-40 + hw, 40 - hw) : 0, oy = count > 1 ? rng.range(-40 + hd, 40 - hd) : 0;
                const double h = 15 + 235 * std::pow(rng.next(), 2.5);
                const float g = float(rng.range(0.45, 0.8));
                s.meshes.push_back(box({cx + ox, cy + oy, h / 2}, {hw, hd, h / 2}, 0, {g, g * 0.97f, g * 0.92f}));
            }
        }
    s.camera = {{-650, -750, 380}, {0, 0, 40}, deg(50)};
    s.lighting = outdoor({0.5, -0.3, 0.6});
    s.defaultRadius = 10;
    return s;
}

// Camera 2 cm above the ground near the origin: pebbles a few centimetres away,
// a boulder and posts at metres, hills kilometres off (depth ~1e-2 .. 1e4).
Scene terrain() {
    Scene s;
    auto height = [](double x, double y) {
        const double r = std::hypot(x, y);
        const double fade = std::clamp((r - 30.0) / 1500.0, 0.0, 1.0);
        double h = 6 * std::sin(x / 230.0) * std::cos(y / 310.0);
        const double hills[][4] = {{-2500, 6000, 700, 1500}, {1500, 5000, 450, 900}, {4200, 7500, 900, 1800},
                                   {-5200, 3500, 500, 1200}, {300, 9000, 1100, 2500}};
        for (const auto& hl : hills) {
            const double dx = x - hl[0], dy = y - hl[1];
            h += hl[2] * std::exp(-(dx * dx + dy * dy) / (2 * hl[3] * hl[3]));
        }
        return fade * fade * h;
    };
    s.meshes.push_back(polarHeightfield(0, 0, 0.004, 30000, 300, 256, height, {0.36f, 0.40f, 0.24f}));
    Lcg rng{5};
    for (int i = 0; i < 14; ++i) {  // pebbles 0.3-1 cm across, 3-20 cm away
        const double r = rng.range(0.03, 0.2), a = rng.range(deg(60), deg(120)), size = rng.range(0.0015, 0.005);
        s.spheres.push_back({{r * std::cos(a), r * std::sin(a), size * 0.6}, size, {0.55f, 0.52f, 0.48f}});
    }
    s.meshes.push_back(box({0.01, 0.045, 0.006}, {0.006, 0.006, 0.006}, 0.4, {0.7f, 0.3f, 0.2f}));  // 1.2 cm cube
    s.spheres.push_back({{-1.2, 5.0, 0.25}, 0.6, {0.5f, 0.48f, 0.45f}});                            // boulder
    for (int i = 0; i < 6; ++i)  // fence posts at 10-60 m
        s.meshes.push_back(cylinder({4.0 + 2.0 * i, 10.0 + 10.0 * i, 0}, 0.08, 1.2, 10, {0.45f, 0.33f, 0.22f}));
    s.camera = {{0, 0, 0.02}, {0, 1, 0.02 - std::tan(deg(6))}, deg(70)};
    s.lighting = outdoor({-0.45, -0.5, 0.55});
    return s;
}

// The built-in demo: a ground plane, a wall corner, boxes, spheres and sky.
Scene studio() {
    Scene s;
    const vec3 wall{0.75f, 0.72f, 0.68f};
    s.meshes.push_back(groundPlane(-1000, 1000, -1000, 1000, 0, kGrey));
    s.meshes.push_back(box({-1.35, 4.15, 1.5}, {2.85, 0.15, 1.5}, 0.0, wall));
    s.meshes.push_back(box({-4.15, 1.00, 1.5}, {0.15, 3.30, 1.5}, 0.0, wall));
    s.meshes.push_back(box({-3.30, 3.30, 0.55}, {0.55, 0.55, 0.55}, 0.0, {0.70f, 0.25f, 0.20f}));
    s.meshes.push_back(box({0.60, 2.00, 0.40}, {0.80, 0.50, 0.40}, 0.50, {0.25f, 0.45f, 0.70f}));
    s.meshes.push_back(box({-2.90, -0.30, 1.00}, {0.40, 0.40, 1.00}, 0.30, {0.80f, 0.75f, 0.35f}));
    s.spheres.push_back({{-0.60, -0.40, 0.70}, 0.70, {0.85f, 0.85f, 0.85f}});
    s.spheres.push_back({{1.90, 0.20, 0.45}, 0.45, {0.30f, 0.65f, 0.30f}});
    s.spheres.push_back({{0.60, 2.00, 1.15}, 0.35, {0.90f, 0.55f, 0.20f}});
    s.camera = {{5.0, -6.5, 2.6}, {-1.0, 1.5, 1.0}, deg(60)};
    s.lighting = outdoor({0.45, -0.55, 0.70});
    return s;
}

} // namespace

glm::vec3 Lighting::sky(const glm::dvec3& d) const {
    const float k = float(std::sqrt(std::clamp(d.z, 0.0, 1.0)));
    return skyStrength * glm::mix(skyHorizon, skyZenith, k);
}

const std::vector<std::string>& sceneNames() {
    static const std::vector<std::string> names = {"corner", "sphere-plane", "cornell", "stairs", "poles",
                                                   "city",   "terrain",      "studio",  "obj:PATH"};
    return names;
}

Scene makeScene(const std::string& spec) {
    Scene s;
    if (spec.rfind("obj:", 0) == 0) return loadObjScene(spec.substr(4));
    if (spec == "corner") s = corner();
    else if (spec == "sphere-plane") s = spherePlane();
    else if (spec == "cornell") s = cornell();
    else if (spec == "stairs") s = stairs();
    else if (spec == "poles") s = poles();
    else if (spec == "city") s = city();
    else if (spec == "terrain") s = terrain();
    else if (spec == "studio") s = studio();
    else throw std::runtime_error("unknown scene \"" + spec + "\"");
    s.name = spec;
    if (spec != "corner" && spec != "cornell") s.groundMesh = 0;  // their first mesh is a ground at z = 0
    return s;
}

} // namespace reference
