#include "io/png_file.h"

#include <zlib.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <vector>

namespace obscura {
namespace {

void putU32(std::vector<std::uint8_t>& out, std::uint32_t v) {
    for (int shift = 24; shift >= 0; shift -= 8) out.push_back(static_cast<std::uint8_t>(v >> shift));
}

// A chunk: its data's length, its type, the data, and the CRC-32 of type and data.
void putChunk(std::vector<std::uint8_t>& out, const char type[5], const std::vector<std::uint8_t>& data) {
    putU32(out, static_cast<std::uint32_t>(data.size()));
    const std::size_t typeAt = out.size();
    out.insert(out.end(), type, type + 4);
    out.insert(out.end(), data.begin(), data.end());
    const uLong crc = crc32(0L, out.data() + typeAt, static_cast<uInt>(4 + data.size()));
    putU32(out, static_cast<std::uint32_t>(crc));
}

std::vector<std::uint8_t> u32s(std::initializer_list<std::uint32_t> values) {
    std::vector<std::uint8_t> out;
    for (std::uint32_t v : values) putU32(out, v);
    return out;
}

std::vector<std::uint8_t> text(const std::string& keyword, const std::string& value) {
    std::vector<std::uint8_t> out(keyword.begin(), keyword.end());
    out.push_back(0);
    out.insert(out.end(), value.begin(), value.end());
    return out;
}

// The Paeth predictor: of left, up and up-left, the one nearest left + up - up-left.
int paeth(int a, int b, int c) {
    const int p = a + b - c, pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
    return pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
}

// Row `y` filtered by each of the five filters, keeping the one whose bytes, read as signed,
// sum smallest in magnitude (the specification's suggested heuristic), prefixed by its type.
void putFilteredRow(std::vector<std::uint8_t>& out, const std::uint8_t* row, const std::uint8_t* above, int rowBytes,
                    int bpp) {
    std::vector<std::uint8_t> best, trial(static_cast<std::size_t>(rowBytes) + 1);
    long bestCost = -1;
    for (int type = 0; type < 5; ++type) {
        trial[0] = static_cast<std::uint8_t>(type);
        long cost = 0;
        for (int i = 0; i < rowBytes; ++i) {
            const int a = i >= bpp ? row[i - bpp] : 0, b = above ? above[i] : 0;
            const int c = above && i >= bpp ? above[i - bpp] : 0;
            const int predicted = type == 0 ? 0 : type == 1 ? a : type == 2 ? b : type == 3 ? (a + b) / 2 : paeth(a, b, c);
            const auto v = static_cast<std::uint8_t>(row[i] - predicted);
            trial[i + 1] = v;
            cost += std::abs(static_cast<int>(static_cast<std::int8_t>(v)));
        }
        if (bestCost < 0 || cost < bestCost) best = trial, bestCost = cost;
    }
    out.insert(out.end(), best.begin(), best.end());
}

} // namespace

std::string writePngFile(const std::string& path, int width, int height, int channels, const std::uint8_t* bytes,
                         const std::string& colourSpaceTag) {
    static const std::uint8_t kColourType[5] = {0, 0, 4, 2, 6};  // by channel count
    if (width <= 0 || height <= 0 || channels < 1 || channels > 4) return "cannot encode a PNG of this shape";
    const int rowBytes = width * channels;
    std::vector<std::uint8_t> filtered;
    filtered.reserve(static_cast<std::size_t>(height) * (rowBytes + 1));
    for (int y = 0; y < height; ++y)
        putFilteredRow(filtered, bytes + static_cast<std::size_t>(y) * rowBytes,
                       y ? bytes + static_cast<std::size_t>(y - 1) * rowBytes : nullptr, rowBytes, channels);
    uLongf packedSize = compressBound(static_cast<uLong>(filtered.size()));
    std::vector<std::uint8_t> packed(packedSize);
    if (compress2(packed.data(), &packedSize, filtered.data(), static_cast<uLong>(filtered.size()), 6) != Z_OK)
        return "zlib could not compress the image";
    packed.resize(packedSize);

    std::vector<std::uint8_t> file = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    std::vector<std::uint8_t> header = u32s({static_cast<std::uint32_t>(width), static_cast<std::uint32_t>(height)});
    header.insert(header.end(), {8, kColourType[channels], 0, 0, 0});  // 8 bits, deflate, no interlace
    putChunk(file, "IHDR", header);
    if (colourSpaceTag == "sRGB") {
        // sRGB, perceptual intent, with the gamma and primaries a reader without sRGB support uses.
        putChunk(file, "sRGB", {0});
        putChunk(file, "gAMA", u32s({45455}));
        putChunk(file, "cHRM", u32s({31270, 32900, 64000, 33000, 30000, 60000, 15000, 6000}));
    }
    if (!colourSpaceTag.empty()) putChunk(file, "tEXt", text("oiio:ColorSpace", colourSpaceTag));
    putChunk(file, "tEXt", text("Software", "obscura"));
    // IDAT in pieces: a chunk holds at most 2^31 - 1 bytes, and readers take any split.
    constexpr std::size_t kPiece = std::size_t(1) << 24;
    for (std::size_t at = 0; at < packed.size(); at += kPiece)
        putChunk(file, "IDAT", std::vector<std::uint8_t>(packed.begin() + at,
                                                         packed.begin() + std::min(packed.size(), at + kPiece)));
    putChunk(file, "IEND", {});

    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    if (!out) return std::string("cannot open for writing: ") + std::strerror(errno);
    out.write(reinterpret_cast<const char*>(file.data()), static_cast<std::streamsize>(file.size()));
    out.close();
    if (!out) return "cannot write: the disk may be full";
    return "";
}

} // namespace obscura
