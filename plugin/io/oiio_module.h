// The few things obscura asks of OpenImageIO (environment maps, PNG previews, deep EXR), as a
// table of functions in a shared library of their own, libobscura_oiio.so, loaded on first use.
// Why: OpenImageIO pulls in ~255 shared libraries (codecs, DICOM, video...), and loading them
// cost every obscura process ~0.45 s of CPU at start, though most runs never call it.
#pragma once
#include "base/image.h"
#include "io/colour.h"

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace obscura {

// A deep image's windows and sample counts.
struct DeepWindows {
    int fullWidth = 0, fullHeight = 0;        // display window size
    int x = 0, y = 0, width = 0, height = 0;  // data window, relative to the display origin
    std::vector<int> counts;                  // samples per pixel, row-major over the data window
};

// A deep image's sample depths as read, before any sorting (io/deep_file.cpp makes layers of them).
struct DeepSamples : DeepWindows {
    bool hasZBack = false;
    std::vector<float> z, zBack;        // all samples, pixel after pixel (zBack empty without it)
};

// Every channel of a deep image's samples, for flattening (io/deep_merge.h).
struct DeepChannels : DeepWindows {
    std::vector<std::string> names;     // as the file lists them
    std::vector<float> values;          // every sample's channels in `names` order, pixel after pixel
};

// Each function returns "" on success, else the error in one line (the caller names the file).
struct OiioModule {
    int abi;  // kOiioModuleAbi: a stale module from another build is refused, not called
    // Size and kind of the first subimage.
    std::string (*probe)(const std::string& path, int& width, int& height, int& channels, bool& deep);
    // Channels 0..2 of the first subimage as floats, and what the file says of its colour, from
    // one open. `accept` sees the size before any pixel is allocated and may throw to refuse it.
    std::string (*readRgb)(const std::string& path, const std::function<void(int width, int height, int channels)>& accept,
                           Image& rgb, ColourMetadata& meta);
    // An 8-bit PNG of `channels` interleaved channels, straight to `path` (the caller renames).
    std::string (*writePng)(const std::string& path, int width, int height, int channels,
                            const std::uint8_t* bytes, const std::string& colourSpaceTag);
    // The samples of channels z (required) and zBack (optional) of a deep image.
    std::string (*readDeep)(const std::string& path, const std::string& z, const std::string& zBack,
                            DeepSamples& out);
    // Every channel of every sample of a deep image, as float.
    std::string (*readDeepChannels)(const std::string& path, DeepChannels& out);
};
constexpr int kOiioModuleAbi = 3;

// The module, loaded once (thread-safe). Throws obscura::Error when it cannot be loaded.
const OiioModule& oiioModule();

} // namespace obscura

// The module's one exported symbol.
extern "C" const obscura::OiioModule* obscuraOiioModule();
