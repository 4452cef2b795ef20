// Smoke test of obscura_report: a --quick run (corner at 64x48, few rays, preset low,
// cpu) into a temporary directory; the CSV has the documented columns and finite
// figures, and the contact sheet and the chart exist.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

std::vector<std::string> splitCsvLine(const std::string& line) {
    std::vector<std::string> cells;
    std::stringstream in(line);
    for (std::string cell; std::getline(in, cell, ',');) cells.push_back(cell);
    return cells;
}

bool nonEmptyFile(const fs::path& p) {
    std::error_code ec;
    return fs::is_regular_file(p, ec) && fs::file_size(p, ec) > 0;
}

} // namespace

TEST(ReportSmoke, QuickRunWritesTableSheetAndChart) {
    const fs::path dir = fs::path(OBSCURA_REPORT_TMP) / "quick";
    fs::remove_all(dir);
    fs::create_directories(dir);
    const std::string command = std::string("'") + OBSCURA_REPORT_PATH + "' --quick --out '" + dir.string() +
                                "' > '" + (dir / "log.txt").string() + "' 2>&1";
    ASSERT_EQ(std::system(command.c_str()), 0) << "see " << (dir / "log.txt");

    std::ifstream csv(dir / "results.csv");
    ASSERT_TRUE(csv) << "no results.csv";
    std::string line;
    ASSERT_TRUE(std::getline(csv, line));
    const std::vector<std::string> expected = {"scene", "method", "preset", "device", "quantity", "definition", "width",
                                               "height", "radius", "directions", "steps", "samples", "interleave",
                                               "blur", "rays", "runs", "time_ms",
                                               "stage_ms", "pixels", "mae", "rmse", "psnr_db", "p99", "max_abs",
                                               "overscan", "rel_rmse", "mean_ratio"};
    const std::vector<std::string> header = splitCsvLine(line);
    ASSERT_EQ(header, expected);

    std::map<std::string, int> perMethod;
    while (std::getline(csv, line)) {
        const std::vector<std::string> cells = splitCsvLine(line);
        ASSERT_EQ(cells.size(), header.size()) << line;
        std::map<std::string, std::string> row;
        for (size_t i = 0; i < cells.size(); ++i) row[header[i]] = cells[i];
        ++perMethod[row["method"] + "/" + row["quantity"]];
        EXPECT_EQ(row["scene"], "corner");
        const bool lit = row["quantity"] != "ao";  // DO and GI: irradiance, rel_rmse is their normalised error
        if (row["quantity"] == "gi") {
            EXPECT_EQ(row["definition"], "gi_within_r");
        } else if (row["quantity"] == "gi_unlimited") {
            EXPECT_EQ(row["definition"], "gi_unlimited");
        } else if (row["quantity"] == "do") {
            EXPECT_EQ(row["definition"], "do_sky_sun");
        } else if (row["method"].rfind("ssdo", 0) == 0) {
            EXPECT_EQ(row["definition"], "cosine_linear");
        } else if (row["method"] == "hbao") {
            EXPECT_EQ(row["definition"], "cosine_none");
        }
        EXPECT_EQ(row["width"], "64");
        EXPECT_EQ(row["height"], "48");
        EXPECT_GT(std::stol(row["pixels"]), 0) << line;
        EXPECT_GT(std::stod(row["time_ms"]), 0.0) << line;
        for (const char* metric : {"mae", "rmse", "psnr_db", "p99", "max_abs", "rel_rmse", "mean_ratio"}) {
            const double v = std::stod(row[metric]);
            EXPECT_TRUE(std::isfinite(v)) << metric << " in " << line;
            // PSNR takes peak 1: below 0 dB for irradiance errors above 1 (DO, GI)
            if (!lit || std::string(metric) != "psnr_db") {
                EXPECT_GE(v, 0.0) << metric << " in " << line;
            }
        }
        if (lit) {
            EXPECT_GT(std::stod(row["mean_ratio"]), 0.0) << line;
        } else {
            EXPECT_LE(std::stod(row["rmse"]), 1.0) << line;
        }
        if (row["method"] == "hbao") {
            EXPECT_EQ(row["preset"], "low");
            EXPECT_EQ(row["device"], "cpu");
            EXPECT_NE(row["stage_ms"].find("hbao="), std::string::npos) << line;
        }
    }
    EXPECT_EQ(perMethod["hbao/ao"], 1);
    EXPECT_EQ(perMethod["ssdo/ao"], 1);
    EXPECT_EQ(perMethod["ssdo-noint/ao"], 1);
    EXPECT_EQ(perMethod["ssdo+bounce/ao"], 1);
    EXPECT_EQ(perMethod["ssdo+bounce/gi"], 1);
    EXPECT_EQ(perMethod["ssdo+bounce/gi_unlimited"], 1);
    EXPECT_EQ(perMethod["hbao+bounce/gi"], 1);
    EXPECT_EQ(perMethod["hbao+deep+bounce/ao"], 1);  // the deep render's layers, coloured, and the bounce
    EXPECT_EQ(perMethod["hbao+deep+bounce/gi"], 1);
    EXPECT_EQ(perMethod["hbao+deep+bounce/gi_unlimited"], 1);
    EXPECT_EQ(perMethod["ssdo/do"], 1);
    EXPECT_EQ(perMethod["ssdo+bounce/do"], 1);
    EXPECT_EQ(perMethod["raytrace/ao"], 4);  // 1 and 4 rays, against cosine_none and cosine_linear
    EXPECT_EQ(perMethod["raytrace/do"], 2);  // the ray tracer's own DO and GI curves: 1 and 4 rays
    EXPECT_EQ(perMethod["raytrace/gi"], 2);

    EXPECT_TRUE(nonEmptyFile(dir / "results.json"));
    EXPECT_TRUE(nonEmptyFile(dir / "corner_sheet.png"));
    EXPECT_TRUE(nonEmptyFile(dir / "error_vs_time.png"));
    EXPECT_TRUE(nonEmptyFile(dir / "error_vs_time_gi.png"));
    EXPECT_TRUE(nonEmptyFile(dir / "error_vs_time_do.png"));
    EXPECT_TRUE(nonEmptyFile(dir / "error_vs_time_hbao.png"));
    EXPECT_TRUE(nonEmptyFile(dir / "error_vs_time_variants.png"));
}
