// A deep EXR's samples, read with OpenEXR's deep API straight into flat arrays (the first part,
// scanline or tiled, any channel type as float).
#pragma once
#include <string>
#include <vector>

namespace obscura {

// A deep image's windows and sample counts.
struct DeepWindows {
    int fullWidth = 0, fullHeight = 0;        // display window size
    int x = 0, y = 0, width = 0, height = 0;  // data window, relative to the display origin
    std::vector<unsigned> counts;             // samples per pixel, row-major over the data window
};

// A deep image's sample depths as read, before any sorting (io/deep_file.cpp makes layers of them).
struct DeepSamples : DeepWindows {
    bool hasZBack = false;
    std::vector<float> z, zBack;  // all samples, pixel after pixel (zBack empty without it)
};

// Every channel of a deep image's samples, for flattening (io/deep_merge.h).
struct DeepChannels : DeepWindows {
    std::vector<std::string> names;  // sorted by name, as OpenEXR lists them
    std::vector<float> values;       // every sample's channels in `names` order, pixel after pixel
};

// The samples of channels z (required) and zBack (optional). The caller has checked the windows
// (checkWindowsBeforeOpening). Throws FileError for a flat file, a missing z channel, sample
// counts the file's size cannot hold, or a truncated or corrupt file.
DeepSamples readDeepDepthSamples(const std::string& path, const std::string& z, const std::string& zBack);

// The windows (no counts), after what readDeepDepthSamples checks before it reads a sample: a deep
// first part with channel z.
DeepWindows readDeepWindows(const std::string& path, const std::string& z);

// Every channel of every sample, as readDeepDepthSamples.
DeepChannels readDeepChannelSamples(const std::string& path);

} // namespace obscura
