#include "operator.h"

#include "core/backend.h"
#include "core/devices.h"
#include "core/hbao_plan.h"

#include "base/error.h"
#include "core/method_runs.h"
#include "core/methods.h"
#include "cpu/parallel.h"
#include "gpu/gl_backend.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <string>

namespace obscura {

void checkPlane(const ConstPlane& plane, int channels, const Box2i& window, const char* what) {
    if (!plane.valid())
        throw Error(std::string("the ") + what + " plane is missing");
    if (plane.channels < channels)
        throw Error(std::string("the ") + what + " plane has " + std::to_string(plane.channels) + " channel(s), needs " +
                    std::to_string(channels));
    if (plane.width != window.width() || plane.height != window.height())
        throw Error(std::string("the ") + what + " plane is " + std::to_string(plane.width) + "x" +
                    std::to_string(plane.height) + " but the data window is " + std::to_string(window.width()) + "x" +
                    std::to_string(window.height()));
}

namespace {

void checkSettings(const Settings& s) {
    if (!findMethod(s.method))
        throw Error("unknown method '" + s.method + "' (available: " + methodNames() + ")");
    if (s.interleave < 1 || s.interleave > 8) throw UsageError("--interleave must be between 1 and 8");
    if (s.interleave * s.interleave > s.ssdoSamples) {
        const std::string m = std::to_string(s.interleave);
        throw UsageError("--samples " + std::to_string(s.ssdoSamples) + " leaves pixels of the " + m + " x " + m +
                         " --interleave block without a sample: give --samples at least " +
                         std::to_string(s.interleave * s.interleave) + ", or a smaller --interleave");
    }
    for (const MethodParam* p : allMethodParams()) {
        const double v = p->intField ? (double)(s.*(p->intField)) : p->floatField ? (double)(s.*(p->floatField)) : 0.0;
        const std::string problem = checkParam(*p, v, true);
        if (!problem.empty()) throw Error(problem);
    }
    if (s.lights.size() > 4)
        throw Error("at most 4 directional lights");
    // Light past 1e9 overflows float in the sums over samples (1e38 gave NaN everywhere).
    auto lightProblem = [](const float rgb[3]) {
        return !std::all_of(rgb, rgb + 3, [](float v) { return withinLight(v); });
    };
    if (methodOutputs(s.method, "do")) {  // the methods that light with them
        if (lightProblem(s.skyRadiance)) throw Error("--sky radiance must be between 0 and 1e9");
        for (const auto& l : s.lights)
            if (lightProblem(l.irradiance)) throw Error("--light irradiance must be between 0 and 1e9");
    }
    if (!(std::isfinite(s.radius) && s.radius > 0.0f))
        throw Error("--radius must be a positive finite number of world units");
    if ((s.blur < 0 && s.blur != kBlurAuto) || s.blur > 64)
        throw Error("--blur must be between 0 and 64 pixels");
    if (!(s.skyDepth > 0.0f))
        throw Error("the sky depth threshold must be positive");
    if (!(s.maxRadiusPixels >= 0.0f && std::isfinite(s.maxRadiusPixels)))
        throw Error("the maximum screen radius must be 0 (automatic) or a positive number of pixels");
}

// View space -> environment space (y up): the camera's rotation, the up-axis convention and
// the user's rotation about up. Without a pose, view space stands in for world space.
glm::mat4 viewToEnvironment(const Camera& cam, const Settings& s) {
    const glm::mat3 viewToWorld = cam.hasPose ? glm::mat3(cam.cameraToWorld) : glm::mat3(1.0f);
    glm::mat3 worldToEnv(1.0f);
    if (s.zUp) worldToEnv = glm::mat3(glm::vec3(1, 0, 0), glm::vec3(0, 0, -1), glm::vec3(0, 1, 0)); // z up -> y up
    const float a = s.envRotationDeg * (float)M_PI / 180.0f;
    const glm::mat3 spin(glm::vec3(std::cos(a), 0, -std::sin(a)), glm::vec3(0, 1, 0), glm::vec3(std::sin(a), 0, std::cos(a)));
    return glm::mat4(spin * worldToEnv * viewToWorld);
}

void fillSsdoParams(const OperatorInputs& in, const Settings& s, KernelParams& p) {
    p.viewToEnv = viewToEnvironment(in.camera, s);
    p.skyRadiance = glm::vec4(s.skyRadiance[0], s.skyRadiance[1], s.skyRadiance[2], 0.0f);
    const glm::mat3 worldToView = in.camera.hasPose ? glm::mat3(glm::inverse(in.camera.cameraToWorld)) : glm::mat3(1.0f);
    p.lightCount = (int)std::min<size_t>(s.lights.size(), 4);
    for (int k = 0; k < p.lightCount; ++k) {
        const auto& l = s.lights[k];
        const glm::vec3 d = glm::normalize(worldToView * glm::vec3(l.direction[0], l.direction[1], l.direction[2]));
        p.lightDirection[k] = glm::vec4(d, 0.0f);
        p.lightIrradiance[k] = glm::vec4(l.irradiance[0], l.irradiance[1], l.irradiance[2], 0.0f);
    }
    p.ssdoSamples = s.ssdoSamples;
    p.interleave = s.interleave;
    p.bounce = s.bounce && in.radiance.valid() ? 1 : 0;
    p.senderAlbedo = in.albedo.valid() ? 1 : 0;
    p.envIntensity = s.envIntensity;
    p.envWidth = p.envHeight = 0; // set by the caller once the map is prefiltered
}

} // namespace

std::string describeDevice(const Settings& s) {
    const DeviceChoice c = chooseDevice(s);
    std::string d = c.description;
    for (const std::string& n : c.notes) d += " (" + n + ")";
    return d;
}

// The bounds of HBAO's 32 sectors, uniform in the pseudo-angle p = b / (|a| + b) (mirrored
// past the normal, kernels/hbao.glsl): F's terms at each, computed once here rather than
// per pixel. At p = k/16 (k <= 16) the direction above the tangent is (1 - p, p), normalised.
void fillSectorTerms(KernelParams& p) {
    for (int k = 0; k <= 32; ++k) {
        const double q = (k <= 16 ? k : 32 - k) / 16.0;
        const double len = std::hypot(q, 1.0 - q);
        const double c = (k <= 16 ? 1.0 - q : q - 1.0) / len, sn = q / len;
        const double theta = std::atan2(sn, c);
        p.sectorTerms[k] = glm::vec4((float)(1.0 - c), (float)sn, (float)(theta - sn * c), (float)(sn * sn));
    }
}

KernelParams makeKernelParams(const OperatorInputs& in, const Settings& s) {
    const Camera& cam = in.camera;
    if (!cam.valid())
        throw Error("the camera has no valid projection (focal length or orthographic width)");
    KernelParams p{};
    p.normalToView = glm::mat4(1.0f);
    if (in.normalSpace == NormalSpace::World) {
        if (!cam.hasPose)
            throw Error("normals are in world space but the camera pose is unknown: give --camera-to-world, "
                        "a JSON sidecar, or a position pass to fit the camera from");
        p.normalToView = glm::mat4(glm::mat3(glm::transpose(glm::inverse(glm::mat3(cam.worldToCamera())))));
    }
    p.fx = (float)cam.fx;
    p.fy = (float)cam.fy;
    p.cx = (float)cam.cx;
    p.cy = (float)cam.cy;
    p.invFx = (float)(1.0 / cam.fx);
    p.invFy = (float)(1.0 / cam.fy);
    p.radius = s.radius;
    const MethodInfo* method = findMethod(s.method);
    p.blurReach = method && method->blurWithinReach ? glsl::BLUR_REACH * s.radius : 0.0f;
    p.skyDepth = s.skyDepth;
    // Bounds the sample loop: beyond the buffer's extent samples leave the buffer anyway.
    // A host rendering tiles pins it (settings.maxRadiusPixels), so tiles agree with the whole frame.
    p.maxRadiusPixels = s.maxRadiusPixels > 0.0f
                            ? s.maxRadiusPixels
                            : (float)std::max(in.dataWindow.width(), in.dataWindow.height()) + 2.0f;
    p.depthScale = 1.0f;
    p.width = in.dataWindow.width();
    p.height = in.dataWindow.height();
    p.originX = in.dataWindow.x0;
    p.originY = in.dataWindow.y0;
    p.directions = s.directions;
    p.steps = s.steps;
    p.cosineWeighting = s.weighting == Weighting::Cosine ? 1 : 0;
    p.linearFalloff = s.falloff == Falloff::Linear ? 1 : 0;
    p.orthographic = cam.projection == Projection::Orthographic ? 1 : 0;
    p.radialDepth = in.depthKind == DepthKind::Radial ? 1 : 0;
    fillHbaoParams(planHbao(s, in.deepLayers.valid() ? in.deepLayers.channels / 2 : 0), p);
    fillSectorTerms(p);
    p.ssaoSamples = s.ssaoSamples;
    p.ssaoHemisphere = s.ssaoHemisphere ? 1 : 0;
    fillSsdoParams(in, s, p);
    // The pyramid's levels and top window are set when it is built (cpu/discs_cpu.h).
    p.discWindow = s.discsWindow;
    p.discPolygon = s.discsNoPolygon ? 0 : 1;
    p.discBlend = s.discsBlendLevels ? 1 : 0;
    // Nodes from level 2 up stand for blocks of 4 x 4 pixels and more, whose disc is a poorer
    // stand-in (they bend, straddle creases): they open one node farther, k + 1 (docs/discs.md).
    p.discWideFrom = 2;
    p.discVisibility = 0;
    p.discUnion = s.discsSum ? 0 : 1;
    return p;
}

namespace {

// Counts sky, holes and surface pixels without a usable normal.
void scanPasses(const OperatorInputs& in, const Settings& s, OperatorStats& st) {
    for (int y = 0; y < in.depth.height; ++y) {
        for (int x = 0; x < in.depth.width; ++x) {
            const float d = *in.depth.at(x, y);
            if (d > 0.0f && d < s.skyDepth) {
                const float* n = in.normal.at(x, y);
                const float len2 = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
                if (!(len2 > 1e-12f && len2 < 1e30f)) ++st.zeroNormalPixels;
            } else if (std::isnan(d) || d < 0.0f) {
                ++st.invalidDepthPixels; // holes: skipped like sky, but worth reporting
            } else {
                ++st.skyPixels;          // 0, +inf or beyond the sky threshold: a sky convention
            }
        }
    }
}

} // namespace

OperatorOutputs runOperator(const OperatorInputs& given, const Settings& s) {
    checkSettings(s);
    if (given.dataWindow.empty())
        throw Error("the data window is empty (0 pixels)");
    // Pixel positions are floats on the devices, and a pixel's centre is half a pixel in: past
    // 2^23 float has no halves (a plane at 8.4e6 read 0.37 with discs).
    for (const Box2i& w : {given.dataWindow, given.displayWindow})
        for (int v : {w.x0, w.y0, w.x1, w.y1})
            if (std::abs((long long)v) > (1 << 23))
                throw Error("the data or display window reaches pixel " + std::to_string(v) +
                            ", beyond 8388608 from the origin, where float pixel centres are no longer exact");
    checkPlane(given.depth, 1, given.dataWindow, "depth");
    const bool fromDepth = given.normalSpace == NormalSpace::Depth;
    if (!fromDepth) checkPlane(given.normal, 3, given.dataWindow, "normal");
    OperatorInputs in = given;
    Image reconstructed;
    if (fromDepth) {  // view-space normals, filled in once the backend is chosen
        reconstructed = Image(in.dataWindow.width(), in.dataWindow.height(), 3, 0.0f);
        in.normal = reconstructed.view();
    }
    if (in.deepLayers.valid()) {
        if (!methodReads(s.method, "deep")) throw Error("--method " + s.method + " does not read deep layers");
        checkPlane(in.deepLayers, 2, in.dataWindow, "deep layers");
        if (in.deepLayers.channels % 2 != 0)
            throw Error("the deep layers plane has " + std::to_string(in.deepLayers.channels) +
                        " channels; it needs (front, back) pairs");
    }
    if (in.deepColour.valid()) {
        checkPlane(in.deepColour, 3, in.dataWindow, "deep colour");
        if (in.deepColour.channels % 3 != 0)
            throw Error("the deep colour plane has " + std::to_string(in.deepColour.channels) +
                        " channels; it needs RGB per layer");
    }
    const KernelParams params = makeKernelParams(in, s);

    OperatorOutputs out;
    OperatorStats& st = out.stats;
    const int threads = cpu::resolveThreads(s.threads);
    const MethodInfo& method = *findMethod(s.method);
    const gpu::ThreadGlState callersGl;  // the calling thread's GL state, as it was, when the run ends
    const std::unique_ptr<Backend> backend = chooseBackend(s, method.gl, threads, st.notes);
    st.device = backend->description();
    st.pixels = in.dataWindow.area();

    if (fromDepth) {
        backend->depthNormals(params, in.depth, reconstructed.view(), st);
        st.normalsFromDepth = true;
    }
    auto t0 = Clock::now();
    scanPasses(in, s, st);
    st.timings.push_back({"scan", secondsSince(t0)});

    out.ao = Image(in.dataWindow.width(), in.dataWindow.height(), 1, 1.0f);
    method.run(MethodRun{in, s, params, *backend, threads, out});
    return out;
}

} // namespace obscura
