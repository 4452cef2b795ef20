// How the GL backend assembles kernel texts (gpu/gl_program.h, gpu/gl_backend.cpp): a shader that
// does not compile is one line naming the kernel and the file:line of the error, and a part taken
// from the middle of a file (the text after an #include line) keeps that file's line numbers.
#include "base/error.h"
#include "gpu/gl_context.h"
#include "gpu/gl_program.h"
#include "support/gl_devices.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

using namespace obscura;

namespace {

// The message building `parts` as kernel `name` fails with ("" if it compiled).
std::string compileError(const char* name, const std::vector<gpu::ShaderPart>& parts) {
    // Each driver words its compiler log its own way (Mesa "0:3(25)", NVIDIA "0(3)").
    const bool egl = obscura::test::firstGlDevice() == "gl-egl";
    auto context = gpu::GlContext::create(egl ? gpu::ContextKind::EglDevice : gpu::ContextKind::OSMesa);
    try {
        gpu::buildComputeProgram(context->gl(), name, parts);
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

} // namespace

TEST(GlKernels, ShaderErrorsNameKernelFileAndLine) {
    const std::string m = compileError("broken", {{"first.glsl", "layout(local_size_x = 1) in;\nfloat ok() { return 1.0f; }\n"},
                                                  {"second.glsl", "\n\nvoid main() { float x = notDeclared(2.0f); }\n"}});
    ASSERT_FALSE(m.empty()) << "a broken shader compiled";
    EXPECT_NE(m.find("kernel 'broken'"), std::string::npos) << m;
    EXPECT_NE(m.find("second.glsl:3"), std::string::npos) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
}

TEST(GlKernels, PartsKeepTheirFilesLineNumbers) {
    const std::string m = compileError("assembled",
                                       {{"skeleton.glsl", "layout(local_size_x = 1) in;\n", 1},
                                        {"model.glsl", "float ok() { return 1.0f; }\n", 1},
                                        // The skeleton again from its line 40, after the include on line 39.
                                        {"skeleton.glsl", "\n\nvoid main() { float x = notDeclared(2.0f); }\n", 40}});
    ASSERT_FALSE(m.empty()) << "a broken shader compiled";
    EXPECT_NE(m.find("skeleton.glsl:42"), std::string::npos) << m;
}
