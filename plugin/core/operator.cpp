#include "operator.h"

#include "core/error.h"
#include "cpu/hbao_cpu.h"
#include "cpu/parallel.h"
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
    if (s.method != "hbao")
        throw Error("unknown method '" + s.method + "' (available: hbao)");
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

} // namespace

std::string describeDevice(const Settings& s) {
    std::vector<std::string> notes;
    std::string d = deviceDescription(selectGlBackend(s.device, notes), cpu::resolveThreads(s.threads));
    for (const std::string& n : notes) d += " (" + n + ")";
    return d;
}

HbaoParams makeHbaoParams(const OperatorInputs& in, const Settings& s) {
    const Camera& cam = in.camera;
    if (!cam.valid())
        throw Error("the camera has no valid projection (focal length or orthographic width)");
    HbaoParams p{};
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
    p.maxRadiusPixels = (float)std::max(in.dataWindow.width(), in.dataWindow.height()) + 2.0f;
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
    return p;
}

OperatorOutputs runOperator(const OperatorInputs& in, const Settings& s) {
    checkSettings(s);
    if (in.dataWindow.empty())
        throw Error("the data window is empty (0 pixels)");
    checkPlane(in.depth, 1, in.dataWindow, "depth");
    checkPlane(in.normal, 3, in.dataWindow, "normal");
    const HbaoParams params = makeHbaoParams(in, s);

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
