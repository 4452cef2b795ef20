// Writing the reference: one single-part multilayer EXR named like Blender
// Cycles' passes (FLOAT, ZIP) with the OpenEXR standard camera attributes, and
// the JSON camera sidecar <stem>.json. Both go to temp files and are renamed.
#pragma once
#include "render.h"

#include <string>

namespace reference {

struct OutputInfo {
    std::string sceneName;
    RenderSettings settings;
    Convergence convergence;
};

// The EXR's worldToCamera: OpenEXR's left-handed camera looking down +Z, as a
// column-vector glm matrix (copy element-wise into Imath's row-vector M44f).
glm::dmat4 exrWorldToCamera(const PinholeCamera& camera);
// worldToNDC: NDC x right and y down, [0, 1] across the display window.
glm::dmat4 exrWorldToNdc(const PinholeCamera& camera);

void writeReference(const std::string& path, const Frame& frame, const PinholeCamera& camera, const OutputInfo& info);

} // namespace reference
