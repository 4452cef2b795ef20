#include "operator.h"

#include "core/error.h"
#include "cpu/hbao_cpu.h"
#include "cpu/parallel.h"
#include "cpu/blur_cpu.h"
#include "cpu/ssdo_cpu.h"
#include "core/environment.h"
#include "gpu/gl_backend.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

namespace obscura {

namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

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

void checkSettings(const Settings& s) {
    if (s.method != "hbao" && s.method != "ssdo")
        throw Error("unknown method '" + s.method + "' (available: hbao, ssdo)");
    if (s.ssdoSamples < 1 || s.ssdoSamples > 4096)
        throw Error("--samples must be between 1 and 4096");
    if (s.interleave < 1 || s.interleave > 8 || s.interleave * s.interleave > s.ssdoSamples)
        throw Error("--interleave must be between 1 and 8, with at least one sample per pixel");
    if (s.lights.size() > 4)
        throw Error("at most 4 directional lights");
    if (!(std::isfinite(s.radius) && s.radius > 0.0f))
        throw Error("--radius must be a positive finite number of world units");
    if (s.directions < 1 || s.directions > 256)
        throw Error("--directions must be between 1 and 256");
    if (s.steps < 1 || s.steps > 256)
        throw Error("--steps must be between 1 and 256");
    if (s.blur < 0 || s.blur > 64)
        throw Error("--blur must be between 0 and 64 pixels");
    if (!(s.skyDepth > 0.0f))
        throw Error("the sky depth threshold must be positive");
    if (!(s.maxRadiusPixels >= 0.0f && std::isfinite(s.maxRadiusPixels)))
        throw Error("the maximum screen radius must be 0 (automatic) or a positive number of pixels");
}

// The GL backend a device name asks for, or nullptr for the CPU. An explicit GL device
// that cannot be made throws; "auto" falls back to the CPU and says why in `notes`.
gpu::GlBackend* selectGlBackend(const std::string& requested, std::vector<std::string>& notes) {
    const std::string device = requested.empty() ? "cpu" : requested;
    if (!gpu::isDeviceName(device))
        throw Error("unknown device '" + device + "' (cpu, auto, gl, gl-egl, gl-osmesa)");
    if (device == "cpu") return nullptr;
    if (device != "auto") return &gpu::glBackendFor(device);
    // auto means "a real GPU if there is one": a software GL would be slower than the CPU path.
    try {
        return &gpu::glBackendFor("gl-egl-hardware");
    } catch (const Error& e) {
        notes.push_back(std::string("--device auto: ") + e.what() + "; using the CPU");
        return nullptr;
    }
}

std::string deviceDescription(const gpu::GlBackend* gl, int threads) {
    if (!gl) return "cpu (" + std::to_string(threads) + " threads)";
    return gl->info().backend + ": " + gl->info().renderer + ", OpenGL " + gl->info().version;
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
    p.sampleArea = (float)M_PI * s.radius * s.radius / (float)s.ssdoSamples;
    p.envWidth = p.envHeight = 0; // set by the caller once the map is prefiltered
}

// SSDO: plan what is needed (no bounce without a source, no map when none is given),
// prefilter the environment to the per-pixel sample count, run, and blur over the
// interleaving block.
void runSsdoMethod(const OperatorInputs& in, const Settings& s, KernelParams p, gpu::GlBackend* gl, int threads,
                   OperatorOutputs& out) {
    if (s.bounce && !in.radiance.valid())
        throw Error("the bounce (GI) needs a radiance source: a direct-diffuse or beauty pass");
    if (in.radiance.valid()) checkPlane(in.radiance, 3, in.dataWindow, "bounce source");
    if (in.albedo.valid()) checkPlane(in.albedo, 3, in.dataWindow, "albedo");
    OperatorStats& st = out.stats;
    auto t0 = Clock::now();
    Image level;
    if (in.environment && !in.environment->empty()) {
        if (in.environment->channels < 3) throw Error("the environment map needs 3 channels");
        level = prefilterLatLong(*in.environment, std::max(1, s.ssdoSamples / (s.interleave * s.interleave)));
        p.envWidth = level.width;
        p.envHeight = level.height;
        st.timings.push_back({"environment", secondsSince(t0)});
    }
    const int w = in.dataWindow.width(), h = in.dataWindow.height();
    out.directional = Image(w, h, 3, 0.0f);
    if (p.bounce) out.indirect = Image(w, h, 3, 0.0f);
    Image unusedIndirect = p.bounce ? Image() : Image(w, h, 3, 0.0f);
    Image& indirect = p.bounce ? out.indirect : unusedIndirect;
    const ConstPlane environment = level.empty() ? ConstPlane{} : ConstPlane(level.view());
    // The interleaved subsets are gathered back by a blur as wide as the block (or --blur).
    const int blur = s.blur > 0 ? s.blur : (s.interleave > 1 ? s.interleave : 0);
    if (gl) {
        gpu::GlTimings t;
        gl->runSsdo(p, {in.depth, in.normal, in.radiance, in.albedo, environment}, out.directional.view(),
                    indirect.view(), out.ao.view(), blur, &t);
        st.timings.push_back({"gl-upload", t.upload});
        st.timings.push_back({"gl-compute", t.compute});
        st.timings.push_back({"gl-readback", t.readback});
        return;
    }
    cpu::SsdoPlanes planes{in.depth, in.normal, in.radiance, in.albedo, environment};
    t0 = Clock::now();
    cpu::runSsdo(p, planes, out.directional.view(), indirect.view(), out.ao.view(), threads);
    st.timings.push_back({p.bounce ? "ssdo+bounce" : "ssdo", secondsSince(t0)});
    if (blur > 0) {
        t0 = Clock::now();
        cpu::runBlur(p, in.depth, in.normal, out.directional.view(), blur, threads);
        if (p.bounce) cpu::runBlur(p, in.depth, in.normal, out.indirect.view(), blur, threads);
        cpu::runBlur(p, in.depth, in.normal, out.ao.view(), blur, threads);
        st.timings.push_back({"blur", secondsSince(t0)});
    }
}

} // namespace

std::string describeDevice(const Settings& s) {
    std::vector<std::string> notes;
    std::string d = deviceDescription(selectGlBackend(s.device, notes), cpu::resolveThreads(s.threads));
    for (const std::string& n : notes) d += " (" + n + ")";
    return d;
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
    fillSsdoParams(in, s, p);
    return p;
}

OperatorOutputs runOperator(const OperatorInputs& in, const Settings& s) {
    checkSettings(s);
    if (in.dataWindow.empty())
        throw Error("the data window is empty (0 pixels)");
    checkPlane(in.depth, 1, in.dataWindow, "depth");
    checkPlane(in.normal, 3, in.dataWindow, "normal");
    const KernelParams params = makeKernelParams(in, s);

    OperatorOutputs out;
    OperatorStats& st = out.stats;
    const int threads = cpu::resolveThreads(s.threads);
    gpu::GlBackend* gl = selectGlBackend(s.device, st.notes);
    st.device = deviceDescription(gl, threads);
    st.pixels = in.dataWindow.area();

    auto t0 = Clock::now();
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
    st.timings.push_back({"scan", secondsSince(t0)});

    out.ao = Image(in.dataWindow.width(), in.dataWindow.height(), 1, 1.0f);
    if (s.method == "ssdo") {
        runSsdoMethod(in, s, params, gl, threads, out);
        return out;
    }
    if (gl) {
        gpu::GlTimings t;
        gl->runHbao(params, in.depth, in.normal, out.ao.view(), s.blur, &t);
        st.timings.push_back({"gl-upload", t.upload});
        st.timings.push_back({"gl-compute", t.compute});
        st.timings.push_back({"gl-readback", t.readback});
        return out;
    }
    t0 = Clock::now();
    cpu::runHbao(params, in.depth, in.normal, out.ao.view(), threads);
    st.timings.push_back({"hbao", secondsSince(t0)});
    if (s.blur > 0) {
        t0 = Clock::now();
        cpu::runBlur(params, in.depth, in.normal, out.ao.view(), s.blur, threads);
        st.timings.push_back({"blur", secondsSince(t0)});
    }
    return out;
}

} // namespace obscura
