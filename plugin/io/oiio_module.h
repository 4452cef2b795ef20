// What obscura asks of OpenImageIO (reading environment maps in any format it knows), as a
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

// Each function returns "" on success, else the error in one line (the caller names the file).
struct OiioModule {
    int abi;  // kOiioModuleAbi: a stale module from another build is refused, not called
    // Channels 0..2 of the first subimage as floats, and what the file says of its colour, from
    // one open. `accept` sees the size before any pixel is allocated and may throw to refuse it.
    std::string (*readRgb)(const std::string& path, const std::function<void(int width, int height, int channels)>& accept,
                           Image& rgb, ColourMetadata& meta);
};
constexpr int kOiioModuleAbi = 5;

// The module, loaded once (thread-safe). Throws obscura::Error when it cannot be loaded.
const OiioModule& oiioModule();

} // namespace obscura

// The module's one exported symbol.
extern "C" const obscura::OiioModule* obscuraOiioModule();
