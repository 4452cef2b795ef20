// Runs of the reference renderer and of the CLI against its ground truth, for tests that
// measure PSNR on a report scene. Header-only: it uses the including test's OBSCURA_CLI_PATH.
#pragma once
#include "support/cli_runner.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace obscura::test {

// reference_render sits at <build>/examples/reference/, the CLI at <build>/plugin/.
inline std::string referenceRenderPath() {
    const std::filesystem::path cli(OBSCURA_CLI_PATH);
    return (cli.parent_path().parent_path() / "examples" / "reference" / "reference_render").string();
}

// Renders `scene` at w x h with 256 AO rays (one GI ray: unused) into `path`, plus `args`.
inline CliResult renderReferenceScene(const std::string& scene, const std::string& path, int w, int h,
                                      const std::vector<std::string>& args = {}) {
    std::vector<std::string> all = {"--scene", scene, "-o", path, "--width", std::to_string(w), "--height",
                                    std::to_string(h), "--ao-rays", "256", "--gi-rays", "1", "--quiet"};
    all.insert(all.end(), args.begin(), args.end());
    return runProgram(referenceRenderPath(), all);
}

// PSNR (dB) of the CLI's AO on `reference` against its Reference.AO_cosine_none, at radius
// `radius`, cosine weighting, no falloff, plus `args`; scratch files go in `dir`.
inline double psnrAgainstCosineReference(const std::string& reference, const std::filesystem::path& dir, float radius,
                                         const std::vector<std::string>& args) {
    const std::string report = (dir / "report.json").string();
    std::vector<std::string> all = {reference, "-o", (dir / "out.exr").string(), "--radius", std::to_string(radius),
                                    "--weighting", "cosine", "--falloff", "none", "--reference",
                                    "Reference.AO_cosine_none", "--report", report, "--quiet"};
    all.insert(all.end(), args.begin(), args.end());
    const CliResult c = runProgram(OBSCURA_CLI_PATH, all);
    EXPECT_EQ(c.exitCode, 0) << c.err;
    std::ifstream in(report);
    return nlohmann::json::parse(in)["reference"]["psnr_db"].get<double>();
}

} // namespace obscura::test
