#include "support/read_back.h"

#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputPart.h>
#include <OpenEXR/ImfMultiPartInputFile.h>

#include <fstream>

namespace obscura::test {

std::vector<float> partChannel(const std::string& path, int part, const std::string& name) {
    Imf::MultiPartInputFile file(path.c_str());
    Imf::InputPart in(file, part);
    const Imath::Box2i dw = in.header().dataWindow();
    std::vector<float> v((size_t)(dw.max.x - dw.min.x + 1) * (dw.max.y - dw.min.y + 1), -1.0f);
    Imf::FrameBuffer fb;
    fb.insert(name, Imf::Slice::Make(Imf::FLOAT, v.data(), dw));
    in.setFrameBuffer(fb);
    in.readPixels(dw.min.y, dw.max.y);
    return v;
}

nlohmann::json readJson(const std::filesystem::path& path) {
    std::ifstream f(path);
    return nlohmann::json::parse(f);
}

} // namespace obscura::test
