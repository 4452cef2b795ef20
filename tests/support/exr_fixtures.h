// Synthetic EXR files for tests: any channel names, single/multi-part, scanline/tiled,
// half/float/uint, data window != display window, plus truncated copies.
#pragma once
#include <OpenEXR/ImfCompression.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfLineOrder.h>
#include <OpenEXR/ImfPixelType.h>
#include <OpenEXR/ImfTileDescription.h>
#include <Imath/ImathBox.h>

#include <cstddef>
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace obscura::fixtures {

struct FixtureChannel {
    std::string name;
    Imf::PixelType type = Imf::FLOAT;
    int xSampling = 1, ySampling = 1;
    // Value at EXR pixel coords (x, y); defaults to patternValue(name, x, y).
    std::function<float(int x, int y)> value;
};

struct FixturePart {
    std::string name;                  // required for multipart files
    std::vector<FixtureChannel> channels;
    Imath::Box2i displayWindow{Imath::V2i(0, 0), Imath::V2i(15, 11)};
    Imath::Box2i dataWindow{Imath::V2i(0, 0), Imath::V2i(15, 11)};
    Imf::Compression compression = Imf::ZIP_COMPRESSION;
    Imf::LineOrder lineOrder = Imf::INCREASING_Y;
    bool tiled = false;
    int tileWidth = 8, tileHeight = 8;
    Imf::LevelMode levelMode = Imf::ONE_LEVEL;  // MIPMAP_LEVELS writes every level
    std::map<std::string, std::string> stringAttributes;
    std::map<std::string, float> floatAttributes;
    std::function<void(Imf::Header&)> editHeader;  // any other attribute (matrices, chromaticities, ...)
};

// Deterministic value, exact in half precision (multiples of 1/8 below 32), distinct per name.
float patternValue(const std::string& channel, int x, int y);
// The value a fixture channel holds at (x, y) as stored (rounded to its pixel type).
float storedValue(const FixtureChannel& ch, int x, int y);

// Writes `parts`: one part gives a single-part file, several a multipart file.
void writeFixture(const std::string& path, const std::vector<FixturePart>& parts);

// Convenience: one scanline float part holding `channels` (all FLOAT) over w x h.
void writeSimple(const std::string& path, const std::vector<std::string>& channels, int w = 16, int h = 12,
                 const std::map<std::string, std::string>& stringAttributes = {});

// Copies the first `keepBytes` bytes of src to dst.
void truncatedCopy(const std::string& src, const std::string& dst, std::size_t keepBytes);
std::size_t fileSize(const std::string& path);

} // namespace obscura::fixtures
