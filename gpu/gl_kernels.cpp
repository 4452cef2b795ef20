#include "gpu/gl_kernels.h"

namespace obscura::gpu {

const char* const kGlBindings = R"glsl(
layout(local_size_x = 8, local_size_y = 8) in;
layout(std140, binding = 0) uniform HbaoBlock { KernelParams P; };
layout(std430, binding = 1) readonly buffer DepthBuffer { float depthData[]; };
layout(std430, binding = 2) readonly buffer NormalBuffer { float normalData[]; };
layout(std430, binding = 3) readonly buffer AoInBuffer { float aoInData[]; };
layout(std430, binding = 4) writeonly buffer AoOutBuffer { float aoOutData[]; };
uniform ivec2 blurAxis;
uniform int blurRadius;

int texelIndex(ivec2 t) { return t.y * P.width + t.x; }
float loadDepth(ivec2 t) { return depthData[texelIndex(t)]; }
vec3 loadNormal(ivec2 t) {
    int i = 3 * texelIndex(t);
    return vec3(normalData[i], normalData[i + 1], normalData[i + 2]);
}
vec4 loadSignal(ivec2 t) { return vec4(aoInData[texelIndex(t)], 0.0f, 0.0f, 0.0f); }
bool outsideDispatch(ivec2 t) { return t.x >= P.width || t.y >= P.height; }
)glsl";

const std::vector<GlKernel>& glKernels() {
    static const std::vector<GlKernel> kernels = {
        {"hbao", "hbao.glsl", "void main() { ivec2 t = ivec2(gl_GlobalInvocationID.xy); if (outsideDispatch(t)) return; aoOutData[texelIndex(t)] = hbaoPixel(t); }"},
        {"blur", "blur.glsl", "void main() { ivec2 t = ivec2(gl_GlobalInvocationID.xy); if (outsideDispatch(t)) return; aoOutData[texelIndex(t)] = blurPixel(t, blurAxis, blurRadius); }"},
    };
    return kernels;
}

} // namespace obscura::gpu
