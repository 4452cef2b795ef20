#include "gpu/gl_program.h"

#include "core/error.h"

#include <cctype>
#include <sstream>

namespace obscura::gpu {

namespace {

// First error line of a compiler log, with "<source>:<line>" (Mesa: "2:41(7): error",
// NVIDIA: "2(41) : error") rewritten as "<file>:<line>".
std::string describeLog(const std::string& log, const std::vector<ShaderPart>& parts) {
    std::istringstream in(log);
    std::string line, first;
    while (std::getline(in, line)) {
        if (line.find("rror") == std::string::npos) continue;
        first = line;
        break;
    }
    if (first.empty()) first = log.substr(0, log.find('\n'));
    size_t i = 0;
    while (i < first.size() && std::isspace((unsigned char)first[i])) ++i;
    size_t j = i;
    while (j < first.size() && std::isdigit((unsigned char)first[j])) ++j;
    if (j == i || j >= first.size() || (first[j] != ':' && first[j] != '(')) return first;
    const int source = std::stoi(first.substr(i, j - i));
    size_t k = j + 1;
    while (k < first.size() && std::isdigit((unsigned char)first[k])) ++k;
    if (k == j + 1 || source < 0 || source >= (int)parts.size()) return first;
    const std::string lineNo = first.substr(j + 1, k - j - 1);
    size_t rest = first.find_first_not_of(")(0123456789 :", k);
    return parts[source].name + ":" + lineNo + ": " + (rest == std::string::npos ? first : first.substr(rest));
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
        source += "#line 1 " + std::to_string(i) + "\n" + parts[i].text + "\n";
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
