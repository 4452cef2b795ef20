// How the GL backend assembles kernel texts (gpu/gl_program.h, gpu/gl_backend.cpp): a part taken
// from the middle of a file (the text after an #include line) keeps that file's line numbers.
#include "base/error.h"
#include "gpu/gl_context.h"
#include "gpu/gl_program.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

using namespace obscura;

TEST(GlKernels, PartsKeepTheirFilesLineNumbers) {
    auto context = gpu::GlContext::create(gpu::ContextKind::OSMesa);
    const std::vector<gpu::ShaderPart> parts = {
        {"skeleton.glsl", "layout(local_size_x = 1) in;\n", 1},
        {"model.glsl", "float ok() { return 1.0f; }\n", 1},
        // The skeleton again from its line 40, after the include on line 39.
        {"skeleton.glsl", "\n\nvoid main() { float x = notDeclared(2.0f); }\n", 40}};
    try {
        gpu::buildComputeProgram(context->gl(), "assembled", parts);
        FAIL() << "a broken shader compiled";
    } catch (const Error& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("skeleton.glsl:42"), std::string::npos) << m;
    }
}
