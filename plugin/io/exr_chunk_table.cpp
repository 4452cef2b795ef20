#include "io/exr_chunk_table.h"

#include "base/error.h"

#include <OpenEXR/ImfDeepScanLineInputPart.h>
#include <OpenEXR/ImfDeepScanLineOutputPart.h>
#include <OpenEXR/ImfDeepTiledInputPart.h>
#include <OpenEXR/ImfDeepTiledOutputPart.h>
#include <OpenEXR/ImfInputPart.h>
#include <OpenEXR/ImfIntAttribute.h>
#include <OpenEXR/ImfMultiPartInputFile.h>
#include <OpenEXR/ImfMultiPartOutputFile.h>
#include <OpenEXR/ImfOutputPart.h>
#include <OpenEXR/ImfPartType.h>
#include <OpenEXR/ImfTileDescription.h>
#include <OpenEXR/ImfTiledInputPart.h>
#include <OpenEXR/ImfTiledOutputPart.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>

namespace obscura {
namespace {

// Where a chunk table entry should lead: a block of lines from y, or tile (x, y) of level (lx, ly).
struct ChunkKey {
    int x = 0, y = 0, lx = 0, ly = 0;
    bool operator==(const ChunkKey& o) const { return x == o.x && y == o.y && lx == o.lx && ly == o.ly; }
};

// Scanlines per chunk, fixed per codec by the file format.
int linesPerChunk(Imf::Compression c) {
    switch (c) {
    case Imf::ZIP_COMPRESSION:
    case Imf::PXR24_COMPRESSION: return 16;
    case Imf::PIZ_COMPRESSION:
    case Imf::B44_COMPRESSION:
    case Imf::B44A_COMPRESSION:
    case Imf::DWAA_COMPRESSION: return 32;
    case Imf::DWAB_COMPRESSION: return 256;
    default: return 1;
    }
}

int roundLog2(int x, Imf::LevelRoundingMode mode) {
    int y = 0;
    if (mode == Imf::ROUND_DOWN)
        for (; x > 1; x >>= 1) ++y;
    else
        for (long long n = 1; n < x; n <<= 1) ++y;
    return y;
}

int levelSize(int size, int level, Imf::LevelRoundingMode mode) {
    const long long b = 1LL << level;
    long long s = size / b;
    if (mode == Imf::ROUND_UP && s * b < size) ++s;
    return (int)std::max(s, 1LL);
}

// Every chunk of a tiled part in table order: levels (rip-maps: y level outer), rows, columns;
// at most `limit` + 1 of them.
std::vector<ChunkKey> tileChunks(const Imf::TileDescription& td, int w, int h, size_t limit) {
    const Imf::LevelRoundingMode r = td.roundingMode;
    int levelsX = 1, levelsY = 1;
    if (td.mode == Imf::MIPMAP_LEVELS) levelsX = levelsY = roundLog2(std::max(w, h), r) + 1;
    if (td.mode == Imf::RIPMAP_LEVELS) levelsX = roundLog2(w, r) + 1, levelsY = roundLog2(h, r) + 1;
    std::vector<ChunkKey> keys;
    for (int ly = 0; ly < levelsY; ++ly)
        for (int lx = 0; lx < levelsX; ++lx) {
            if (td.mode != Imf::RIPMAP_LEVELS && lx != ly) continue;
            // In 64 bits: a header may give a tile size up to 2^31 - 1 (a fuzzer's did).
            const long long tileW = std::max<long long>(td.xSize, 1), tileH = std::max<long long>(td.ySize, 1);
            const int nx = (int)((levelSize(w, lx, r) + tileW - 1) / tileW);
            const int ny = (int)((levelSize(h, ly, r) + tileH - 1) / tileH);
            for (int ty = 0; ty < ny && keys.size() <= limit; ++ty)
                for (int tx = 0; tx < nx && keys.size() <= limit; ++tx) keys.push_back({tx, ty, lx, ly});
        }
    return keys;
}

// The chunks a part's windows make, in table order; more than `limit` when the file cannot
// hold their table (each entry takes 8 bytes).
std::vector<ChunkKey> expectedChunks(const Imf::Header& h, bool tiled, size_t limit) {
    const Imath::Box2i& dw = h.dataWindow();
    const int w = dw.max.x - dw.min.x + 1, height = dw.max.y - dw.min.y + 1;
    if (tiled) return tileChunks(h.tileDescription(), w, height, limit);
    std::vector<ChunkKey> keys;
    const int lines = linesPerChunk(h.compression());
    for (long long y = dw.min.y; y <= dw.max.y; y += lines) keys.push_back({0, (int)y, 0, 0});
    return keys;
}

std::string keyText(const ChunkKey& k, bool tiled) {
    if (!tiled) return "lines from " + std::to_string(k.y);
    return "tile (" + std::to_string(k.x) + "," + std::to_string(k.y) + ") of level (" + std::to_string(k.lx) + "," +
           std::to_string(k.ly) + ")";
}

// The byte after the last header: where the chunk tables begin; -1 when the headers do not end.
long long headersEnd(std::ifstream& f, bool multipart) {
    f.seekg(8);
    auto skipString = [&] {  // false at the end of the file
        for (char c; f.get(c);)
            if (c == 0) return true;
        return false;
    };
    for (;;) {
        const int next = f.peek();
        if (next == EOF) return -1;
        if (next == 0) {  // an empty name ends a header; in a multipart file, another ends the list
            f.get();
            if (!multipart || f.peek() == 0) {
                if (multipart) f.get();
                return (long long)f.tellg();
            }
            continue;
        }
        int32_t size = 0;
        if (!skipString() || !skipString() || !f.read(reinterpret_cast<char*>(&size), 4) || size < 0) return -1;
        f.seekg(size, std::ios::cur);
    }
}

struct TableReader {
    const std::string& path;
    std::ifstream& f;
    long long fileBytes, tablesEnd;
    bool multipart;

    bool read(long long at, void* out, long long n) {
        if (at < 0 || at + n > fileBytes) return false;
        f.clear();
        f.seekg(at);
        return (bool)f.read(static_cast<char*>(out), n);
    }

    // Part p's table at `at`; returns the byte after it.
    long long checkPart(int p, const ExrPart& part, long long at) {
        const bool deep = part.deep, tiled = part.tiled;
        const std::vector<ChunkKey> keys = expectedChunks(part.header, tiled, (size_t)(fileBytes / 8));
        auto fail = [&](const std::string& why) {
            throw FileError(path, "truncated or corrupt: the chunk table of part " + std::to_string(p) + ": " + why);
        };
        if (keys.size() > (size_t)(fileBytes / 8)) fail("the file is too small to hold it");
        const auto* count = part.header.findTypedAttribute<Imf::IntAttribute>("chunkCount");
        if (count && count->value() != (int)keys.size())
            fail("chunkCount says " + std::to_string(count->value()) + ", the windows make " + std::to_string(keys.size()));
        std::vector<uint64_t> table(keys.size());
        if (!read(at, table.data(), 8LL * (long long)table.size())) fail("it runs past the end of the file");
        for (size_t i = 0; i < keys.size(); ++i) checkChunk(i, (long long)table[i], keys[i], p, deep, tiled, fail);
        return at + 8LL * (long long)table.size();
    }

    template <class Fail>
    void checkChunk(size_t i, long long offset, const ChunkKey& want, int p, bool deep, bool tiled, const Fail& fail) {
        const std::string entry = "entry " + std::to_string(i) + " (" + keyText(want, tiled) + ")";
        if (offset < tablesEnd || offset >= fileBytes)
            fail(entry + " points at byte " + std::to_string((uint64_t)offset) + ", outside the chunks (" +
                 std::to_string(tablesEnd) + " to " + std::to_string(fileBytes) + ")");
        int32_t ints[5] = {};
        const int nInts = (multipart ? 1 : 0) + (tiled ? 4 : 1);
        int64_t sizes[3] = {};  // deep: sample table, packed, unpacked; flat: packed
        if (!read(offset, ints, 4 * nInts) ||
            !read(offset + 4 * nInts, sizes, deep ? 24 : 4))
            fail(entry + ": its chunk runs past the end of the file");
        if (!deep) sizes[0] = (int64_t)(int32_t)(uint32_t)sizes[0];  // one int32
        const int32_t* k = ints + (multipart ? 1 : 0);
        const ChunkKey found = tiled ? ChunkKey{k[0], k[1], k[2], k[3]} : ChunkKey{0, k[0], 0, 0};
        if (multipart && ints[0] != p) fail(entry + " leads to a chunk of part " + std::to_string(ints[0]));
        if (!(found == want)) fail(entry + " leads to " + keyText(found, tiled));
        const long long data = offset + 4 * nInts + (deep ? 24 : 4);
        // The stored sizes, each within the file before they are added; deep data's unpacked size
        // may exceed the file's.
        if (sizes[0] < 0 || sizes[0] > fileBytes || sizes[1] < 0 || sizes[1] > fileBytes || sizes[2] < 0 ||
            (deep ? sizes[0] + sizes[1] : sizes[0]) > fileBytes - data)
            fail(entry + ": its chunk's data run past the end of the file");
    }
};

} // namespace

void checkChunkTables(const std::string& path, const ExrInfo& info) {
    std::ifstream f(path, std::ios::binary);
    std::error_code ec;
    const long long fileBytes = (long long)std::filesystem::file_size(path, ec);
    unsigned char version[8] = {};
    if (!f || ec || !f.read(reinterpret_cast<char*>(version), 8)) throw FileError(path, "cannot read its chunk tables");
    const bool multipart = (version[5] & 0x10) != 0;
    const long long tablesStart = headersEnd(f, multipart);
    if (tablesStart < 0) throw FileError(path, "truncated or corrupt: its headers do not end");
    long long tablesEnd = tablesStart;
    for (const ExrPart& part : info.parts)
        tablesEnd += 8LL * (long long)expectedChunks(part.header, part.tiled, (size_t)(fileBytes / 8)).size();
    TableReader reader{path, f, fileBytes, tablesEnd, multipart};
    long long at = tablesStart;
    for (size_t p = 0; p < info.parts.size(); ++p) at = reader.checkPart((int)p, info.parts[p], at);
}

namespace {

template <class In, class Out>
void copyChunks(Imf::MultiPartInputFile& in, Imf::MultiPartOutputFile& out, int p) {
    In from(in, p);
    Out(out, p).copyPixels(from);
}

} // namespace

void copyPartChunks(Imf::MultiPartInputFile& in, Imf::MultiPartOutputFile& out, int p) {
    const std::string& type = out.header(p).type();
    if (type == Imf::TILEDIMAGE) copyChunks<Imf::TiledInputPart, Imf::TiledOutputPart>(in, out, p);
    else if (type == Imf::DEEPSCANLINE) copyChunks<Imf::DeepScanLineInputPart, Imf::DeepScanLineOutputPart>(in, out, p);
    else if (type == Imf::DEEPTILE) copyChunks<Imf::DeepTiledInputPart, Imf::DeepTiledOutputPart>(in, out, p);
    else copyChunks<Imf::InputPart, Imf::OutputPart>(in, out, p);
}

} // namespace obscura
