#include "gpu/gl_kernels.h"

#include "base/kernel_params.h"

namespace obscura::gpu {

// Buffer bindings (GlBackend uses the same numbers). A program may use at most 8
// storage blocks (the OpenGL 4.3 minimum); none here uses more.
const char* const kGlBindings = R"glsl(
layout(local_size_x = 8, local_size_y = 8) in;
layout(std140, binding = 0) uniform KernelBlock { KernelParams P; };
layout(std430, binding = 1) readonly buffer DepthBuffer { float depthData[]; };
layout(std430, binding = 2) readonly buffer NormalBuffer { float normalData[]; };
layout(std430, binding = 3) readonly buffer SignalInBuffer { float signalIn[]; };
layout(std430, binding = 4) writeonly buffer SignalOutBuffer { float signalOut[]; };
layout(std430, binding = 5) readonly buffer RadianceBuffer { float radianceData[]; };
layout(std430, binding = 6) readonly buffer AlbedoBuffer { float albedoData[]; };
layout(std430, binding = 7) readonly buffer EnvBuffer { float envData[]; };
layout(std430, binding = 8) writeonly buffer DirectionalBuffer { float directionalOut[]; };
layout(std430, binding = 9) writeonly buffer IndirectBuffer { float indirectOut[]; };
uniform ivec2 blurAxis;
uniform int blurRadius;
uniform int signalChannels;   // channels per texel of signalIn / signalOut (1: AO, 3: DO or GI)
uniform int hasAlbedo;        // 0: albedo 1 (no albedo pass bound)

int texelIndex(ivec2 t) { return t.y * P.width + t.x; }
float loadDepth(ivec2 t) { return depthData[texelIndex(t)]; }
vec3 loadNormal(ivec2 t) {
    int i = 3 * texelIndex(t);
    return vec3(normalData[i], normalData[i + 1], normalData[i + 2]);
}
vec4 loadSignal(ivec2 t) {
    int i = signalChannels * texelIndex(t);
    vec4 v = vec4(signalIn[i], 0.0f, 0.0f, 0.0f);
    for (int c = 1; c < signalChannels; ++c) v[c] = signalIn[i + c];
    return v;
}
void storeSignal(ivec2 t, vec4 v) {
    int i = signalChannels * texelIndex(t);
    for (int c = 0; c < signalChannels; ++c) signalOut[i + c] = v[c];
}
vec3 loadRadiance(ivec2 t) {
    int i = 3 * texelIndex(t);
    return vec3(radianceData[i], radianceData[i + 1], radianceData[i + 2]);
}
vec3 loadAlbedo(ivec2 t) {
    if (hasAlbedo == 0) return vec3(1.0f);
    int i = 3 * texelIndex(t);
    return vec3(albedoData[i], albedoData[i + 1], albedoData[i + 2]);
}
vec3 loadEnv(ivec2 t) {
    int i = 3 * (t.y * P.envWidth + t.x);
    return vec3(envData[i], envData[i + 1], envData[i + 2]);
}
// The lane kernels' loads (kernels/*.glsl): one pixel per thread, 0 where not used (albedo 1).
float gatherDepth(int x, int y, bool use) { return use ? depthData[texelIndex(ivec2(x, y))] : 0.0f; }
// The buffer texel whose display corner is `corner` (HBAO's reads at display corners).
ivec2 bufferTexel(vec2 corner) { return ivec2(int(corner.x) - P.originX, int(corner.y) - P.originY); }
float gatherDepthAtDisplay(vec2 corner, bool use) {
    ivec2 t = bufferTexel(corner);
    return gatherDepth(t.x, t.y, use);
}
vec3 gatherNormal(int x, int y, bool use) { return use ? loadNormal(ivec2(x, y)) : vec3(0.0f); }
// HBAO's edge texels (the CPU tables them once per frame; here they are texels like any other).
float gatherEdgeDepth(vec2 edgeCorner, bool use) { return gatherDepthAtDisplay(edgeCorner, use); }
vec4 gatherEdgeTexel(vec2 edgeCorner, bool use) {
    ivec2 t = bufferTexel(edgeCorner);
    vec3 normal = gatherNormal(t.x, t.y, use);
    return vec4(gatherEdgeDepth(edgeCorner, use), normal);
}
vec3 gatherRadiance(int x, int y, bool use) { return use ? loadRadiance(ivec2(x, y)) : vec3(0.0f); }
// HBAO's indirect light: packed words in the radiance binding (kernels/hbao_gi.glsl), one per texel
// and layer (P.deepLayers of them with deep input, else one); the visible surface's normal's word
// in the albedo binding (which the light does not read: its source has the albedo applied).
uint gatherRadianceBitsAtDisplay(vec2 corner, int layer, bool use) {
    int i = texelIndex(bufferTexel(corner));
    return use ? floatBitsToUint(radianceData[i * max(P.deepLayers, 1) + layer]) : 0u;
}
uint gatherNormalWordAtDisplay(vec2 corner, bool use) {
    int i = texelIndex(bufferTexel(corner));
    return use ? floatBitsToUint(albedoData[i]) : 0u;
}
vec3 gatherAlbedo(int x, int y, bool use) { return use ? loadAlbedo(ivec2(x, y)) : vec3(1.0f); }
vec3 gatherEnv(int x, int y, bool use) { return use ? loadEnv(ivec2(x, y)) : vec3(0.0f); }
vec4 gatherSignal(int x, int y, bool use) { return use ? loadSignal(ivec2(x, y)) : vec4(0.0f); }
// HBAO's deep layers (P.deepLayers (front, back) pairs per texel) come through the signal-in binding.
float gatherDeepAtDisplay(vec2 corner, int c, bool use) {
    int i = texelIndex(bufferTexel(corner));
    return use ? signalIn[i * 2 * P.deepLayers + c] : 0.0f;
}
// Disc AO reads the host's pyramid (a plane per channel, P.discStride apart, cpu/discs_cpu.h)
// through the signal-in binding.
float gatherDisc(int index, int c, bool use) { return use ? signalIn[c * P.discStride + index] : 0.0f; }
bool outsideDispatch(ivec2 t) { return t.x >= P.width || t.y >= P.height; }
)glsl";

namespace {
// HBAO's plan (core/hbao_plan.h): one program per model, so the untaken models leave the march.
std::string hbaoDefines(const glsl::KernelParams& p) {
    return "#define HBAO_MODEL " + std::to_string(p.hbaoModel) + "\n#define HBAO_RUNS " + std::to_string(p.hbaoRuns) +
           "\n";
}
// HBAO with its indirect light: the same plan, and HBAO_GI (kernels/hbao.glsl leaves it 0 for AO alone).
std::string hbaoGiDefines(const glsl::KernelParams& p) { return hbaoDefines(p) + "#define HBAO_GI 1\n"; }
} // namespace

const std::vector<GlKernel>& glKernels() {
    static const std::vector<GlKernel> kernels = {
        {"hbao", "hbao.glsl", "void main() { ivec2 t = ivec2(gl_GlobalInvocationID.xy); if (outsideDispatch(t)) return; signalOut[texelIndex(t)] = hbaoLanes(t.x, t.y); }", hbaoDefines},
        {"hbao_gi", "hbao.glsl", "void main() { ivec2 t = ivec2(gl_GlobalInvocationID.xy); if (outsideDispatch(t)) return; int i = texelIndex(t); signalOut[i] = hbaoLanes(t.x, t.y); for (int c = 0; c < 3; ++c) indirectOut[3 * i + c] = hbaoIrradiance[c]; }", hbaoGiDefines},
        {"ssao", "ssao.glsl", "void main() { ivec2 t = ivec2(gl_GlobalInvocationID.xy); if (outsideDispatch(t)) return; signalOut[texelIndex(t)] = ssaoLanes(t.x, t.y); }"},
        {"discs", "discs.glsl", "void main() { ivec2 t = ivec2(gl_GlobalInvocationID.xy); if (outsideDispatch(t)) return; signalOut[texelIndex(t)] = discsLanes(t.x, t.y); }"},
        {"blur", "blur.glsl", "void main() { ivec2 t = ivec2(gl_GlobalInvocationID.xy); if (outsideDispatch(t)) return; storeSignal(t, blurLanes(t.x, t.y, blurAxis, blurRadius)); }"},
        // Every program holds depth_normal.glsl (GlBackend's constructor); this one runs only it.
        {"depth_normals", "depth_normal.glsl", "void main() { ivec2 t = ivec2(gl_GlobalInvocationID.xy); if (outsideDispatch(t)) return; vec3 n = depthNormalLanes(t.x, t.y); int i = texelIndex(t); for (int c = 0; c < 3; ++c) signalOut[3 * i + c] = n[c]; }"},
        {"ssdo", "ssdo.glsl", "void main() { ivec2 t = ivec2(gl_GlobalInvocationID.xy); if (outsideDispatch(t)) return; vec3 d; vec3 g; float a; ssdoLanes(t.x, t.y, d, g, a); int i = texelIndex(t); signalOut[i] = a; for (int c = 0; c < 3; ++c) { directionalOut[3 * i + c] = d[c]; indirectOut[3 * i + c] = g[c]; } }"},
    };
    return kernels;
}

} // namespace obscura::gpu
