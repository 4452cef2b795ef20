// The per-scene contact sheet: a 2 x 2 PNG of
//   top-left  the input beauty (ViewLayer.Combined)
//   top-right obscura's AO           bottom-left the converged reference AO
//   bottom-right |obscura - reference| as a heat map (inferno, 0 .. heatMax, sky grey),
//                with a scale bar under it.
// The beauty and AO panels are in obscura's display encoding (io/preview.h: clamped, sRGB
// OETF), as --preview writes them; the heat map's colours are the colour map's own.
#pragma once
#include "base/image.h"

#include <string>

namespace report {

struct SheetPanels {
    std::string exrPath;                 // beauty source (ViewLayer.Combined.R/G/B)
    const obscura::Image* ao = nullptr;  // one channel, same size as the EXR
    const obscura::Image* reference = nullptr;
    const obscura::Image* depth = nullptr;  // sky where depth is not in (0, skyDepth)
    float skyDepth = 1e9f;
    std::string aoLabel, referenceLabel;  // e.g. "obscura hbao high cpu", "reference 1024 rays"
    double heatMax = 0.25;                // |error| mapped to the top of the colour scale
};

// Writes the sheet as an 8-bit PNG. Returns false when text could not be drawn (no font
// OpenImageIO can find): the sheet is then written without labels. Throws on I/O failure.
bool writeContactSheet(const std::string& pngPath, const SheetPanels& panels);

} // namespace report
