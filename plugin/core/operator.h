// The obscura operator: a pure function over in-memory planes. It knows nothing
// about files, argv, OFX clips or numpy; hosts adapt their data to these views.
#pragma once
#include "camera.h"
#include "base/image.h"
#include "settings.h"
#include "base/kernel_params.h"

#include <string>
#include <vector>

namespace obscura {

struct OperatorInputs {
    Box2i displayWindow;        // display window, origin (0,0) by convention
    Box2i dataWindow;           // the rectangle the planes cover (may exceed the display window)
    ConstPlane depth;           // 1 channel, required
    ConstPlane normal;          // 3 channels; not read (may be invalid) with NormalSpace::Depth
    ConstPlane position;        // 3 channels, optional (world space)
    DepthKind depthKind = DepthKind::Planar;
    // Depth: the normals are reconstructed from the depth and the camera
    // (kernels/depth_normal.glsl) on the device the method runs on, for every method alike.
    NormalSpace normalSpace = NormalSpace::World;
    Camera camera;
    // HBAO, optional (docs/deep.md): 2L channels per texel, L surfaces along the texel's ray as
    // (front, back) depths in the depth pass's units and kind, nearest first; layer 0 is the
    // visible surface; front +inf past a ray's last surface; back == front where the span is unknown.
    ConstPlane deepLayers;
    // HBAO's bounce with deep layers, optional: 3L channels, the RGB (un-premultiplied) each layer
    // radiates, as the deep file holds it; invalid: the hidden layers send no light.
    ConstPlane deepColour;

    // ---- SSDO only ----
    ConstPlane radiance;            // bounce source, 3 channels (needed for GI)
    ConstPlane albedo;              // 3 channels, optional: multiplies the bounce source
    const Image* environment = nullptr;  // lat-long RGB radiance; nullptr: the settings' sky colour
    // The host already set the radiance's and the albedo's NaN, infinite, huge and negative values
    // to 0 and said so (plugin/io does): the methods skip their own pass over them
    // (core/light_inputs.h).
    bool lightChecked = false;
};

struct StageTiming {
    std::string name;
    double seconds = 0;
};

struct OperatorStats {
    long long pixels = 0;
    long long skyPixels = 0;          // 0, +inf or >= sky depth: skipped, AO = 1
    long long invalidDepthPixels = 0; // NaN or negative: treated as holes (skipped, AO = 1)
    long long zeroNormalPixels = 0;   // non-sky pixels whose normal has ~zero length
    bool normalsFromDepth = false;    // the normals were reconstructed from the depth
    std::string device;               // "cpu (N threads)", "gl-osmesa: llvmpipe ..., OpenGL 4.5 ..."
    std::vector<std::string> notes;   // e.g. why --device auto fell back to the CPU
    // The light inputs that held NaN, infinite or huge values, taken as 0 ("the bounce source"):
    // named as in the notes, for a host that words its own message (the OpenFX node).
    std::vector<std::string> unphysicalLight;
    std::vector<StageTiming> timings;
};

struct OperatorOutputs {
    Image ao;                         // 1 channel over the data window
    Image directional;                // SSDO: DO irradiance, RGB (empty for HBAO)
    Image indirect;                   // SSDO with bounce: one-bounce irradiance, RGB (empty otherwise)
    OperatorStats stats;
};

using glsl::KernelParams;

// The kernel parameter block for these inputs and settings (shared by every backend).
KernelParams makeKernelParams(const OperatorInputs& in, const Settings& settings);

// The device `settings.device` resolves to, with its renderer and GL version, for
// --inspect. Throws obscura::Error when an explicit GL device cannot be made.
std::string describeDevice(const Settings& settings);

// Throws obscura::Error on inconsistent inputs (sizes, missing camera pose for world normals...).
OperatorOutputs runOperator(const OperatorInputs& in, const Settings& settings);

} // namespace obscura
