// Quick-look 8-bit PNG previews of in-memory planes (OpenImageIO).
//
// Every PNG obscura and its examples write uses one display encoding: scene-linear values
// times 2^EV, clamped to [0, 1], through the sRGB OETF (IEC 61966-2-1), rounded to 8 bits.
// So an AO preview, a contact sheet tile (examples/contact_sheet.py) and a report sheet
// (examples/report) of the same AO agree to the 8-bit step.
#pragma once
#include <string>

#include "base/image.h"

namespace obscura {

// The sRGB OETF of v clamped to [0, 1]; NaN gives 0.
float srgbOetf(float v);

// The 99th percentile (nearest rank) of each pixel's largest channel among 0..2 (channel 0
// alone with fewer than 3), NaN and infinities left out; 0 when no pixel has a finite value.
float previewPercentile99(const Image& img);

// Stops that bring previewPercentile99() to kAutoExposurePeak. At most 1 % of the pixels clip
// in any channel, and the brightest large surface (a sunlit floor) shows below white with its
// shading, while the top 1 % (highlights) keeps 1/0.8 = 1.25x of headroom. The largest
// channel, not luminance, because a saturated colour (a sunlit red wall) clips its strongest
// channel before its luminance reaches 1. 0 for an image with nothing above 0; within
// the range --preview-exposure accepts (core/settings_schema.h).
constexpr float kAutoExposurePeak = 0.8f;
float autoExposureEv(const Image& img);

// Writes `img` to `path` as an 8-bit PNG in the encoding above, atomically (temp file +
// rename), tagged sRGB: channels 0..2 as RGB when it has 3 or more, else channel 0 as grey.
// Throws obscura::Error with a one-line message on failure.
void writePreviewPng(const std::string& path, const Image& img, float exposureEv = 0.0f);

// Writes values that are already display-encoded (e.g. through an OpenColorIO display/view
// transform): channels 0..2 as RGB (channel 0 as grey with fewer than 3 channels), clamped
// to [0,1] and quantised with no transfer function, atomically like writePreviewPng.
// `colourSpaceTag`, when not empty, is stored as oiio:ColorSpace. Throws obscura::Error.
void writeEncodedPreviewPng(const std::string& path, const Image& img, const std::string& colourSpaceTag);

} // namespace obscura
