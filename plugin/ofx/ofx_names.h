// The names the host knows the node by: the plugin's identifier and version, its clips, and
// its parameters (each name is also the parameter's script name). Saved projects refer to
// them, so they never change.
#pragma once
#include "ofx_api.h"

namespace obscura::ofx {

inline constexpr const char* kPluginId = "io.github.obscura.AmbientOcclusion";
inline constexpr unsigned kVersionMajor = OBSCURA_OFX_VERSION_MAJOR;
inline constexpr unsigned kVersionMinor = OBSCURA_OFX_VERSION_MINOR;

// Clips.
inline constexpr const char* kClipSource = kOfxImageEffectSimpleSourceClipName;
inline constexpr const char* kClipDepth = "Depth";
inline constexpr const char* kClipNormal = "Normal";
inline constexpr const char* kClipPosition = "Position";
inline constexpr const char* kClipAlbedo = "Albedo";
inline constexpr const char* kClipOutput = kOfxImageEffectOutputClipName;

// Parameters. The methods' own parameters are named by the method table (MethodParam::key).
inline constexpr const char* kParamOutput = "output";
inline constexpr const char* kParamStrength = "strength";
inline constexpr const char* kParamMethod = "method";
inline constexpr const char* kParamGiMethod = "giMethod";
inline constexpr const char* kParamRadius = "radius";
inline constexpr const char* kParamDirections = "directions";
inline constexpr const char* kParamSteps = "steps";
inline constexpr const char* kParamWeighting = "weighting";
inline constexpr const char* kParamFalloff = "falloff";
inline constexpr const char* kParamBlur = "blur";
inline constexpr const char* kParamProjection = "projection";
inline constexpr const char* kParamFov = "fovDeg";
inline constexpr const char* kParamOrthoWidth = "orthoWidth";
inline constexpr const char* kParamFocal = "focalMm";
inline constexpr const char* kParamAperture = "apertureMm";
inline constexpr const char* kParamCameraToWorld = "cameraToWorld";
inline constexpr const char* kParamDepthKind = "depthKind";
inline constexpr const char* kParamNormalSpace = "normalSpace";
inline constexpr const char* kParamDepthNear = "depthRangeNear";
inline constexpr const char* kParamDepthFar = "depthRangeFar";
inline constexpr const char* kParamSkyDepth = "skyDepth";
inline constexpr const char* kParamMaxScreenRadius = "maxScreenRadius";
inline constexpr const char* kParamDevice = "device";
inline constexpr const char* kParamThreads = "threads";
inline constexpr const char* kParamSsdoSamples = "samples";
inline constexpr const char* kParamInterleave = "interleave";
inline constexpr const char* kParamSkyColour = "skyColour";
inline constexpr const char* kParamEnvMap = "envMap";
inline constexpr const char* kParamEnvRotation = "envRotation";
inline constexpr const char* kParamEnvIntensity = "envIntensity";
inline constexpr const char* kParamUpAxis = "upAxis";
inline constexpr const char* kParamTimesAlbedo = "timesAlbedo";
inline constexpr const char* kGroupSsdo = "ssdoGroup";
inline constexpr const char* kGroupCamera = "cameraGroup";
inline constexpr const char* kGroupAdvanced = "advancedGroup";
inline constexpr const char* kPage = "controls";

} // namespace obscura::ofx
