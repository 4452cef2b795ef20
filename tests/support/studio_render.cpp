#include "support/studio_render.h"

#include <cmath>
#include <cstdio>

namespace obscura::test {

const StudioRender& studioRender() {
    static const StudioRender s = [] {
        const int w = kStudioDisplay.max.x + 1, h = kStudioDisplay.max.y + 1;
        const Camera cam = studioCamera(w, h);
        const Box2i data{kStudioData.min.x, kStudioData.min.y, kStudioData.max.x + 1, kStudioData.max.y + 1};
        return StudioRender{renderScene(studioScene(), cam, Box2i{0, 0, w, h}, data), cliCameraFlags(cam, w)};
    }();
    return s;
}

std::vector<std::string> cliCameraFlags(const Camera& cam, int width) {
    std::string m;
    char buf[40];
    for (int row = 0; row < 4; ++row)
        for (int col = 0; col < 4; ++col) {
            std::snprintf(buf, sizeof buf, "%.17g", cam.cameraToWorld[col][row]);
            m += (m.empty() ? "" : ",") + std::string(buf);
        }
    std::snprintf(buf, sizeof buf, "%.17g", cam.horizontalFovRad(width) * 180.0 / M_PI);
    return {"--fov-deg", buf, "--camera-to-world", m};
}

fixtures::FixtureChannel studioChannel(const std::string& name, const Image& img, int c) {
    return {name, Imf::FLOAT, 1, 1,
            [&img, c](int x, int y) { return img.at(x - kStudioData.min.x, y - kStudioData.min.y)[c]; }};
}

fixtures::FixturePart studioGeometryPart(Imf::Compression compression) {
    const StudioRender& s = studioRender();
    fixtures::FixturePart part;
    part.displayWindow = kStudioDisplay;
    part.dataWindow = kStudioData;
    part.compression = compression;
    part.channels.push_back(studioChannel("Z", s.buffers.depth, 0));
    for (int c = 0; c < 3; ++c) part.channels.push_back(studioChannel(std::string("N.") + "XYZ"[c], s.buffers.normal, c));
    return part;
}

} // namespace obscura::test
