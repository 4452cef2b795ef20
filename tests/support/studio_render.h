// The studio scene rendered over an overscan data window, with the CLI flags that give its
// camera: the input the output-file tests (--write copy, new, append) build their EXRs from.
#pragma once
#include "support/exr_fixtures.h"
#include "support/scenes.h"

#include <OpenEXR/ImfChromaticities.h>
#include <Imath/ImathBox.h>
#include <Imath/ImathMatrix.h>

#include <string>
#include <vector>

namespace obscura::test {

// A 48 x 36 display window and a data window 4 and 3 pixels wider on each side (overscan).
const Imath::Box2i kStudioDisplay(Imath::V2i(0, 0), Imath::V2i(47, 35));
const Imath::Box2i kStudioData(Imath::V2i(-4, -3), Imath::V2i(51, 38));
// The attributes a renderer leaves that every output must keep.
const Imath::M44f kStudioWorldToCamera(1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0.5f, -1.5f, 3, 1);
const Imf::Chromaticities kAcesCgPrimaries(Imath::V2f(0.713f, 0.293f), Imath::V2f(0.165f, 0.830f),
                                           Imath::V2f(0.128f, 0.044f), Imath::V2f(0.32168f, 0.33767f));

struct StudioRender {
    SceneBuffers buffers;                 // over kStudioData
    std::vector<std::string> cameraFlags;  // --fov-deg F --camera-to-world m00,...,m33
};
// Rendered once per process.
const StudioRender& studioRender();
// --fov-deg F --camera-to-world m00,...,m33 for `cam` over a display `width` pixels wide, to 17 digits.
std::vector<std::string> cliCameraFlags(const Camera& cam, int width);

// Channel `c` of a plane over kStudioData, as a float fixture channel.
fixtures::FixtureChannel studioChannel(const std::string& name, const Image& img, int c);
// A part over the render's windows holding its depth (Z) and normals (N.X, N.Y, N.Z).
fixtures::FixturePart studioGeometryPart(Imf::Compression compression);

} // namespace obscura::test
