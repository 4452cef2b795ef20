#include "gpu/gl_backend.h"

#include "core/error.h"
#include "gpu/gl_context.h"
#include "gpu/gl_kernels.h"
#include "gpu/gl_program.h"
#include "gpu/kernel_sources.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <vector>

namespace obscura::gpu {

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

std::string kernelText(const char* file) {
    for (const KernelSource& s : kernelSources())
        if (std::strcmp(s.name, file) == 0) return s.text;
    throw Error(std::string("kernel source '") + file + "' is not embedded in this build");
}

// The largest projected radius over the frame (the nearest surface), as hbaoPixel computes it.
float maxReachPixels(const glsl::KernelParams& p, ConstPlane depth) {
    if (p.orthographic) return std::min(p.radius * p.fx, p.maxRadiusPixels);
    double zMin = INFINITY;
    for (int y = 0; y < depth.height; ++y) {
        const double ry = (p.cy - (p.originY + y + 0.5)) * p.invFy;
        for (int x = 0; x < depth.width; ++x) {
            double z = *depth.at(x, y) * (double)p.depthScale;
            if (!(z >= 1.17549435e-38 && z < p.skyDepth)) continue;
            if (p.radialDepth) {
                const double rx = (p.originX + x + 0.5 - p.cx) * p.invFx;
                z /= std::sqrt(1.0 + rx * rx + ry * ry);
            }
            zMin = std::min(zMin, z);
        }
    }
    if (!std::isfinite(zMin)) return 0.0f;
    const double r = p.radius * (double)p.fx / std::sqrt(std::max(zMin * zMin - (double)p.radius * p.radius, 1e-30));
    return (float)std::min(r, (double)p.maxRadiusPixels);
}

enum Binding { kParams = 0, kDepth = 1, kNormal = 2, kAoIn = 3, kAoOut = 4 };
constexpr int kGroup = 8;  // local_size_x/y in kGlBindings

} // namespace

GlBackend::GlBackend(ContextKind kind, bool hardwareOnly) : context_(GlContext::create(kind, hardwareOnly)) {
    const GlApi& gl = context_->gl();
    for (const GlKernel& k : glKernels()) {
        const std::vector<ShaderPart> parts = {
            {"glsl_prelude.glsl", kernelText("glsl_prelude.glsl")},
            {"kernel_params.glsl", kernelText("kernel_params.glsl")},
            {"gl_kernels.cpp (bindings)", kGlBindings},
            {"common.glsl", kernelText("common.glsl")},
            {k.file, kernelText(k.file)},
            {"gl_kernels.cpp (main)", k.main},
        };
        programs_[k.name] = buildComputeProgram(gl, k.name, parts);
    }
    gl.GenBuffers(5, buffers_);
}

const ContextInfo& GlBackend::info() const { return context_->info(); }

GlBackend::~GlBackend() {
    try {
        context_->makeCurrent();
        const GlApi& gl = context_->gl();
        gl.DeleteBuffers(5, buffers_);
        for (auto& [name, program] : programs_) gl.DeleteProgram(program);
    } catch (...) {
        // Destruction at thread exit: the context may already be gone; nothing to report to.
    }
}

void GlBackend::runHbao(const glsl::KernelParams& p, ConstPlane depth, ConstPlane normal, MutablePlane ao, int blur,
                        GlTimings* timings, long long maxTexels) {
    context_->makeCurrent();
    const GlApi& gl = context_->gl();
    GlTimings t;
    const int W = p.width, H = p.height;
    // How far a pixel's result reads: the HBAO samples (radius plus snapping), then the blur.
    const int apron = (int)std::ceil(std::min(maxReachPixels(p, depth), (float)std::max(W, H))) + 2 + std::max(blur, 0);
    if (maxTexels <= 0) maxTexels = info().maxStorageBlockBytes / (3 * (long long)sizeof(float));  // normals: 3 floats
    const long long groupLimit = (long long)std::min(info().maxWorkGroups[0], info().maxWorkGroups[1]) * kGroup;
    int tileSide = std::max(W, H);
    if ((long long)W * H > maxTexels || std::max(W, H) > groupLimit) {
        tileSide = (int)std::min<long long>((long long)std::sqrt((double)maxTexels), groupLimit) - 2 * apron;
        if (tileSide < 16)
            throw Error("the radius (" + std::to_string(apron) + " px apron) is too large to tile on this GPU; use --device cpu");
    }

    std::vector<float> depthTile, normalTile, aoTile;
    for (int ty = 0; ty < H; ty += tileSide) {
        for (int tx = 0; tx < W; tx += tileSide) {
            const Box2i inner{tx, ty, std::min(tx + tileSide, W), std::min(ty + tileSide, H)};
            const Box2i buf = inner.width() == W && inner.height() == H
                                  ? inner
                                  : intersect(Box2i{inner.x0 - apron, inner.y0 - apron, inner.x1 + apron, inner.y1 + apron},
                                              Box2i{0, 0, W, H});
            const int bw = buf.width(), bh = buf.height();
            glsl::KernelParams q = p;
            q.width = bw;
            q.height = bh;
            q.originX = p.originX + buf.x0;
            q.originY = p.originY + buf.y0;

            auto t0 = Clock::now();
            depthTile.resize((size_t)bw * bh);
            normalTile.resize((size_t)bw * bh * 3);
            for (int y = 0; y < bh; ++y)
                for (int x = 0; x < bw; ++x) {
                    const size_t i = (size_t)y * bw + x;
                    depthTile[i] = *depth.at(buf.x0 + x, buf.y0 + y);
                    const float* n = normal.at(buf.x0 + x, buf.y0 + y);
                    normalTile[3 * i] = n[0];
                    normalTile[3 * i + 1] = n[1];
                    normalTile[3 * i + 2] = n[2];
                }
            auto upload = [&](int binding, GLenum target, const void* data, size_t bytes) {
                gl.BindBuffer(target, buffers_[binding]);
                gl.BufferData(target, (GLsizeiptr)bytes, data, GL_DYNAMIC_DRAW);
                gl.BindBufferBase(target, binding, buffers_[binding]);
            };
            upload(kParams, GL_UNIFORM_BUFFER, &q, sizeof(q));
            upload(kDepth, GL_SHADER_STORAGE_BUFFER, depthTile.data(), depthTile.size() * sizeof(float));
            upload(kNormal, GL_SHADER_STORAGE_BUFFER, normalTile.data(), normalTile.size() * sizeof(float));
            upload(kAoIn, GL_SHADER_STORAGE_BUFFER, nullptr, depthTile.size() * sizeof(float));
            upload(kAoOut, GL_SHADER_STORAGE_BUFFER, nullptr, depthTile.size() * sizeof(float));
            t.upload += since(t0);

            t0 = Clock::now();
            const GLuint groupsX = (GLuint)((bw + kGroup - 1) / kGroup), groupsY = (GLuint)((bh + kGroup - 1) / kGroup);
            gl.UseProgram(programs_.at("hbao"));
            gl.DispatchCompute(groupsX, groupsY, 1);
            GLuint result = buffers_[kAoOut];
            if (blur > 0) {
                const GLuint blurProgram = programs_.at("blur");
                gl.UseProgram(blurProgram);
                gl.Uniform1i(gl.GetUniformLocation(blurProgram, "blurRadius"), blur);
                for (int axis = 0; axis < 2; ++axis) {
                    // Ping-pong: the previous pass's output is this pass's input.
                    const GLuint src = result, dst = src == buffers_[kAoOut] ? buffers_[kAoIn] : buffers_[kAoOut];
                    gl.MemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
                    gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, kAoIn, src);
                    gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, kAoOut, dst);
                    gl.Uniform2i(gl.GetUniformLocation(blurProgram, "blurAxis"), axis == 0, axis == 1);
                    gl.DispatchCompute(groupsX, groupsY, 1);
                    result = dst;
                }
            }
            gl.MemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
            gl.Finish();
            t.compute += since(t0);

            t0 = Clock::now();
            aoTile.resize((size_t)bw * bh);
            gl.BindBuffer(GL_SHADER_STORAGE_BUFFER, result);
            gl.GetBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, (GLsizeiptr)(aoTile.size() * sizeof(float)), aoTile.data());
            for (int y = inner.y0; y < inner.y1; ++y)
                for (int x = inner.x0; x < inner.x1; ++x)
                    *ao.at(x, y) = aoTile[(size_t)(y - buf.y0) * bw + (x - buf.x0)];
            t.readback += since(t0);
            ++t.tiles;
            const GLenum err = gl.GetError();
            if (err != GL_NO_ERROR)
                throw Error("OpenGL error 0x" + [&] { char b[16]; std::snprintf(b, sizeof b, "%04x", err); return std::string(b); }() +
                            " while running HBAO on " + info().backend);
        }
    }
    if (timings) *timings = t;
}

bool isDeviceName(const std::string& n) {
    return n == "cpu" || n == "auto" || n == "gl" || n == "gl-egl" || n == "gl-osmesa";
}

GlBackend& glBackendFor(const std::string& device) {
    // One backend per thread and device: a GL context is current on one thread only.
    thread_local std::map<std::string, std::unique_ptr<GlBackend>> cache;
    auto& slot = cache[device];
    if (slot) return *slot;
    if (device == "gl-egl") {
        slot = std::make_unique<GlBackend>(ContextKind::EglDevice, false);
    } else if (device == "gl-egl-hardware") {
        slot = std::make_unique<GlBackend>(ContextKind::EglDevice, true);
    } else if (device == "gl-osmesa") {
        slot = std::make_unique<GlBackend>(ContextKind::OSMesa, false);
    } else if (device == "gl") {
        try {
            slot = std::make_unique<GlBackend>(ContextKind::EglDevice, false);
        } catch (const Error& egl) {
            try {
                slot = std::make_unique<GlBackend>(ContextKind::OSMesa, false);
            } catch (const Error& osmesa) {
                throw Error(std::string("no OpenGL context: ") + egl.what() + "; " + osmesa.what());
            }
        }
    } else {
        throw Error("unknown device '" + device + "' (cpu, auto, gl, gl-egl, gl-osmesa)");
    }
    return *slot;
}

} // namespace obscura::gpu
