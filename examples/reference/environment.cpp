#include "environment.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace reference {

EnvironmentMap EnvironmentMap::load(const std::string& path, double rotationDeg) {
    auto in = OIIO::ImageInput::open(path);
    if (!in) throw std::runtime_error("cannot read environment " + path + ": " + OIIO::geterror());
    const OIIO::ImageSpec& spec = in->spec();
    if (spec.nchannels < 3) throw std::runtime_error("environment " + path + " needs 3 channels");
    EnvironmentMap m;
    m.width = spec.width;
    m.height = spec.height;
    m.rotationDeg = rotationDeg;
    m.rgb.resize(size_t(m.width) * m.height * 3);
    if (!in->read_image(0, 0, 0, 3, OIIO::TypeDesc::FLOAT, m.rgb.data()))
        throw std::runtime_error("cannot read environment " + path + ": " + in->geterror());
    if (m.width <= 0 || m.height <= 0) throw std::runtime_error("environment " + path + " is empty");
    return m;
}

EnvironmentMap EnvironmentMap::fromFunction(int width, int height,
                                            const std::function<glm::vec3(const glm::dvec3&)>& radiance) {
    EnvironmentMap m;
    m.width = width;
    m.height = height;
    m.rgb.resize(size_t(width) * height * 3);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            // Inverse of radiance()'s lookup: u = 0.5 + atan2(e.x, -e.z) / 2 pi, v = acos(e.y) / pi.
            const double phi = 2 * M_PI * ((x + 0.5) / width - 0.5), theta = M_PI * (y + 0.5) / height;
            const glm::dvec3 e(std::sin(theta) * std::sin(phi), std::cos(theta), -std::sin(theta) * std::cos(phi));
            const glm::vec3 c = radiance(glm::dvec3(e.x, -e.z, e.y));  // env (x, z, -y) -> world, rotation 0
            for (int k = 0; k < 3; ++k) m.rgb[(size_t(y) * width + x) * 3 + k] = c[k];
        }
    return m;
}

glm::dvec3 EnvironmentMap::worldToEnvironment(const glm::dvec3& w) const {
    // obscura: worldToEnv = mat3((1,0,0), (0,0,-1), (0,1,0)) (columns): (x, y, z) -> (x, z, -y);
    // spin = mat3((c,0,-s), (0,1,0), (s,0,c)) (columns), s = sin(rotation).
    const glm::dvec3 e(w.x, w.z, -w.y);
    const double a = rotationDeg * M_PI / 180.0, c = std::cos(a), s = std::sin(a);
    return {c * e.x + s * e.z, e.y, -s * e.x + c * e.z};
}

glm::dvec3 EnvironmentMap::radiance(const glm::dvec3& worldDir) const {
    const glm::dvec3 d = worldToEnvironment(worldDir);
    const double u = 0.5 + std::atan2(d.x, -d.z) / (2 * M_PI);
    const double v = std::acos(std::clamp(d.y, -1.0, 1.0)) / M_PI;
    const double tx = u * width - 0.5, ty = v * height - 0.5;
    const double fx = tx - std::floor(tx), fy = ty - std::floor(ty);
    const int ix = int(std::floor(tx)), iy = int(std::floor(ty));
    const int x0 = ((ix % width) + width) % width, x1 = (x0 + 1) % width;
    const int y0 = std::clamp(iy, 0, height - 1), y1 = std::clamp(iy + 1, 0, height - 1);
    auto at = [&](int x, int y) {
        const float* p = &rgb[(size_t(y) * width + x) * 3];
        return glm::dvec3(p[0], p[1], p[2]);
    };
    const glm::dvec3 top = glm::mix(at(x0, y0), at(x1, y0), fx), bottom = glm::mix(at(x0, y1), at(x1, y1), fx);
    return glm::mix(top, bottom, fy);
}

EnvironmentMap skyMap(const Lighting& lighting) {
    return EnvironmentMap::fromFunction(128, 64, [&](const glm::dvec3& d) { return lighting.sky(d); });
}

void writeEnvironment(const std::string& path, const EnvironmentMap& map) {
    auto out = OIIO::ImageOutput::create(path);
    const OIIO::ImageSpec spec(map.width, map.height, 3, OIIO::TypeDesc::FLOAT);
    if (!out || !out->open(path, spec) || !out->write_image(OIIO::TypeDesc::FLOAT, map.rgb.data()) || !out->close())
        throw std::runtime_error("cannot write environment " + path + ": " + OIIO::geterror());
}

} // namespace reference
