#include "gpu/gl_program.h"

#include "base/error.h"

#include <sstream>

namespace obscura::gpu {

namespace {

// Each part's lines are numbered from (index + 1) * kLineBase, so "<source>:<line>" in a log
// maps back to a file whether or not the driver honours #line's source number (Mesa does not).
constexpr long kLineBase = 100000;

// First error line of a compiler log, with its location (Mesa: "0:100041(7): error",
// NVIDIA: "0(100041) : error") rewritten as "<file>:<line>".
std::string describeLog(const std::string& log, const std::vector<ShaderPart>& parts) {
    std::istringstream in(log);
    std::string line, first;
    while (std::getline(in, line)) {
        if (line.find("rror") == std::string::npos) continue;
        first = line;
        break;
    }
    if (first.empty()) first = log.substr(0, log.find('\n'));
    size_t i = first.find_first_of("0123456789");
    if (i == std::string::npos) return first;
    size_t j = first.find_first_not_of("0123456789", i);       // after the source number
    if (j == std::string::npos || (first[j] != ':' && first[j] != '(')) return first;
    const size_t k = first.find_first_not_of("0123456789", j + 1);  // after the line number
    if (k == std::string::npos || k == j + 1) return first;
    const long global = std::stol(first.substr(j + 1, k - j - 1));
    const long part = global / kLineBase - 1;
    if (part < 0 || part >= (long)parts.size()) return first;
    const size_t rest = first.find_first_not_of(")(0123456789 :", k);
    return parts[part].name + ":" + std::to_string(global % kLineBase) + ": " +
           (rest == std::string::npos ? first : first.substr(rest));
}

std::string shaderLog(const GlApi& gl, GLuint shader) {
    GLint len = 0;
    gl.GetShaderiv(shader, GL_INFO_LOG_LENGTH, &len);
    std::string log(len > 0 ? len : 1, '\0');
    gl.GetShaderInfoLog(shader, (GLsizei)log.size(), nullptr, log.data());
    return log;
}

} // namespace

GLuint buildComputeProgram(const GlApi& gl, const std::string& kernel, const std::vector<ShaderPart>& parts) {
    std::string source = "#version 430 core\n";
    for (size_t i = 0; i < parts.size(); ++i)
        source += "#line " + std::to_string((i + 1) * kLineBase + parts[i].firstLine) + " " + std::to_string(i) + "\n" +
                  parts[i].text + "\n";
    const GLuint shader = gl.CreateShader(GL_COMPUTE_SHADER);
    const char* text = source.c_str();
    gl.ShaderSource(shader, 1, &text, nullptr);
    gl.CompileShader(shader);
    GLint ok = 0;
    gl.GetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        const std::string message = describeLog(shaderLog(gl, shader), parts);
        gl.DeleteShader(shader);
        throw Error("GLSL error in kernel '" + kernel + "', " + message);
    }
    const GLuint program = gl.CreateProgram();
    gl.AttachShader(program, shader);
    gl.LinkProgram(program);
    gl.DeleteShader(shader);
    gl.GetProgramiv(program, GL_LINK_STATUS, &ok);
    if (!ok) {
        GLint len = 0;
        gl.GetProgramiv(program, GL_INFO_LOG_LENGTH, &len);
        std::string log(len > 0 ? len : 1, '\0');
        gl.GetProgramInfoLog(program, (GLsizei)log.size(), nullptr, log.data());
        gl.DeleteProgram(program);
        throw Error("GLSL link error in kernel '" + kernel + "': " + log.substr(0, log.find('\n')));
    }
    return program;
}

} // namespace obscura::gpu
