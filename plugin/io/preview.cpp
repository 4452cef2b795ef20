#include "io/preview.h"

#include "base/error.h"
#include "core/settings_schema.h"
#include "io/atomic_files.h"
#include "io/png_file.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace obscura {
namespace {

float clamp01(float v) { return std::isnan(v) ? 0.0f : std::min(1.0f, std::max(0.0f, v)); }

std::uint8_t quantise(float v) { return static_cast<std::uint8_t>(std::lround(v * 255.0f)); }

// The file part shared by both writers: 8-bit bytes -> PNG, temp file + rename.
void writePngBytes(const std::string& path, const std::string& what, int width, int height,
                   int channels, const std::vector<std::uint8_t>& bytes, const std::string& colourSpaceTag) {
    // The temp name keeps the .png extension so nothing guesses another format.
    writeAtomically(path, [&](const std::string& tmp) {
        const std::string failed = writePngFile(tmp, width, height, channels, bytes.data(), colourSpaceTag);
        if (!failed.empty()) throw FileError(path, what + failed);
    }, ".png");
}

void requireImage(const Image& img, const std::string& path, const std::string& what) {
    if (img.empty() || img.width <= 0 || img.height <= 0 || img.channels <= 0)
        throw FileError(path, what + "the image is empty");
}

// The channels a preview shows: 0..2 of an RGB image, else channel 0 as grey.
int previewChannels(const Image& img) { return img.channels >= 3 ? 3 : 1; }

} // namespace

float srgbOetf(float v) {
    v = clamp01(v);
    return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

float previewPercentile99(const Image& img) {
    const int shown = previewChannels(img);
    std::vector<float> peaks;
    peaks.reserve(static_cast<std::size_t>(img.width) * img.height);
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
            float peak = -std::numeric_limits<float>::infinity();
            for (int c = 0; c < shown; ++c)
                if (std::isfinite(img.at(x, y)[c])) peak = std::max(peak, img.at(x, y)[c]);
            if (std::isfinite(peak)) peaks.push_back(peak);
        }
    if (peaks.empty()) return 0.0f;
    const std::size_t rank = static_cast<std::size_t>(std::ceil(0.99 * peaks.size())) - 1;
    std::nth_element(peaks.begin(), peaks.begin() + rank, peaks.end());
    return peaks[rank];
}

float autoExposureEv(const Image& img) {
    const float p99 = previewPercentile99(img);
    if (!(p99 > 0.0f)) return 0.0f;
    return std::clamp(std::log2(kAutoExposurePeak / p99), (float)numberSetting("preview_exposure").min,
                      (float)numberSetting("preview_exposure").max);
}

void writePreviewPng(const std::string& path, const Image& img, float exposureEv) {
    const std::string what = "cannot write the preview: ";
    requireImage(img, path, what);
    const int shown = previewChannels(img);
    const float scale = std::exp2(exposureEv);
    std::vector<std::uint8_t> bytes(static_cast<std::size_t>(img.width) * img.height * shown);
    std::size_t k = 0;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x)
            for (int c = 0; c < shown; ++c) bytes[k++] = quantise(srgbOetf(img.at(x, y)[c] * scale));
    writePngBytes(path, what, img.width, img.height, shown, bytes, "sRGB");
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
