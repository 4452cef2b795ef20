// Reading back what a run wrote: one channel of one part as floats, a JSON report.
#pragma once
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfMultiPartInputFile.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace obscura::test {

// Part `part`'s level 0 into `fb`, tiled or scanline, with OpenEXR's own readers (independent
// of obscura's).
void readPart(Imf::MultiPartInputFile& file, int part, const Imf::FrameBuffer& fb);
// Channel `name` of part `part` (a tiled part's level 0), converted to float by OpenEXR, over
// the part's data window (row-major); -1 where the channel is absent.
std::vector<float> partChannel(const std::string& path, int part, const std::string& name);
nlohmann::json readJson(const std::filesystem::path& path);
// The mean of v where `on` (NaN where nowhere).
double meanOver(const std::vector<float>& v, const std::vector<bool>& on);

} // namespace obscura::test
