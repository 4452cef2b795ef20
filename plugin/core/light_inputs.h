// The colour the light reads (the bounce source, the senders' albedo, the environment map) is
// radiance or reflectance. A NaN or an infinity is neither: a renderer's broken pixel, or a
// firefly that overflowed half float, which would spread through the bounce's blur or the map's
// prefilter into every pixel. It counts as 0 (black), and the run says how many pixels held one.
// A value below 0 counts as 0 too, without a word: converting a saturated colour into a
// narrower working space gives small negative components, and negative light would take light
// away from its receivers.
#pragma once
#include "base/image.h"

namespace obscura {

// Sets every value that is not finite, or is below 0, to 0 in place; returns how many pixels
// held one that is not finite.
long long zeroUnphysical(MutablePlane plane);

// `plane` as it is when every value is finite and >= 0 (no copy), else a copy into `storage`
// with zeroUnphysical's changes; `nonFinite` says how many pixels held a NaN or an infinity.
ConstPlane physical(ConstPlane plane, Image& storage, long long& nonFinite);

} // namespace obscura
