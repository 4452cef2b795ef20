// Reading back what a run wrote: one channel of one part as floats, a JSON report.
#pragma once
#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace obscura::test {

// Channel `name` of part `part`, converted to float by OpenEXR, over the part's data window
// (row-major); -1 where the channel is absent.
std::vector<float> partChannel(const std::string& path, int part, const std::string& name);
nlohmann::json readJson(const std::filesystem::path& path);

} // namespace obscura::test
