// Compute programs assembled from embedded kernel texts, with compile errors
// reported by kernel and file:line.
#pragma once
#include "gpu/gl_api.h"

#include <string>
#include <vector>

namespace obscura::gpu {

struct ShaderPart {
    std::string name;  // file name, for error messages
    std::string text;
    int firstLine = 1; // the text's first line in that file
};

// GLSL 4.30 core compute program of `parts` in order. Each part is numbered
// with its own #line range (from its firstLine), so an error maps back to its file and line. Throws obscura::Error
// "GLSL error in kernel 'hbao', hbao.glsl:42: <compiler message>".
GLuint buildComputeProgram(const GlApi& gl, const std::string& kernel, const std::vector<ShaderPart>& parts);

} // namespace obscura::gpu
