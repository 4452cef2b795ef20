#include "io/preview.h"

#include "base/error.h"

#include "io/oiio_module.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <system_error>
#include <vector>

namespace obscura {
namespace {

float clamp01(float v) { return std::isnan(v) ? 0.0f : std::min(1.0f, std::max(0.0f, v)); }

float srgbOetf(float v) {
    return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

std::uint8_t quantise(float v) { return static_cast<std::uint8_t>(std::lround(v * 255.0f)); }

// The file part shared by both writers: 8-bit bytes -> PNG, temp file + rename.
void writePngBytes(const std::string& path, const std::string& what, int width, int height,
                   int channels, const std::vector<std::uint8_t>& bytes, const std::string& colourSpaceTag) {
    namespace fs = std::filesystem;
    const fs::path target(path);
    const fs::path dir = target.parent_path().empty() ? fs::path(".") : target.parent_path();
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) throw FileError(path, what + "directory " + dir.string() + " does not exist");

    // The temp name keeps the .png extension so nothing guesses another format.
    const fs::path tmp = dir / ("." + target.filename().string() + ".tmp.png");
    const std::string failed = oiioModule().writePng(tmp.string(), width, height, channels, bytes.data(), colourSpaceTag);
    if (!failed.empty()) {
        fs::remove(tmp, ec);
        throw FileError(path, what + failed);
    }
    fs::rename(tmp, target, ec);
    if (ec) {
        const std::string msg = ec.message();
        fs::remove(tmp, ec);
        throw FileError(path, what + msg);
    }
}

void requireImage(const Image& img, const std::string& path, const std::string& what) {
    if (img.empty() || img.width <= 0 || img.height <= 0 || img.channels <= 0)
        throw FileError(path, what + "the image is empty");
}

} // namespace

void writePreviewPng(const std::string& path, const Image& img, int channel) {
    const std::string what = "cannot write the preview: ";
    requireImage(img, path, what);
    if (channel >= img.channels)
        throw FileError(path, what + "channel " + std::to_string(channel) + " does not exist (the image has " +
                    std::to_string(img.channels) + ")");

    const bool rgb = channel < 0 && img.channels >= 3;
    const int first = channel < 0 ? 0 : channel;
    const int outChannels = rgb ? 3 : 1;

    std::vector<std::uint8_t> bytes(static_cast<std::size_t>(img.width) * img.height * outChannels);
    std::size_t k = 0;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
            const float* p = img.at(x, y);
            for (int c = 0; c < outChannels; ++c) {
                float v = clamp01(p[first + c]);
                bytes[k++] = quantise(rgb ? srgbOetf(v) : v);
            }
        }
    writePngBytes(path, what, img.width, img.height, outChannels, bytes, rgb ? "sRGB" : "");
}

void writeEncodedPreviewPng(const std::string& path, const Image& img, const std::string& colourSpaceTag) {
    const std::string what = "cannot write the preview: ";
    requireImage(img, path, what);
    const int outChannels = img.channels >= 3 ? 3 : 1;
    std::vector<std::uint8_t> bytes(static_cast<std::size_t>(img.width) * img.height * outChannels);
    std::size_t k = 0;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
            const float* p = img.at(x, y);
            for (int c = 0; c < outChannels; ++c) bytes[k++] = quantise(clamp01(p[c]));
        }
    writePngBytes(path, what, img.width, img.height, outChannels, bytes, colourSpaceTag);
}

} // namespace obscura
