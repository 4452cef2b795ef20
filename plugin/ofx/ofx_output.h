// Writing the Output image: what each Output option puts in a pixel, from the operator's
// planes, Strength, and the Source and Albedo images under the render window.
#pragma once
#include "ofx_coords.h"
#include "ofx_images.h"
#include "ofx_params.h"

#include "core/operator.h"

namespace obscura::ofx {

// The operator's result over a render window's data region (display-ordered, y down).
struct Occlusion {
    PixRect data;           // the depth/normal pixels read, OFX pixels
    bool computed = false;  // false: the AO is off or the window reads no data (AO = 1)
    OperatorOutputs result;
};

// Writes `out` over `window`: `source` and `albedo` are fetched under the window when the
// output reads them (empty images otherwise).
void writeOutput(const Params& p, const FrameMap& f, const Occlusion& occ, const ClipImage& out,
                 const ClipImage& source, const ClipImage& albedo, const PixRect& window);

} // namespace obscura::ofx
