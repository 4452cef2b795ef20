#include "support/read_back.h"

#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputPart.h>
#include <OpenEXR/ImfMultiPartInputFile.h>
#include <OpenEXR/ImfTiledInputPart.h>

#include <cmath>
#include <fstream>

namespace obscura::test {

void readPart(Imf::MultiPartInputFile& file, int part, const Imf::FrameBuffer& fb) {
    if (file.header(part).hasTileDescription()) {
        Imf::TiledInputPart in(file, part);
        in.setFrameBuffer(fb);
        in.readTiles(0, in.numXTiles(0) - 1, 0, in.numYTiles(0) - 1, 0, 0);
        return;
    }
    Imf::InputPart in(file, part);
    const Imath::Box2i dw = in.header().dataWindow();
    in.setFrameBuffer(fb);
    in.readPixels(dw.min.y, dw.max.y);
}

double meanOver(const std::vector<float>& v, const std::vector<bool>& on) {
    double sum = 0;
    int n = 0;
    for (size_t i = 0; i < v.size(); ++i)
        if (on[i]) sum += v[i], ++n;
    return n ? sum / n : NAN;
}

std::vector<float> partChannel(const std::string& path, int part, const std::string& name) {
    Imf::MultiPartInputFile file(path.c_str());
    const Imf::Header& h = file.header(part);
    const Imath::Box2i dw = h.dataWindow();
    std::vector<float> v((size_t)(dw.max.x - dw.min.x + 1) * (dw.max.y - dw.min.y + 1), -1.0f);
    Imf::FrameBuffer fb;
    fb.insert(name, Imf::Slice::Make(Imf::FLOAT, v.data(), dw));
    readPart(file, part, fb);
    return v;
}

nlohmann::json readJson(const std::filesystem::path& path) {
    std::ifstream f(path);
    return nlohmann::json::parse(f);
}

} // namespace obscura::test
