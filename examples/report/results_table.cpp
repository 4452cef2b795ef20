#include "results_table.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace report {

namespace {

std::string number(double v, const char* format = "%.6g") {
    if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
    char buf[48];
    std::snprintf(buf, sizeof buf, format, v);
    return buf;
}

// "scan=0.12;hbao=10.3": the medians of the stages, ms.
std::string stageText(const ResultRow& r) {
    std::string s;
    for (const auto& [name, ms] : r.stageMs) s += (s.empty() ? "" : ";") + name + "=" + number(ms, "%.4g");
    return s;
}

nlohmann::json finiteOrNull(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

} // namespace

const std::vector<std::string>& csvColumns() {
    static const std::vector<std::string> columns = {
        "scene", "method", "preset", "device", "quantity", "definition", "width", "height", "radius", "directions",
        "steps", "samples", "interleave", "blur", "rays", "runs", "time_ms", "stage_ms", "pixels", "mae", "rmse", "psnr_db", "p99", "max_abs", "overscan", "rel_rmse", "mean_ratio"};
    return columns;
}

void writeTextFile(const std::string& path, const std::string& text) {
    const std::string tmp = path + ".tmp";
    {
        std::ofstream out(tmp, std::ios::binary);
        out << text;
        if (!out) throw std::runtime_error("cannot write " + tmp);
    }
    std::filesystem::rename(tmp, path);
}

void writeCsv(const std::string& path, const std::vector<ResultRow>& rows) {
    std::string text;
    for (const std::string& c : csvColumns()) text += (text.empty() ? "" : ",") + c;
    text += "\n";
    for (const ResultRow& r : rows) {
        const obscura::ErrorMetrics& m = r.metrics;
        const std::vector<std::string> cells = {
            r.scene, r.method, r.preset, r.device, r.quantity, r.definition, std::to_string(r.width),
            std::to_string(r.height), number(r.radius), std::to_string(r.directions), std::to_string(r.steps),
            std::to_string(r.samples), std::to_string(r.interleave), std::to_string(r.blur),
            std::to_string(r.rays), std::to_string(r.runs), number(r.timeMs, "%.4f"), stageText(r),
            std::to_string(m.pixels), number(m.mae), number(m.rmse), number(m.psnr, "%.3f"), number(m.p99),
            number(m.maxAbs), std::to_string(r.overscan), number(r.relativeRmse), number(r.meanRatio)};
        std::string line;
        for (const std::string& c : cells) line += (line.empty() ? "" : ",") + c;  // no cell holds a comma
        text += line + "\n";
    }
    writeTextFile(path, text);
}

void writeJson(const std::string& path, const std::vector<ResultRow>& rows, const nlohmann::json& meta) {
    nlohmann::json list = nlohmann::json::array();
    for (const ResultRow& r : rows) {
        nlohmann::json stages = nlohmann::json::object();
        for (const auto& [name, ms] : r.stageMs) stages[name] = ms;
        const obscura::ErrorMetrics& m = r.metrics;
        list.push_back({{"scene", r.scene}, {"method", r.method}, {"preset", r.preset}, {"device", r.device},
                        {"device_detail", r.deviceDetail}, {"quantity", r.quantity}, {"definition", r.definition}, {"width", r.width},
                        {"height", r.height}, {"radius", r.radius}, {"directions", r.directions},
                        {"steps", r.steps}, {"samples", r.samples}, {"interleave", r.interleave}, {"blur", r.blur}, {"rays", r.rays}, {"runs", r.runs},
                        {"time_ms", r.timeMs}, {"stage_ms", stages}, {"pixels", m.pixels}, {"mae", m.mae},
                        {"rmse", m.rmse}, {"psnr_db", finiteOrNull(m.psnr)}, {"p99", m.p99}, {"max_abs", m.maxAbs},
                        {"overscan", r.overscan}, {"rel_rmse", r.relativeRmse}, {"mean_ratio", r.meanRatio}});
    }
    writeTextFile(path, nlohmann::json{{"meta", meta}, {"rows", list}}.dump(1) + "\n");
}

} // namespace report
