// Lat-long environment maps for SSDO, read the same way by every host (the CLI, Python and the
// OpenFX node): any format OpenImageIO reads, converted from its colour space to the
// OpenColorIO working space, so one map lights a shot alike in each.
#pragma once
#include "base/image.h"

#include <string>
#include <vector>

namespace obscura {

struct EnvironmentMap {
    Image rgb;                          // RGB floats in the working space
    std::string colourSpace, source;    // what it was converted from, and how that was decided
    std::vector<std::string> warnings;  // e.g. an unknown colour space tag
};

// colourSpace: the user's override ("" = from the file's metadata). A window above maxPixels
// is refused before allocating. Throws FileError naming the map.
EnvironmentMap readEnvironmentMap(const std::string& path, const std::string& colourSpace, long long maxPixels);

} // namespace obscura
