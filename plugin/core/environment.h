// Lat-long environment maps for SSDO: prefiltering to a sample's footprint.
#pragma once
#include "base/image.h"

namespace obscura {

// The mip level of a lat-long map (2x2 box-filtered per level) whose texels cover about
// the solid angle one of `samples` cosine-distributed directions stands for (2 pi / n),
// so each sample reads the light of its whole footprint instead of aliasing.
Image prefilterLatLong(const Image& latLong, int samples);

} // namespace obscura
