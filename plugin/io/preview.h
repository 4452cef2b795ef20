// Quick-look 8-bit PNG previews of in-memory planes (OpenImageIO).
#pragma once
#include <string>

#include "base/image.h"

namespace obscura {

// Writes `img` to `path` as an 8-bit PNG, atomically (temp file + rename).
//  - channel >= 0: that channel alone, as a grey image of data values clamped to
//    [0,1] with no transfer function (AO, masks: 0.5 is stored as 128).
//  - channel < 0 and img.channels >= 3: channels 0..2 as scene-linear RGB,
//    clamped to [0,1] and encoded with the sRGB OETF. With fewer than 3
//    channels, channel 0 is written as data.
// NaN is written as 0. Throws obscura::Error with a one-line message on failure.
void writePreviewPng(const std::string& path, const Image& img, int channel = 0);

// Writes values that are already display-encoded (e.g. through an OpenColorIO display/view
// transform): channels 0..2 as RGB (channel 0 as grey with fewer than 3 channels), clamped
// to [0,1] and quantised with no transfer function, atomically like writePreviewPng.
// `colourSpaceTag`, when not empty, is stored as oiio:ColorSpace. Throws obscura::Error.
void writeEncodedPreviewPng(const std::string& path, const Image& img, const std::string& colourSpaceTag);

} // namespace obscura
