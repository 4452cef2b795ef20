#include "environment_map.h"

#include "base/error.h"
#include "io/colour.h"
#include "io/exr_file.h"
#include "io/oiio_module.h"

namespace obscura {

EnvironmentMap readEnvironmentMap(const std::string& path, const std::string& colourSpace, long long maxPixels) {
    auto accept = [&](int width, int height, int channels) {
        if (channels < 3) throw FileError(path, "the environment map has fewer than 3 channels");
        checkWindow(path, "image", Imath::Box2i(Imath::V2i(0, 0), Imath::V2i(width - 1, height - 1)), maxPixels);
    };
    EnvironmentMap map;
    ColourMetadata meta;
    const std::string failed = oiioModule().readRgb(path, accept, map.rgb, meta);
    if (!failed.empty()) throw FileError(path, "cannot read the environment map: " + failed);
    const ColourManager& cm = colourManager();
    const ColourSpaceGuess space = cm.detectColourSpace(meta, colourSpace, "--env-colorspace");
    if (!space.warning.empty()) map.warnings.push_back("environment: " + space.warning);
    cm.toWorkingSpace(map.rgb, space.name);
    map.colourSpace = space.name;
    map.source = space.source;
    return map;
}

} // namespace obscura
