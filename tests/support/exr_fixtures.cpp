#include "support/exr_fixtures.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFloatAttribute.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfMultiPartOutputFile.h>
#include <OpenEXR/ImfOutputPart.h>
#include <OpenEXR/ImfPartType.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <OpenEXR/ImfTiledOutputPart.h>
#include <Imath/half.h>

#include <cstring>
#include <fstream>
#include <stdexcept>

namespace obscura::fixtures {
namespace {

int floorDiv(int a, int b) { return a >= 0 ? a / b : -((-a + b - 1) / b); }
int samples(int lo, int hi, int s) { return floorDiv(hi, s) - floorDiv(lo + s - 1, s) + 1; }  // inclusive lo..hi

size_t bps(Imf::PixelType t) { return t == Imf::HALF ? 2 : 4; }

// Fills a tightly packed buffer of `ch` over window `w` and returns its slice.
Imf::Slice fill(const FixtureChannel& ch, const Imath::Box2i& w, std::vector<char>& buf) {
    int nx = samples(w.min.x, w.max.x, ch.xSampling), ny = samples(w.min.y, w.max.y, ch.ySampling);
    size_t b = bps(ch.type);
    buf.assign((size_t)nx * ny * b, 0);
    int x0 = floorDiv(w.min.x + ch.xSampling - 1, ch.xSampling), y0 = floorDiv(w.min.y + ch.ySampling - 1, ch.ySampling);
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
            float v = storedValue(ch, (x0 + i) * ch.xSampling, (y0 + j) * ch.ySampling);
            char* p = buf.data() + ((size_t)j * nx + i) * b;
            if (ch.type == Imf::HALF) { half h(v); std::memcpy(p, &h, 2); }
            else if (ch.type == Imf::UINT) { unsigned u = (unsigned)v; std::memcpy(p, &u, 4); }
            else std::memcpy(p, &v, 4);
        }
    return Imf::Slice::Make(ch.type, buf.data(), w, b, b * nx, ch.xSampling, ch.ySampling);
}

Imf::Header makeHeader(const FixturePart& part, bool multipart) {
    Imf::Header h(part.displayWindow, part.dataWindow, 1.0f, Imath::V2f(0, 0), 1.0f, part.lineOrder,
                  part.compression);
    for (const FixtureChannel& ch : part.channels)
        h.channels().insert(ch.name, Imf::Channel(ch.type, ch.xSampling, ch.ySampling));
    if (part.tiled) {
        h.setTileDescription(Imf::TileDescription(part.tileWidth, part.tileHeight, part.levelMode));
        h.setType(Imf::TILEDIMAGE);
    } else {
        h.setType(Imf::SCANLINEIMAGE);
    }
    if (multipart || !part.name.empty()) h.setName(part.name.empty() ? "part" : part.name);
    for (const auto& [k, v] : part.stringAttributes) h.insert(k, Imf::StringAttribute(v));
    for (const auto& [k, v] : part.floatAttributes) h.insert(k, Imf::FloatAttribute(v));
    if (part.editHeader) part.editHeader(h);
    return h;
}

} // namespace

float patternValue(const std::string& channel, int x, int y) {
    unsigned seed = 0;
    for (char c : channel) seed = seed * 31 + (unsigned char)c;
    int v = (int)((unsigned)(x * 7 + y * 13 + 1000) + seed) % 251;
    return (v - 100) / 8.0f;  // negative values too; exact in half
}

float storedValue(const FixtureChannel& ch, int x, int y) {
    float v = ch.value ? ch.value(x, y) : patternValue(ch.name, x, y);
    if (ch.type == Imf::HALF) return float(half(v));
    if (ch.type == Imf::UINT) return float((unsigned)(v < 0 ? -v : v));
    return v;
}

void writeFixture(const std::string& path, const std::vector<FixturePart>& parts) {
    bool multipart = parts.size() > 1;
    std::vector<Imf::Header> headers;
    for (const FixturePart& p : parts) headers.push_back(makeHeader(p, multipart));
    Imf::MultiPartOutputFile file(path.c_str(), headers.data(), (int)headers.size());
    for (size_t p = 0; p < parts.size(); ++p) {
        const FixturePart& part = parts[p];
        std::vector<std::vector<char>> bufs(part.channels.size());
        if (!part.tiled) {
            Imf::FrameBuffer fb;
            for (size_t c = 0; c < part.channels.size(); ++c)
                fb.insert(part.channels[c].name, fill(part.channels[c], part.dataWindow, bufs[c]));
            Imf::OutputPart out(file, (int)p);
            out.setFrameBuffer(fb);
            out.writePixels(part.dataWindow.max.y - part.dataWindow.min.y + 1);
            continue;
        }
        Imf::TiledOutputPart out(file, (int)p);
        int levels = part.levelMode == Imf::ONE_LEVEL ? 1 : out.numLevels();
        for (int l = 0; l < levels; ++l) {
            Imath::Box2i w = out.dataWindowForLevel(l, l);
            Imf::FrameBuffer fb;
            for (size_t c = 0; c < part.channels.size(); ++c)
                fb.insert(part.channels[c].name, fill(part.channels[c], w, bufs[c]));
            out.setFrameBuffer(fb);
            out.writeTiles(0, out.numXTiles(l) - 1, 0, out.numYTiles(l) - 1, l, l);
        }
    }
}

void writeSimple(const std::string& path, const std::vector<std::string>& channels, int w, int h,
                 const std::map<std::string, std::string>& stringAttributes) {
    FixturePart part;
    part.displayWindow = part.dataWindow = Imath::Box2i(Imath::V2i(0, 0), Imath::V2i(w - 1, h - 1));
    for (const std::string& c : channels) part.channels.push_back({c, Imf::FLOAT, 1, 1, {}});
    part.stringAttributes = stringAttributes;
    writeFixture(path, {part});
}

void truncatedCopy(const std::string& src, const std::string& dst, std::size_t keepBytes) {
    std::ifstream in(src, std::ios::binary);
    if (!in) throw std::runtime_error("truncatedCopy: cannot read " + src);
    std::vector<char> data(keepBytes);
    in.read(data.data(), (std::streamsize)keepBytes);
    std::ofstream out(dst, std::ios::binary | std::ios::trunc);
    out.write(data.data(), in.gcount());
}

std::size_t fileSize(const std::string& path) {
    std::ifstream in(path, std::ios::binary | std::ios::ate);
    return in ? (std::size_t)in.tellg() : 0;
}

} // namespace obscura::fixtures
