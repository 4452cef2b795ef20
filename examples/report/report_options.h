// obscura_report's command line.
#pragma once
#include "methods.h"
#include "reference_runs.h"

#include <string>
#include <vector>

namespace report {

struct ReportOptions {
    std::vector<std::string> scenes, methods, presets, devices;  // empty lists: every registered one
    AoDefinition definition;          // cosine_none unless --definition
    ReferenceSettings reference;      // size, converged rays, curve rays, runs
    std::string outDir = "report", cacheDir;  // cacheDir "" = <outDir>/cache
    std::string sheetPreset = "high", sheetDevice = "cpu";
    double heatMax = 0.25;
    std::string plotScript, python;  // python: /usr/bin/python3 when present (Debian's, with matplotlib), else python3
    bool plot = true;
    int overscan = 0;  // > 0: obscura reads passes rendered this many pixels past each display edge
    bool depthNormals = false;  // --normals depth: obscura reconstructs the normals from the depth
};

// Parses argv; prints usage and exits (0 for --help, 2 for a bad command line).
ReportOptions parseReportOptions(int argc, char** argv);

} // namespace report
