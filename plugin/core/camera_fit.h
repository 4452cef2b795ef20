// Solving the camera from the world-position pass: every valid pixel is a
// correspondence between its centre (x + 0.5, y + 0.5) and a world point.
#pragma once
#include "camera.h"
#include "base/image.h"

namespace obscura {

struct FitOptions {
    double maxResidualPx = 0.5;      // refuse when the RMS over inliers is above this
    double minInlierFraction = 0.7;  // ... or when fewer of the valid samples fit
    int maxPoints = 4000;            // samples used (spread evenly over the valid pixels)
};

// Fits a pinhole camera (principal point at the display centre, pixel aspect as
// given, no skew; the principal point is freed only if that fits poorly) and an
// orthographic one, and returns whichever reprojects better, with hasPose = true,
// fitResidualPx and a `source` such as "fit:position (perspective, rms 0.03 px ...)".
// Pixels that are non-finite, all zero or >= 1e9 in magnitude (sky) are ignored,
// and silhouette pixels (blended positions) are rejected as outliers.
// Orthographic fits cannot see the eye's distance along the view axis: the eye is
// put one scene extent in front of the nearest sample.
// Throws obscura::Error (one line, with the residual) when the fit is poor or the
// samples are too few or degenerate.
// `position`: 3 floats per pixel covering `dataWindow`; `display` sets the principal point.
Camera fitCameraFromPosition(ConstPlane position, Box2i dataWindow, Box2i display,
                             double pixelAspect = 1.0, const FitOptions& options = {});

// How well a camera (with pose) explains a position pass: RMS reprojection error in
// pixels over the best 90% of samples (silhouettes and sky blends are not its fault).
// Returns -1 when there are no valid samples.
double reprojectionRmsPx(const Camera& camera, ConstPlane position, Box2i dataWindow, int maxPoints = 4000);

} // namespace obscura
