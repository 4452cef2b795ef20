// Frame sequences: "shot.####.exr" or "shot.%04d.exr" patterns and frame ranges.
#pragma once
#include <string>
#include <vector>

namespace obscura {

// True when `path` holds a frame placeholder (a run of '#' or a printf-style %0Nd / %d).
bool isFramePattern(const std::string& path);
// The path of one frame: '#' runs are zero-padded to their length, %0Nd to N digits.
std::string framePath(const std::string& pattern, int frame);
// "1-100", "1-100x2" (every 2nd), "7" or "1,5,9-12"; throws obscura::Error on bad syntax.
std::vector<int> parseFrames(const std::string& spec);
// Frames whose file exists, found by listing the pattern's directory, in order.
std::vector<int> existingFrames(const std::string& pattern);
// The frames in order, cut into consecutive chunks of `size` (the last may be shorter): the same
// list and size always give the same chunks, so a farm task's frames never depend on timing.
std::vector<std::vector<int>> chunkFrames(const std::vector<int>& frames, int size);
// The shortest --frames text for `frames` in order ("1-4,7,9-13x2"); parseFrames reads it back.
std::string frameSpec(const std::vector<int>& frames);

} // namespace obscura
