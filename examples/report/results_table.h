// One row per (scene, method, preset, device): median compute time and error against
// the converged ray-traced reference. Written as results.csv and results.json.
#pragma once
#include "core/metrics.h"

#include <nlohmann/json.hpp>

#include <string>
#include <utility>
#include <vector>

namespace report {

struct ResultRow {
    std::string scene, method, preset, device, definition;
    // "ao": AO vs Reference.AO_<definition>; "do": DO vs Reference.DO; "gi": GI vs Reference.GI (surfaces within
    // R); "gi_unlimited": GI vs Reference.GI_unlimited (every surface). DO and GI: luminance of RGB irradiance.
    std::string quantity = "ao";
    std::string deviceDetail;      // e.g. "gl-osmesa: llvmpipe (LLVM 15.0.6, 256 bits), OpenGL 4.5 ..." (JSON only)
    int width = 0, height = 0;
    double radius = 0;
    int directions = 0, steps = 0, blur = 0;  // HBAO's sample counts (0 for the ray tracer and SSDO)
    int samples = 0, interleave = 0;           // SSDO: N and the M x M block; ssao: points; rtao: rays; blur = the applied one
    int rays = 0;                              // AO rays per pixel (ray tracer rows; 0 for obscura)
    int runs = 0;                              // timed runs after the warm-up
    int overscan = 0;                          // obscura ran on passes this many pixels past each display edge
    double timeMs = 0;                         // median time per frame (obscura: runOperator; ray tracer: render)
    std::vector<std::pair<std::string, double>> stageMs;  // median of each stage, ms
    obscura::ErrorMetrics metrics;             // against the converged reference, non-sky pixels
    double relativeRmse = 0;                   // the normalised error: RMSE / mean(reference), non-sky pixels
    double meanRatio = 0;                      // mean(result) / mean(reference): 1 = no bias
};

// The CSV header, in column order.
const std::vector<std::string>& csvColumns();
// Writes `rows` as CSV (one header line); atomically.
void writeCsv(const std::string& path, const std::vector<ResultRow>& rows);
// Writes {"meta": meta, "rows": [...]}; atomically.
void writeJson(const std::string& path, const std::vector<ResultRow>& rows, const nlohmann::json& meta);
// Writes `text` to a temporary file next to `path` and renames it over `path`.
void writeTextFile(const std::string& path, const std::string& text);

} // namespace report
