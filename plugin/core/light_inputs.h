// The colour the light reads (the bounce source, the senders' albedo, the environment map, deep
// colour) is radiance or reflectance. A NaN, an infinity or a value beyond kMaxLight is neither: a
// renderer's broken pixel, or a firefly that overflowed, which would spread through the bounce's
// blur or the map's prefilter into every pixel (sums of 3e38 overflow). It counts as 0 (black),
// and the run says how many pixels held one.
// A value below 0 counts as 0 too, without a word: converting a saturated colour into a
// narrower working space gives small negative components, and negative light would take light
// away from its receivers.
#pragma once
#include "base/image.h"

#include <string>

namespace obscura {

// Sets every value that is not finite, beyond kMaxLight or below 0 to 0 in place; returns how
// many pixels held one of the first two.
long long zeroUnphysical(MutablePlane plane);

// `plane` as it is when every value is finite and >= 0 (no copy), else a copy into `storage`
// with zeroUnphysical's changes; `nonFinite` says how many pixels held a NaN, an infinity or a
// value beyond kMaxLight.
ConstPlane physical(ConstPlane plane, Image& storage, long long& nonFinite);

// The line a run says of `what` ("the bounce source") with `pixels` such pixels.
std::string unphysicalNote(const std::string& what, long long pixels);

} // namespace obscura
