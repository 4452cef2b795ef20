// SSDO's lit outputs on the report: directional occlusion (DO) and one-bounce GI, against the
// converged render's Reference.DO and Reference.GI, under the lights the scene's direct pass
// was rendered with (its sun, and its sky as a lat-long map).
#pragma once
#include "obscura_runs.h"

#include "core/metrics.h"
#include "core/settings.h"
#include "reference/scene.h"

#include <string>

namespace report {

// The converged render's RGB reference layers (irradiance, not / pi).
struct LitReferences {
    obscura::Image directional;  // Reference.DO: sky through the open directions + the sun, unless blocked within R
    obscura::Image gi;           // Reference.GI: one bounce from surfaces within R (SSDO's GI)
    obscura::Image giUnlimited;  // Reference.GI_unlimited: every surface (pi x DiffInd)
};
LitReferences loadLitReferences(const std::string& exrPath);

// The scene's sky as the lat-long image obscura's SSDO reads (OperatorInputs::environment),
// the same pixels as the reference's DO environment.
obscura::Image skyEnvironment(const reference::Scene& scene);
// SSDO's lights for the scene: z up, no rotation, and the sun as a directional light of
// irradiance pi x sunColour (the scene's sun is in DiffDir units).
void applySceneLights(const reference::Scene& scene, obscura::Settings& s);

// The normalised error of an RGB irradiance against its reference, on luminance (Rec. 709) over
// the frame's surface pixels: relative RMSE = RMSE / mean(reference), and the ratio of the means
// (1 = no bias). `metrics` holds the plain luminance errors.
struct LitError {
    obscura::ErrorMetrics metrics;
    double relativeRmse = 0, meanRatio = 0, referenceMean = 0;
};
LitError litError(const obscura::Image& rgb, const obscura::Image& referenceRgb, const LoadedFrame& frame);

} // namespace report
