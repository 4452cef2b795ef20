// Depth as files store it (--depth planar|radial|inverse|normalized, --depth-range A,B), decoded
// to the planar or radial depth the operator reads, every kind of sky becoming +inf; depth
// from the position pass where a file has none; and what --inspect says of a stored depth.
#pragma once
#include "base/image.h"
#include "core/camera.h"
#include "core/settings.h"

#include <array>
#include <optional>
#include <string>

namespace obscura {

struct DepthDecoding {
    DepthEncoding encoding = DepthEncoding::Planar;
    // normalized: the stored value is 0 at range[0] and 1 at range[1] (range[0] > range[1]: white near).
    std::optional<std::array<double, 2>> range;
};

// Throws Error (naming no file: the caller's does) for normalized without a range.
void requireDecodable(const DepthDecoding& d);

// In place, to DepthKind decodedKind(d.encoding). Sky becomes +inf: +-inf in any encoding, 0
// in planar, radial and inverse (a plate's background where alpha is 0; inverse's sky), the far
// end of the range or beyond in normalized. NaN and negative stored values
// stay invalid (NaN, or negative), for --bad-pixels to judge. requireDecodable first.
void decodeDepth(Image& depth, const DepthDecoding& d);

// Planar depth of world positions (3 channels) through `camera`'s pose; +inf where a position
// is not finite or exactly (0, 0, 0), what renderers write where there is no surface. Throws
// Error when the camera has no pose.
Image depthFromPositions(const Image& positions, const Camera& camera);

// The stored depth as --inspect describes it.
struct DepthStatistics {
    double min = 0, max = 0;  // over the pixels that are not sky (0 when there are none)
    double skyShare = 0;      // pixels at 0, +-inf, NaN or at or beyond the sky depth
    std::string type;         // the channel's pixel type: "half", "float", "uint"
    std::string hint;         // "" or why it looks like an inverse or normalised depth rather than a distance
};
DepthStatistics depthStatistics(const Image& stored, float skyDepth, const std::string& type);

} // namespace obscura
