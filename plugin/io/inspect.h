// --inspect: what obscura finds in a frame before computing anything (layers, roles,
// conventions, camera, how it would write, device). One structure, two forms: the JSON of
// `--inspect --json` and Python's obscura.inspect(), and the text of `--inspect`, which is
// printed from that JSON so the two cannot say different things.
#pragma once
#include "io/frame_job.h"

#include <nlohmann/json.hpp>

#include <string>

namespace obscura {

// Reads the headers and the passes the camera needs; writes nothing. A camera or device that
// cannot be had is reported in the structure ("camera": null, "camera_error": why), not thrown.
nlohmann::json inspectFrameJson(const FrameJob& job);
// The readable form of inspectFrameJson's structure.
std::string inspectText(const nlohmann::json& inspected);
inline std::string inspectFrame(const FrameJob& job) { return inspectText(inspectFrameJson(job)); }

} // namespace obscura
