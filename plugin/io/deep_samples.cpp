#include "io/deep_samples.h"

#include "base/error.h"
#include "io/exr_file.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfDeepFrameBuffer.h>
#include <OpenEXR/ImfDeepScanLineInputPart.h>
#include <OpenEXR/ImfDeepTiledInputPart.h>
#include <OpenEXR/ImfMultiPartInputFile.h>
#include <OpenEXR/ImfPartType.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <memory>

namespace obscura {

namespace {

// A deflate stream (ZIP, ZIPS) inflates to at most 1032 times its size, OpenEXR's RLE to about
// 64 times: a file whose sample counts add up to more bytes than that claims samples it cannot hold.
constexpr double kMaxExpansion = 1100.0;

// Rows of a scanline part decoded per call: the pointer tables stay small at any width.
constexpr int kBandRows = 64;

// OpenEXR finds pixel (x, y) at base + x xStride + y yStride: the base that puts pixel (x0, y0)
// at `first`. Integer arithmetic: the base itself may point outside the array.
char* originBase(const void* first, int x0, int y0, size_t xStride, size_t yStride) {
    return reinterpret_cast<char*>(reinterpret_cast<std::intptr_t>(first) - (std::intptr_t)x0 * (std::intptr_t)xStride -
                                   (std::intptr_t)y0 * (std::intptr_t)yStride);
}

// A channel to fill: sample i's value goes to (*values)[i * stride + offset]; the vector grows
// band by band as the counts are read.
struct DeepTarget {
    std::string name;
    std::vector<float>* values;
    size_t offset, stride;  // in floats
};

// Part 0 of a deep file, read in bands of rows: each band's sample counts, then its samples.
class DeepPartReader {
public:
    explicit DeepPartReader(const std::string& path) : path_(path), file_(path.c_str()) {
        const Imf::Header& h = file_.header(0);
        const std::string type = h.hasType() ? h.type() : std::string();
        if (type != Imf::DEEPSCANLINE && type != Imf::DEEPTILE)
            throw FileError(path, "not a deep image (a flat file gives the passes with --flat)");
        dw_ = h.dataWindow();
        width_ = dw_.max.x - dw_.min.x + 1;
        if (type == Imf::DEEPTILE)
            tiled_ = std::make_unique<Imf::DeepTiledInputPart>(file_, 0);
        else
            scan_ = std::make_unique<Imf::DeepScanLineInputPart>(file_, 0);
        for (auto it = h.channels().begin(); it != h.channels().end(); ++it)
            bytesPerSample_ += it.channel().type == Imf::HALF ? 2 : 4;
        std::error_code ec;
        fileBytes_ = (double)std::filesystem::file_size(path, ec);
    }

    const Imf::Header& header() const { return file_.header(0); }

    // The windows alone, from the header.
    void windows(DeepWindows& w) const {
        const Imath::Box2i& display = header().displayWindow();
        w.fullWidth = display.max.x - display.min.x + 1;
        w.fullHeight = display.max.y - display.min.y + 1;
        w.x = dw_.min.x - display.min.x;
        w.y = dw_.min.y - display.min.y;
        w.width = width_;
        w.height = dw_.max.y - dw_.min.y + 1;
    }

    // The windows, every pixel's sample count and every sample of `targets`. OpenEXR's idiom:
    // the frame buffer names each band's table of per-pixel pointers, filled once the band's
    // counts are read and before its samples are.
    void read(DeepWindows& w, const std::vector<DeepTarget>& targets) {
        windows(w);
        w.counts.assign((size_t)w.width * w.height, 0u);
        const int rows = tiled_ ? tiled_->tileYSize() : kBandRows;
        std::vector<std::vector<float*>> pointers(targets.size(), std::vector<float*>((size_t)rows * width_));
        size_t total = 0;
        for (int y0 = dw_.min.y, band = 0; y0 <= dw_.max.y; y0 += rows, ++band) {
            const int y1 = std::min(y0 + rows - 1, dw_.max.y);
            Imf::DeepFrameBuffer fb;
            const size_t countStride = sizeof(unsigned);
            fb.insertSampleCountSlice(Imf::Slice(Imf::UINT, originBase(w.counts.data(), dw_.min.x, dw_.min.y, countStride, countStride * width_),
                                                 countStride, countStride * width_));
            const size_t xStride = sizeof(float*), yStride = xStride * width_;
            for (size_t t = 0; t < targets.size(); ++t)
                fb.insert(targets[t].name, Imf::DeepSlice(Imf::FLOAT, originBase(pointers[t].data(), dw_.min.x, y0, xStride, yStride),
                                                          xStride, yStride, sizeof(float) * targets[t].stride));
            const unsigned* counts = w.counts.data() + (size_t)(y0 - dw_.min.y) * width_;
            const size_t pixels = (size_t)(y1 - y0 + 1) * width_;
            if (tiled_) {
                tiled_->setFrameBuffer(fb);
                tiled_->readPixelSampleCounts(0, tiled_->numXTiles(0) - 1, band, band, 0, 0);
            } else {
                scan_->setFrameBuffer(fb);
                scan_->readPixelSampleCounts(y0, y1);
            }
            const size_t first = total;
            for (size_t p = 0; p < pixels; ++p) total += counts[p];
            checkTotal(total);
            for (size_t t = 0; t < targets.size(); ++t) {
                std::vector<float>& values = *targets[t].values;
                values.resize(std::max(values.size(), total * targets[t].stride));
                fillPointers(pointers[t].data(), counts, pixels, values.data(), first * targets[t].stride + targets[t].offset,
                             targets[t].stride);
            }
            if (tiled_)
                tiled_->readTiles(0, tiled_->numXTiles(0) - 1, band, band, 0, 0);
            else
                scan_->readPixels(y0, y1);
        }
    }

private:
    // Pixel p's first sample at values + at, `at` moving on by stride per sample; none where the
    // pixel has no sample (values may then be empty).
    static void fillPointers(float** out, const unsigned* counts, size_t pixels, float* values, size_t at, size_t stride) {
        for (size_t p = 0; p < pixels; ++p) {
            out[p] = counts[p] ? values + at : nullptr;
            at += counts[p] * stride;
        }
    }

    void checkTotal(size_t total) const {
        if ((double)total * (double)bytesPerSample_ > kMaxExpansion * fileBytes_ + 65536.0)
            throw FileError(path_, "truncated or corrupt: its sample counts claim at least " + std::to_string(total) +
                                       " samples, more than its size can hold");
    }

    std::string path_;
    Imf::MultiPartInputFile file_;
    std::unique_ptr<Imf::DeepScanLineInputPart> scan_;
    std::unique_ptr<Imf::DeepTiledInputPart> tiled_;
    Imath::Box2i dw_;
    int width_ = 0;
    size_t bytesPerSample_ = 0;  // of all channels: what the file stores per sample
    double fileBytes_ = 0.0;
};

// Runs read(), OpenEXR's exceptions made one line naming the file.
template <class Read>
auto readDeepPart(const std::string& path, Read read) {
    checkExrMagic(path);
    checkAttributeSizes(path);
    ensureExrThreads();
    try {
        DeepPartReader reader(path);
        return read(reader);
    } catch (const Error&) {
        throw;
    } catch (const std::exception& e) {
        throw FileError(path, "truncated or corrupt: " + exrErrorDetail(e));
    }
}

void requireChannel(const std::string& path, const DeepPartReader& reader, const std::string& z) {
    if (!reader.header().channels().findChannel(z)) throw FileError(path, "deep image without a " + z + " channel");
}

} // namespace

DeepWindows readDeepWindows(const std::string& path, const std::string& z) {
    return readDeepPart(path, [&](DeepPartReader& reader) {
        requireChannel(path, reader, z);
        DeepWindows w;
        reader.windows(w);
        return w;
    });
}

DeepSamples readDeepDepthSamples(const std::string& path, const std::string& z, const std::string& zBack) {
    return readDeepPart(path, [&](DeepPartReader& reader) {
        requireChannel(path, reader, z);
        const Imf::ChannelList& channels = reader.header().channels();
        DeepSamples out;
        out.hasZBack = channels.findChannel(zBack) != nullptr;
        std::vector<DeepTarget> targets = {{z, &out.z, 0, 1}};
        if (out.hasZBack) targets.push_back({zBack, &out.zBack, 0, 1});
        reader.read(out, targets);
        return out;
    });
}

DeepChannels readDeepChannelSamples(const std::string& path) {
    return readDeepPart(path, [&](DeepPartReader& reader) {
        DeepChannels out;
        const Imf::ChannelList& channels = reader.header().channels();
        for (auto it = channels.begin(); it != channels.end(); ++it) out.names.push_back(it.name());
        std::vector<DeepTarget> targets;
        for (size_t c = 0; c < out.names.size(); ++c) targets.push_back({out.names[c], &out.values, c, out.names.size()});
        reader.read(out, targets);
        return out;
    });
}

} // namespace obscura
