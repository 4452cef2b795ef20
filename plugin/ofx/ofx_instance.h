// One instance of the node: its clip and parameter handles, found once at creation, its own
// environment map cache and the message it last showed (the only mutable state, each behind its
// mutex; never shared between instances).
#pragma once
#include "ofx_api.h"
#include "ofx_environment.h"

#include <mutex>
#include <string>
#include <vector>

namespace obscura::ofx {

struct Instance {
    OfxImageEffectHandle effect = nullptr;
    OfxImageClipHandle source = nullptr, depth = nullptr, normal = nullptr, position = nullptr, albedo = nullptr,
                       output = nullptr;
    OfxParamHandle output_ = nullptr, strength = nullptr, method = nullptr, giMethod = nullptr, radius = nullptr, directions = nullptr,
                   steps = nullptr, weighting = nullptr, falloff = nullptr, blur = nullptr, projection = nullptr,
                   fov = nullptr, focal = nullptr, aperture = nullptr, orthoWidth = nullptr, cameraToWorld = nullptr,
                   depthKind = nullptr, depthNear = nullptr, depthFar = nullptr,
                   normalSpace = nullptr, skyDepth = nullptr, maxScreenRadius = nullptr, device = nullptr,
                   threads = nullptr;
    OfxParamHandle ssdoSamples = nullptr, interleave = nullptr, skyColour = nullptr, envMap = nullptr,
                   envRotation = nullptr, envIntensity = nullptr, upAxis = nullptr, timesAlbedo = nullptr;
    std::vector<OfxParamHandle> methodParams;  // one per allMethodParams(), in its order
    mutable EnvironmentCache environment;
    std::mutex messageMutex;
    std::string shownError;      // the error the node should show (ofx_actions.cpp), "" for none
    std::string shownWarning;    // the last render's warning, shown where there is no error
    unsigned long messageVersion = 0;  // bumped at each change of either: the host is told outside the lock
};

// The instance the host holds for `effect` (its instance data); throws for none.
Instance* instanceOf(OfxImageEffectHandle effect);
// The same, or nullptr where there is none (a descriptor, a failed creation); never throws.
Instance* findInstance(OfxImageEffectHandle effect) noexcept;

} // namespace obscura::ofx
