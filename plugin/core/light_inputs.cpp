#include "core/light_inputs.h"

#include "core/settings.h"

#include <cmath>

namespace obscura {

namespace {

// Values the run speaks of; a merely negative one is mended without a word.
bool brokenValue(float v) { return std::isnan(v) || std::isinf(v) || v > kMaxLight; }

bool allPhysical(ConstPlane plane) {
    for (int y = 0; y < plane.height; ++y)
        for (int x = 0; x < plane.width; ++x)
            for (int c = 0; c < plane.channels; ++c)
                if (!withinLight(plane.at(x, y)[c])) return false;
    return true;
}

} // namespace

long long zeroUnphysical(MutablePlane plane) {
    long long nonFinite = 0;
    for (int y = 0; plane.valid() && y < plane.height; ++y)
        for (int x = 0; x < plane.width; ++x) {
            bool counted = false;
            for (int c = 0; c < plane.channels; ++c) {
                float& v = plane.at(x, y)[c];
                if (withinLight(v)) continue;
                if (brokenValue(v) && !counted) ++nonFinite, counted = true;
                v = 0.0f;
            }
        }
    return nonFinite;
}

ConstPlane physical(ConstPlane plane, Image& storage, long long& nonFinite) {
    nonFinite = 0;
    if (!plane.valid() || allPhysical(plane)) return plane;
    storage = Image(plane.width, plane.height, plane.channels);
    for (int y = 0; y < plane.height; ++y)
        for (int x = 0; x < plane.width; ++x)
            for (int c = 0; c < plane.channels; ++c) storage.at(x, y)[c] = plane.at(x, y)[c];
    nonFinite = zeroUnphysical(storage.view());
    return storage.view();
}

std::string unphysicalNote(const std::string& what, long long pixels) {
    return what + ": " + std::to_string(pixels) + " pixel(s) hold NaN, infinite or huge (above 1e9) values; they count as 0 "
                                                   "(black)";
}

} // namespace obscura
