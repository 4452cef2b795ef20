// An 8-bit PNG writer (the PNG specification, W3C 2003: chunks, scanline filters, a zlib
// stream), for --preview and display previews. Written here on zlib rather than through
// OpenImageIO: loading OpenImageIO's ~255 libraries cost a preview about 0.4 s of CPU, on a
// frame that took 0.15 s without it (io/oiio_module.h).
#pragma once
#include <cstdint>
#include <string>

namespace obscura {

// `channels` (1 grey, 2 grey + alpha, 3 RGB, 4 RGBA) interleaved bytes, rows top to bottom,
// straight to `path`. colourSpaceTag "sRGB" writes the sRGB chunk with its gAMA and cHRM
// fallbacks; any other non-empty tag is written as the text `oiio:ColorSpace` (what
// OpenImageIO reads back); "" leaves the image untagged (data). Returns "" on success, else
// the error in one line (the caller names the file).
std::string writePngFile(const std::string& path, int width, int height, int channels, const std::uint8_t* bytes,
                         const std::string& colourSpaceTag);

} // namespace obscura
