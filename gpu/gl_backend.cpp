#include "gpu/gl_backend.h"

#include "base/cancel.h"
#include "base/error.h"
#include "base/hbao_reach.h"
#include "gpu/gl_context.h"
#include "gpu/gl_kernels.h"
#include "gpu/gl_program.h"
#include "gpu/kernel_sources.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <functional>
#include <vector>

namespace obscura::gpu {

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

std::string kernelText(const std::string& file) {
    for (const KernelSource& s : kernelSources())
        if (file == s.name) return s.text;
    throw Error("kernel source '" + file + "' is not embedded in this build");
}

// Kernel file `file` as parts, each line `#include "other.glsl"` replaced by that file's parts:
// GLSL has no #include, and the CPU's C++ compiler reads the same lines. Each part keeps its
// file's line numbers, so a compile error names the line it is on.
void appendKernelParts(const std::string& file, std::vector<ShaderPart>& parts) {
    const std::string text = kernelText(file);
    const std::string directive = "#include \"";
    size_t start = 0; // of the text not yet in a part
    int startLine = 1;
    int line = 1;
    for (size_t pos = 0; pos < text.size(); ++line) {
        const size_t end = std::min(text.find('\n', pos), text.size());
        if (text.compare(pos, directive.size(), directive) == 0) {
            parts.push_back({file, text.substr(start, pos - start), startLine});
            const size_t name = pos + directive.size();
            appendKernelParts(text.substr(name, text.find('"', name) - name), parts);
            start = end + 1;
            startLine = line + 1;
        }
        pos = end + 1;
    }
    if (start < text.size()) parts.push_back({file, text.substr(start), startLine});
}

enum Binding {
    kParams = 0, kDepth = 1, kNormal = 2, kSignalIn = 3, kSignalOut = 4,
    kRadiance = 5, kAlbedo = 6, kEnv = 7, kDirectional = 8, kIndirect = 9, kBindings = 10
};
constexpr int kGroup = 8;  // local_size_x/y in kGlBindings

// A tile of the frame: the texels it produces (inner) and those it reads (buf = inner + apron).
struct Tile {
    Box2i inner, buf;
};

// Tiles that fit the context's buffer and dispatch limits; one tile when the frame fits.
// `apron` is how far a result reads; tiles then equal the one-tile result exactly.
std::vector<Tile> planTiles(int W, int H, int apron, long long maxTexels, const ContextInfo& info) {
    const long long groupLimit = (long long)std::min(info.maxWorkGroups[0], info.maxWorkGroups[1]) * kGroup;
    std::vector<Tile> tiles;
    if ((long long)W * H <= maxTexels && std::max(W, H) <= groupLimit) {
        tiles.push_back({Box2i{0, 0, W, H}, Box2i{0, 0, W, H}});
        return tiles;
    }
    const int side = (int)std::min<long long>((long long)std::sqrt((double)maxTexels), groupLimit) - 2 * apron;
    if (side < 16)
        throw Error("the radius (" + std::to_string(apron) + " px apron) is too large to tile on this GPU; use --device cpu");
    for (int ty = 0; ty < H; ty += side)
        for (int tx = 0; tx < W; tx += side) {
            const Box2i inner{tx, ty, std::min(tx + side, W), std::min(ty + side, H)};
            tiles.push_back({inner, intersect(Box2i{inner.x0 - apron, inner.y0 - apron, inner.x1 + apron, inner.y1 + apron},
                                              Box2i{0, 0, W, H})});
        }
    return tiles;
}

// Whether `channels` floats a texel over [x0, x1) of every row are one run of `plane`'s memory.
bool rowsContiguous(ConstPlane plane, int x0, int x1, int channels) {
    return plane.xStride == channels && plane.yStride == (std::ptrdiff_t)plane.width * channels && x0 == 0 &&
           x1 == plane.width;
}

std::string hex(unsigned v) {
    char b[16];
    std::snprintf(b, sizeof b, "0x%04x", v);
    return b;
}

// The program of kernel k with `defines` (empty: none).
GLuint compileKernel(const GlApi& gl, const GlKernel& k, const std::string& defines) {
    std::vector<ShaderPart> parts = {
        {"glsl_prelude.glsl", kernelText("glsl_prelude.glsl")},
        {"kernel_params.glsl", kernelText("kernel_params.glsl")},
        {"gl_kernels.cpp (bindings)", kGlBindings},
    };
    appendKernelParts("common.glsl", parts);
    // In every program: disc AO's elements use the depth normals too.
    parts.push_back({"depth_normal.glsl", kernelText("depth_normal.glsl")});
    if (!defines.empty()) parts.push_back({std::string(k.name) + " (defines)", defines});
    if (std::strcmp(k.file, "depth_normal.glsl") != 0) appendKernelParts(k.file, parts);
    parts.push_back({"gl_kernels.cpp (main)", k.main});
    return buildComputeProgram(gl, k.name, parts);
}

} // namespace

GlBackend::GlBackend(ContextKind kind, bool hardwareOnly) : context_(GlContext::create(kind, hardwareOnly)) {
    const GlApi& gl = context_->gl();
    for (const GlKernel& k : glKernels())
        if (!k.defines) programs_[k.name] = compileKernel(gl, k, "");
    gl.GenBuffers(kBufferCount, buffers_);
}

GLuint GlBackend::program(const char* name, const glsl::KernelParams& q) {
    for (const GlKernel& k : glKernels()) {
        if (std::strcmp(k.name, name) != 0) continue;
        if (!k.defines) return programs_.at(name);
        const std::string defines = k.defines(q);
        const std::string key = std::string(name) + "\n" + defines;
        const auto found = programs_.find(key);
        if (found != programs_.end()) return found->second;
        return programs_[key] = compileKernel(context_->gl(), k, defines);
    }
    throw Error(std::string("no GL kernel named '") + name + "'");
}

const ContextInfo& GlBackend::info() const { return context_->info(); }

GlBackend::~GlBackend() {
    try {
        context_->makeCurrent();
        const GlApi& gl = context_->gl();
        gl.DeleteBuffers(kBufferCount, buffers_);
        for (auto& [name, program] : programs_) gl.DeleteProgram(program);
    } catch (...) {
        // Destruction at thread exit: the context may already be gone; nothing to report to.
    }
}

// Shared by every kernel: tiles, uploads the depth, normal and deep pairs (the last two when valid) and
// whatever `upload` adds, dispatches `run`, then `readback` copies each tile's inner texels out.
void GlBackend::runTiled(const glsl::KernelParams& p, ConstPlane depth, ConstPlane normal, ConstPlane deep, int blur,
                         long long maxTexels, GlTimings& t,
                         const std::function<void(const Box2i& buf, const glsl::KernelParams& q)>& upload,
                         const std::function<void(const glsl::KernelParams& q)>& run,
                         const std::function<void(const Box2i& inner, const Box2i& buf)>& readback) {
    context_->makeCurrent();
    const GlApi& gl = context_->gl();
    const int W = p.width, H = p.height;
    // How far a pixel's result reads: its samples (radius plus snapping), then the blur.
    const int apron = (int)std::ceil(std::min(hbaoReachPixels(p, depth), (float)std::max(W, H))) + 2 + std::max(blur, 0);
    // A tile's largest buffer per texel: a 3-float plane, or deep input's 2 floats a layer.
    const int widest = std::max(3, deep.valid() ? 2 * p.deepLayers : 0);
    if (maxTexels <= 0) maxTexels = info().maxStorageBlockBytes / (widest * (long long)sizeof(float));
    for (const Tile& tile : planTiles(W, H, apron, maxTexels, info())) {
        throwIfCancelled();  // the host's check, between dispatches (base/cancel.h)
        glsl::KernelParams q = p;
        q.width = tile.buf.width();
        q.height = tile.buf.height();
        q.originX = p.originX + tile.buf.x0;
        q.originY = p.originY + tile.buf.y0;
        auto t0 = Clock::now();
        uploadBuffer(kParams, GL_UNIFORM_BUFFER, &q, sizeof(q));
        uploadPlane(kDepth, depth, tile.buf, 1);
        if (normal.valid()) uploadPlane(kNormal, normal, tile.buf, 3);  // none for the depth's own normals
        // HBAO's deep pairs go to the signal-in buffer (HBAO reads no signal).
        if (deep.valid()) uploadPlane(kSignalIn, deep, tile.buf, 2 * q.deepLayers);
        upload(tile.buf, q);
        t.upload += since(t0);

        t0 = Clock::now();
        run(q);
        gl.MemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
        gl.Finish();
        t.compute += since(t0);

        t0 = Clock::now();
        readback(tile.inner, tile.buf);
        t.readback += since(t0);
        ++t.tiles;
        const GLenum err = gl.GetError();
        if (err != GL_NO_ERROR) throw Error("OpenGL error " + hex(err) + " on " + info().backend);
    }
}

void GlBackend::uploadBuffer(int binding, unsigned target, const void* data, size_t bytes) {
    const GlApi& gl = context_->gl();
    gl.BindBuffer(target, buffers_[binding]);
    // Never an empty buffer (binding one is an error), but never read past the caller's data either.
    gl.BufferData(target, (GLsizeiptr)std::max<size_t>(bytes, 16), bytes >= 16 ? data : nullptr, GL_DYNAMIC_DRAW);
    if (bytes < 16 && data && bytes > 0) gl.BufferSubData(target, 0, (GLsizeiptr)bytes, data);
    gl.BindBufferBase(target, binding, buffers_[binding]);
}

void GlBackend::dispatch(const char* program, const glsl::KernelParams& q) {
    const GlApi& gl = context_->gl();
    gl.UseProgram(this->program(program, q));
    gl.DispatchCompute((GLuint)((q.width + kGroup - 1) / kGroup), (GLuint)((q.height + kGroup - 1) / kGroup), 1);
}

// Two geometry-aware blur passes over the `channels`-channel signal in buffer `binding`;
// the result ends in the same buffer (ping-pong through the signal-out scratch).
void GlBackend::blurBuffer(int binding, int channels, int radius, const glsl::KernelParams& q) {
    if (radius <= 0) return;
    const GlApi& gl = context_->gl();
    const GLuint program = programs_.at("blur");
    gl.UseProgram(program);
    gl.Uniform1i(gl.GetUniformLocation(program, "blurRadius"), radius);
    gl.Uniform1i(gl.GetUniformLocation(program, "signalChannels"), channels);
    const size_t bytes = (size_t)q.width * q.height * channels * sizeof(float);
    gl.BindBuffer(GL_SHADER_STORAGE_BUFFER, buffers_[kScratch]);
    gl.BufferData(GL_SHADER_STORAGE_BUFFER, (GLsizeiptr)bytes, nullptr, GL_DYNAMIC_DRAW);
    const GLuint data = buffers_[binding], scratch = buffers_[kScratch];
    for (int axis = 0; axis < 2; ++axis) {
        gl.MemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
        gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, kSignalIn, axis == 0 ? data : scratch);
        gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, kSignalOut, axis == 0 ? scratch : data);
        gl.Uniform2i(gl.GetUniformLocation(program, "blurAxis"), axis == 0, axis == 1);
        gl.DispatchCompute((GLuint)((q.width + kGroup - 1) / kGroup), (GLuint)((q.height + kGroup - 1) / kGroup), 1);
    }
    gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, kSignalOut, buffers_[kSignalOut]);
}

// `channels` floats per texel of `plane` over `box`, rows of box.width() texels back to back as the
// shader reads them, into buffer `binding`. GL copies the data before BufferData returns, so a plane
// already laid out that way goes straight from its memory; other rows are gathered into packed_.
void GlBackend::uploadPlane(int binding, ConstPlane plane, const Box2i& box, int channels) {
    const size_t row = (size_t)box.width() * channels, bytes = row * box.height() * sizeof(float);
    if (rowsContiguous(plane, box.x0, box.x1, channels)) {
        uploadBuffer(binding, GL_SHADER_STORAGE_BUFFER, plane.at(0, box.y0), bytes);
        return;
    }
    packed_.resize(row * box.height());
    float* o = packed_.data();
    for (int y = box.y0; y < box.y1; ++y, o += row) {
        if (plane.xStride == channels) {
            std::copy_n(plane.at(box.x0, y), row, o);
            continue;
        }
        for (int x = box.x0; x < box.x1; ++x) std::copy_n(plane.at(x, y), channels, o + (size_t)(x - box.x0) * channels);
    }
    uploadBuffer(binding, GL_SHADER_STORAGE_BUFFER, packed_.data(), bytes);
}

void GlBackend::uploadPlaneOrStub(int binding, ConstPlane plane, bool use, const Box2i& box, int channels) {
    if (use) uploadPlane(binding, plane, box, channels);
    else uploadBuffer(binding, GL_SHADER_STORAGE_BUFFER, nullptr, 16);
}

// Copies `channels` floats per texel of buffer `binding` (laid out over `buf`) over `inner` into `out`.
// Only the rows holding `inner` are read; straight into `out` when those rows are one run of both.
void GlBackend::readInner(int binding, int channels, const Box2i& inner, const Box2i& buf, MutablePlane out) {
    const GlApi& gl = context_->gl();
    gl.BindBuffer(GL_SHADER_STORAGE_BUFFER, buffers_[binding]);
    const size_t row = (size_t)buf.width() * channels, floats = row * inner.height();
    const auto first = (GLintptr)((size_t)(inner.y0 - buf.y0) * row * sizeof(float));
    if (inner.x0 == buf.x0 && inner.x1 == buf.x1 && rowsContiguous(out, inner.x0, inner.x1, channels)) {
        gl.GetBufferSubData(GL_SHADER_STORAGE_BUFFER, first, (GLsizeiptr)(floats * sizeof(float)), out.at(0, inner.y0));
        return;
    }
    readback_.resize(floats);
    gl.GetBufferSubData(GL_SHADER_STORAGE_BUFFER, first, (GLsizeiptr)(floats * sizeof(float)), readback_.data());
    const size_t innerRow = (size_t)inner.width() * channels;
    for (int y = inner.y0; y < inner.y1; ++y) {
        const float* v = readback_.data() + (size_t)(y - inner.y0) * row + (size_t)(inner.x0 - buf.x0) * channels;
        if (out.xStride == channels) {
            std::memcpy(out.at(inner.x0, y), v, innerRow * sizeof(float));
            continue;
        }
        for (int x = inner.x0; x < inner.x1; ++x) std::copy_n(v + (size_t)(x - inner.x0) * channels, channels, out.at(x, y));
    }
}

void GlBackend::runAoWith(const char* program, const glsl::KernelParams& p, ConstPlane depth, ConstPlane normal,
                          ConstPlane deep, MutablePlane ao, int blur, GlTimings* timings, long long maxTexels) {
    GlTimings t;
    runTiled(
        p, depth, normal, deep, blur, maxTexels, t,
        [&](const Box2i& buf, const glsl::KernelParams&) {
            uploadBuffer(kSignalOut, GL_SHADER_STORAGE_BUFFER, nullptr, (size_t)buf.width() * buf.height() * sizeof(float));
        },
        [&](const glsl::KernelParams& q) {
            dispatch(program, q);
            blurBuffer(kSignalOut, 1, blur, q);
        },
        [&](const Box2i& inner, const Box2i& buf) { readInner(kSignalOut, 1, inner, buf, ao); });
    if (timings) *timings = t;
}

void GlBackend::runDepthNormals(const glsl::KernelParams& p, ConstPlane depth, MutablePlane normal, GlTimings* timings) {
    GlTimings t;
    glsl::KernelParams q = p;
    q.maxRadiusPixels = 0.0f;  // a texel reads two neighbours each way: runTiled's least apron, 2
    runTiled(
        q, depth, ConstPlane{}, ConstPlane{}, 0, 0, t,
        [&](const Box2i& buf, const glsl::KernelParams&) {
            uploadBuffer(kSignalOut, GL_SHADER_STORAGE_BUFFER, nullptr, (size_t)buf.width() * buf.height() * 3 * sizeof(float));
        },
        [&](const glsl::KernelParams& r) { dispatch("depth_normals", r); },
        [&](const Box2i& inner, const Box2i& buf) { readInner(kSignalOut, 3, inner, buf, normal); });
    if (timings) *timings = t;
}

void GlBackend::runDiscs(const glsl::KernelParams& p, const float* pyramid, size_t pyramidFloats, ConstPlane depth,
                         ConstPlane normal, MutablePlane ao, int blur, GlTimings* timings) {
    context_->makeCurrent();
    const GlApi& gl = context_->gl();
    const ContextInfo& ci = info();
    const size_t bytes = pyramidFloats * sizeof(float);
    const long long groupLimit = (long long)std::min(ci.maxWorkGroups[0], ci.maxWorkGroups[1]) * kGroup;
    // Every receiver may read any node of the pyramid, so the frame runs as one tile.
    if ((long long)bytes > ci.maxStorageBlockBytes || std::max(p.width, p.height) > groupLimit)
        throw Error("the disc pyramid (" + std::to_string(bytes >> 20) + " MiB) does not fit one " + ci.backend +
                    " storage buffer; use --device cpu");
    GlTimings t;
    auto t0 = Clock::now();
    uploadBuffer(kParams, GL_UNIFORM_BUFFER, &p, sizeof(p));
    uploadBuffer(kSignalIn, GL_SHADER_STORAGE_BUFFER, pyramid, bytes);
    uploadBuffer(kSignalOut, GL_SHADER_STORAGE_BUFFER, nullptr, (size_t)p.width * p.height * sizeof(float));
    const Box2i frame{0, 0, p.width, p.height};
    // The receivers' normals always (their hemispheres); the depth for the blur only.
    uploadPlane(kNormal, normal, frame, 3);
    if (blur > 0) uploadPlane(kDepth, depth, frame, 1);
    t.upload += since(t0);
    t0 = Clock::now();
    dispatch("discs", p);
    gl.MemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    blurBuffer(kSignalOut, 1, blur, p);
    gl.MemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    gl.Finish();
    t.compute += since(t0);
    t0 = Clock::now();
    readInner(kSignalOut, 1, frame, frame, ao);
    t.readback += since(t0);
    t.tiles = 1;
    const GLenum err = gl.GetError();
    if (err != GL_NO_ERROR) throw Error("OpenGL error " + hex(err) + " on " + ci.backend);
    if (timings) *timings = t;
}

void GlBackend::requireEveryBinding(const char* what) const {
    if (info().maxStorageBindings < kBindings)
        throw Error(info().backend + " offers " + std::to_string(info().maxStorageBindings) + " storage buffer bindings; " +
                    what + " needs " + std::to_string(kBindings) + "; use --device cpu");
}

void GlBackend::runSsdo(const glsl::KernelParams& p, const SsdoInputs& in, MutablePlane directional, MutablePlane indirect,
                        MutablePlane ao, int blur, GlTimings* timings) {
    requireEveryBinding("ssdo");
    GlTimings t;
    // GI's blur is wider, within a share of r_max across the surface (kernel_params.glsl).
    const int giBlur = p.bounce ? glsl::SSDO_GI_BLUR_SCALE * blur : 0;
    runTiled(
        p, in.depth, in.normal, ConstPlane{}, std::max(blur, giBlur), 0, t,
        [&](const Box2i& buf, const glsl::KernelParams& q) {
            const size_t texels = (size_t)buf.width() * buf.height();
            // An input left out still gets a (small) buffer: every binding the program declares must hold one.
            uploadPlaneOrStub(kRadiance, in.radiance, q.bounce != 0, buf, 3);
            uploadPlaneOrStub(kAlbedo, in.albedo, in.albedo.valid(), buf, 3);
            uploadPlaneOrStub(kEnv, in.environment, in.environment.valid(),
                              Box2i{0, 0, in.environment.width, in.environment.height}, 3);
            uploadBuffer(kSignalOut, GL_SHADER_STORAGE_BUFFER, nullptr, texels * sizeof(float));
            uploadBuffer(kDirectional, GL_SHADER_STORAGE_BUFFER, nullptr, texels * 3 * sizeof(float));
            uploadBuffer(kIndirect, GL_SHADER_STORAGE_BUFFER, nullptr, texels * 3 * sizeof(float));
        },
        [&](const glsl::KernelParams& q) {
            const GlApi& gl = context_->gl();
            const GLuint program = programs_.at("ssdo");
            gl.UseProgram(program);
            gl.Uniform1i(gl.GetUniformLocation(program, "hasAlbedo"), in.albedo.valid() ? 1 : 0);
            dispatch("ssdo", q);
            blurBuffer(kDirectional, 3, blur, q);
            blurBuffer(kSignalOut, 1, blur, q);
            if (q.bounce) blurBuffer(kIndirect, 3, giBlur, q);
        },
        [&](const Box2i& inner, const Box2i& buf) {
            readInner(kDirectional, 3, inner, buf, directional);
            if (p.bounce) readInner(kIndirect, 3, inner, buf, indirect);
            readInner(kSignalOut, 1, inner, buf, ao);
        });
    if (timings) *timings = t;
}

void GlBackend::runHbaoGi(const glsl::KernelParams& p, ConstPlane depth, ConstPlane normal, ConstPlane deep,
                          ConstPlane radiance, ConstPlane facing, MutablePlane ao, MutablePlane gi, int blur,
                          GlTimings* timings, long long maxTexels) {
    requireEveryBinding("hbao's GI");
    GlTimings t;
    runTiled(
        p, depth, normal, deep, blur, maxTexels, t,
        [&](const Box2i& buf, const glsl::KernelParams& q) {
            const size_t texels = (size_t)buf.width() * buf.height();
            // With deep input the radiance has a word per layer. The normals' words (the light per
            // run reads them) come through the albedo binding, which the light does not otherwise
            // read (the source has the albedo applied).
            uploadPlane(kRadiance, radiance, buf, deep.valid() ? q.deepLayers : 1);
            uploadPlaneOrStub(kAlbedo, facing, facing.valid(), buf, 1);
            uploadBuffer(kSignalOut, GL_SHADER_STORAGE_BUFFER, nullptr, texels * sizeof(float));
            uploadBuffer(kIndirect, GL_SHADER_STORAGE_BUFFER, nullptr, texels * 3 * sizeof(float));
        },
        [&](const glsl::KernelParams& q) {
            dispatch("hbao_gi", q);
            blurBuffer(kIndirect, 3, blur, q);
            blurBuffer(kSignalOut, 1, blur, q);
        },
        [&](const Box2i& inner, const Box2i& buf) {
            readInner(kIndirect, 3, inner, buf, gi);
            readInner(kSignalOut, 1, inner, buf, ao);
        });
    if (timings) *timings = t;
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
        throw Error("unknown GL device '" + device + "'");
    }
    return *slot;
}

} // namespace obscura::gpu
