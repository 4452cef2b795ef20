// The camera the operator sees through, from the camera group's parameters at the frame's
// display window and pixel aspect.
#pragma once
#include "ofx_coords.h"
#include "ofx_params.h"

#include "core/camera.h"

namespace obscura::ofx {

// Throws obscura::Error for a field of view, width or camera-to-world the camera cannot use.
Camera makeCamera(const Params& p, const FrameMap& f);

} // namespace obscura::ofx
