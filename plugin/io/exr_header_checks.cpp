// What is checked of an EXR before OpenEXR's reader allocates anything for it: each window
// against --max-pixels and against the bytes the file has, and each part's decoded size
// against what its codec can possibly expand to.
#include "io/exr_file.h"

#include "base/error.h"

#include <OpenEXR/openexr.h>

#include <climits>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

namespace fs = std::filesystem;

namespace obscura {

void checkWindow(const std::string& path, const char* which, const Imath::Box2i& w, long long maxPixels,
                 long long minFileBytes, long long fileBytes) {
    const long long width = (long long)w.max.x - w.min.x + 1, height = (long long)w.max.y - w.min.y + 1;
    auto fail = [&](const std::string& why) {
        throw FileError(path, std::string(which) + " window [" + std::to_string(w.min.x) + "," + std::to_string(w.min.y) +
                    " - " + std::to_string(w.max.x) + "," + std::to_string(w.max.y) + "] " + why);
    };
    if (width <= 0 || height <= 0) fail("is empty or inverted");
    if (width > INT32_MAX || height > INT32_MAX || width * height > maxPixels)
        fail("holds " + std::to_string(width) + " x " + std::to_string(height) + " pixels, more than the limit of " +
             std::to_string(maxPixels) + " (--max-pixels)");
    if (fileBytes >= 0 && minFileBytes > fileBytes)
        fail("needs at least " + std::to_string(minFileBytes) + " bytes of chunk table, but the file has " +
             std::to_string(fileBytes));
}

namespace {

// The most a codec can shrink pixel data (decoded bytes per stored byte), from how each works:
// RLE stores a run of at most 127 bytes in 2; deflate (ZIP, ZIPS) gains at most 1032:1; PIZ's
// Huffman stage codes a run of at most 256 values in no fewer than 10 bits (measured: 402:1 on
// zeros), bounded here by deflate's 1032; PXR24 first drops a float to 24 bits, then deflates;
// B44 stores a 4x4 block of halves in at least 3 bytes; DWA keeps one deflated DC value and at
// least one deflated or Huffman-coded AC end code per 8x8 block (64 floats in >= 4/1032 bytes).
// Zero-filled 2048^2 files measure below each: 60 (RLE), 954 (ZIP), 1241 (PXR24), 10.7 (B44A),
// 3456 (DWAB).
double maxCompressionRatio(exr_compression_t c) {
    switch (c) {
    case EXR_COMPRESSION_NONE: return 1;
    case EXR_COMPRESSION_RLE: return 64;
    case EXR_COMPRESSION_ZIPS:
    case EXR_COMPRESSION_ZIP:
    case EXR_COMPRESSION_PIZ: return 1032;
    case EXR_COMPRESSION_PXR24: return 1032 * 4.0 / 3.0;
    case EXR_COMPRESSION_B44:
    case EXR_COMPRESSION_B44A: return 32.0 / 3.0;
    default: return 64 * 1032.0;  // DWAA, DWAB (and any later codec): 256 bytes in 4/1032
    }
}

// Bytes the channels of `chlist` decode to over `data` (level 0), or -1 if a sampling is invalid
// (left to the C++ API to report).
double decodedBytes(const exr_attr_chlist_t* chlist, const exr_attr_box2i_t& data) {
    double bytes = 0;
    for (int c = 0; c < chlist->num_channels; ++c) {
        const exr_attr_chlist_entry_t& e = chlist->entries[c];
        if (e.x_sampling < 1 || e.y_sampling < 1) return -1;
        const double nx = sampleCount(data.min.x, (int)std::min<long long>(INT_MAX, data.max.x + 1LL), e.x_sampling);
        const double ny = sampleCount(data.min.y, (int)std::min<long long>(INT_MAX, data.max.y + 1LL), e.y_sampling);
        bytes += std::max(0.0, nx) * std::max(0.0, ny) * (e.pixel_type == EXR_PIXEL_HALF ? 2 : 4);
    }
    return bytes;
}


} // namespace

void checkAttributeSizes(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    std::error_code ec;
    const long long fileBytes = (long long)fs::file_size(path, ec);
    unsigned char version[8];
    if (ec || !f.read(reinterpret_cast<char*>(version), 8)) return;
    const bool multipart = (version[5] & 0x10) != 0;
    auto readName = [&](std::string& out) {
        out.clear();
        for (char c; f.get(c);) {
            if (c == 0) return true;
            if (out.size() >= 255) return false;
            out.push_back(c);
        }
        return false;
    };
    std::string name, type;
    for (;;) {
        if (!readName(name)) return;
        if (name.empty()) {  // end of a header; a multipart file ends its list with an empty one
            if (!multipart || f.peek() == 0) return;
            continue;
        }
        int32_t size = 0;
        if (!readName(type) || !f.read(reinterpret_cast<char*>(&size), 4)) return;
        const long long end = (long long)f.tellg() + size;
        if (size < 0 || end > fileBytes)
            throw FileError(path, "truncated or corrupt: attribute '" + name + "' claims " + std::to_string(size) +
                                      " bytes, past the end of the file (" + std::to_string(fileBytes) + " bytes)");
        f.seekg(end);
    }
}

// The windows, from the header alone: OpenEXR's core API reads no chunk table, where the C++
// API sizes and reads one from the windows as it opens a file. A header the core API refuses
// is left to the C++ API to report.
void checkWindowsBeforeOpening(const std::string& path, long long maxPixels) {
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = [](exr_const_context_t, exr_result_t, const char*) {};
    exr_context_t ctx = nullptr;
    const bool opened = exr_start_read(&ctx, path.c_str(), &init) == EXR_ERR_SUCCESS;
    struct Finish {
        exr_context_t* ctx;
        ~Finish() { exr_finish(ctx); }
    } finish{&ctx};
    if (!opened) return;
    std::error_code ec;
    const long long fileBytes = (long long)fs::file_size(path, ec);
    int parts = 0;
    if (exr_get_count(ctx, &parts) != EXR_ERR_SUCCESS) return;
    auto box = [](const exr_attr_box2i_t& b) { return Imath::Box2i(Imath::V2i(b.min.x, b.min.y), Imath::V2i(b.max.x, b.max.y)); };
    double storedAtLeast = 0;  // bytes the parts' pixels need in the file, at their codecs' best
    for (int p = 0; p < parts; ++p) {
        exr_attr_box2i_t data, display;
        int32_t chunks = 0;
        if (exr_get_data_window(ctx, p, &data) != EXR_ERR_SUCCESS ||
            exr_get_display_window(ctx, p, &display) != EXR_ERR_SUCCESS)
            return;
        if (exr_get_chunk_count(ctx, p, &chunks) != EXR_ERR_SUCCESS) chunks = 0;
        // Every chunk has an 8-byte entry in the offset table: a lower bound on the file size.
        checkWindow(path, "data", box(data), maxPixels, 8LL * chunks, ec ? -1 : fileBytes);
        checkWindow(path, "display", box(display), maxPixels);

        // A window the file is too small to hold, however well compressed: refused before the
        // readers allocate what the header claims.
        exr_storage_t storage;
        exr_compression_t codec;
        const exr_attr_chlist_t* chlist = nullptr;
        if (ec || exr_get_storage(ctx, p, &storage) != EXR_ERR_SUCCESS ||
            (storage != EXR_STORAGE_SCANLINE && storage != EXR_STORAGE_TILED) ||
            exr_get_compression(ctx, p, &codec) != EXR_ERR_SUCCESS ||
            exr_get_channels(ctx, p, &chlist) != EXR_ERR_SUCCESS || !chlist)
            continue;
        const double bytes = decodedBytes(chlist, data);
        if (bytes < 0) continue;
        storedAtLeast += bytes / maxCompressionRatio(codec);
        if (storedAtLeast > (double)fileBytes) {
            char ratio[32];
            std::snprintf(ratio, sizeof ratio, "%.0f", maxCompressionRatio(codec));
            const Imath::Box2i w = box(data);
            throw FileError(path, "data window [" + std::to_string(w.min.x) + "," + std::to_string(w.min.y) + " - " +
                                      std::to_string(w.max.x) + "," + std::to_string(w.max.y) + "] decodes to " +
                                      std::to_string((long long)bytes) + " bytes, more than the file's " +
                                      std::to_string(fileBytes) + " bytes can hold (its codec shrinks data " +
                                      ratio + ":1 at most)");
        }
    }
}

} // namespace obscura
