#include "report_options.h"

#include "core/settings.h"
#include "reference/scene.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#ifndef OBSCURA_REPORT_PLOT_SCRIPT
#define OBSCURA_REPORT_PLOT_SCRIPT "plot_report.py"
#endif

namespace report {

namespace {

void usage(FILE* to) {
    std::fprintf(to,
        "usage: obscura_report [options]\n"
        "Runs every method x quality preset x device of obscura on the reference scenes, measures\n"
        "time and error against a converged ray-traced reference, and writes results.csv,\n"
        "results.json, <scene>_sheet.png and error_vs_time.png into the output directory.\n"
        "  --out DIR              output directory (report)\n"
        "  --cache DIR            converged references, reused when present (OUT/cache)\n"
        "  --scenes A,B           scenes (all: corner,sphere-plane,cornell,stairs,poles,city,terrain,studio)\n"
        "  --methods A,B          methods (all registered, see below); SSDO's presets\n"
        "                         are N = 16/64/256/1024 samples, interleave 2 (ssdo-noint: 1, no blur)\n"
        "  --presets A,B          quality presets (low,medium,high,ultra)\n"
        "  --devices A,B          devices (cpu,gl-osmesa,gl-egl); an unavailable one is skipped with a note\n"
        "  --definition NAME      AO definition compared: cosine_none, cosine_linear, uniform_none,\n"
        "                         uniform_linear (cosine_none: what a ray tracer's AO pass computes)\n"
        "  --width W, --height H  render size (320 x 240)\n"
        "  --converged-rays N     AO rays per pixel of the converged reference (1024)\n"
        "  --gi-rays N            GI rays of the converged render: beauty, Reference.GI (1024)\n"
        "  --radius-scale F       every scene's AO distance R times F (1; references cached per F)\n"
        "  --rt-rays A,B          ray counts of the ray tracer's own curves, AO/DO and GI (1,4,16,64,256)\n"
        "  --runs N               timed runs after one warm-up; the median is reported (3)\n"
        "  --run-budget S         stop timing a point after S seconds of runs (at least one run) (2)\n"
        "  --sheet-preset P       preset shown on the contact sheets (high)\n"
        "  --sheet-device D       device shown on the contact sheets (cpu)\n"
        "  --heat-max E           |error| at the top of the heat map's scale (0.25)\n"
        "  --plot-script PATH     the matplotlib script (the source tree's plot_report.py)\n"
        "  --python EXE           interpreter for it (/usr/bin/python3 if present, else python3)\n"
        "  --no-plot              skip error_vs_time.png\n"
        "  --overscan N           obscura reads passes rendered N pixels past each edge of the frame\n"
        "                         (cached, 1 AO ray: passes only) and its AO is compared over the\n"
        "                         display window; SSDO keeps the frame alone (0)\n"
        "  --normals given|depth  the normal pass (given, default), or normals reconstructed from the\n"
        "                         depth (what obscura does for a file without a normal layer)\n"
        "  --quick                tiny run: corner at 64x48, 64 converged rays, curve 1,4,\n"
        "                         preset low, cpu, 1 run (flags after it override it)\n");
    std::string all;
    for (const std::string& m : registeredMethods()) all += (all.empty() ? "" : ",") + m;
    std::fprintf(to, "methods registered: %s\n"
                     "  (hbao+horizon: --thickness inf --border open; hbao+open, hbao+clamp: --border open, clamp;\n"
                     "   hbao+deep: hbao with the scene's deep render (every solid along each ray, cached) as --flat;\n"
                     "   hbao+bounce: hbao --bounce (GI rows, senders DiffDir x DiffCol); hbao+deep+bounce: both, each\n"
                     "   hidden layer radiating its deep colour (DiffDir x DiffCol of its surface, cached apart);\n"
                     "   rtao+sheet: rtao --thickness 0; rtao+thick: --thickness R/5; discs+vis: --disc-passes 2;\n"
                     "   discs-blend: --disc-blend-levels; discs-nopoly: --disc-no-polygon; discs-sum: --disc-sum;\n"
                     "   a device a method does not run on, as rtao on GL, is skipped)\n", all.c_str());
}

[[noreturn]] void fail(const std::string& message) {
    std::fprintf(stderr, "obscura_report: %s\n", message.c_str());
    usage(stderr);
    std::exit(2);
}

std::vector<std::string> splitList(const std::string& s) {
    std::vector<std::string> out;
    size_t start = 0;
    while (start <= s.size()) {
        const size_t comma = std::min(s.find(',', start), s.size());
        if (comma > start) out.push_back(s.substr(start, comma - start));
        start = comma + 1;
    }
    return out;
}

int toInt(const std::string& flag, const std::string& s, int lo, int hi) {
    char* end = nullptr;
    const long v = std::strtol(s.c_str(), &end, 10);
    if (end == s.c_str() || *end != '\0' || v < lo || v > hi)
        fail(flag + " needs an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " + s);
    return int(v);
}

void requireKnown(const std::string& flag, const std::vector<std::string>& given,
                  const std::vector<std::string>& known) {
    for (const std::string& g : given)
        if (std::find(known.begin(), known.end(), g) == known.end()) fail(flag + ": unknown name '" + g + "'");
}

// The procedural scenes (reference_render's list without obj:PATH).
std::vector<std::string> builtInScenes() {
    std::vector<std::string> names;
    for (const std::string& s : reference::sceneNames())
        if (s.rfind("obj:", 0) != 0) names.push_back(s);
    return names;
}

std::vector<std::string> presetNames() {
    std::vector<std::string> names;
    for (const obscura::QualityPreset& p : obscura::qualityPresets()) names.push_back(p.name);
    return names;
}

} // namespace

ReportOptions parseReportOptions(int argc, char** argv) {
    ReportOptions o;
    o.plotScript = OBSCURA_REPORT_PLOT_SCRIPT;
    // Debian's interpreter, where python3-matplotlib is installed, before whatever python3 PATH finds.
    o.python = std::filesystem::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
    parseDefinition("cosine_none", o.definition);
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto value = [&]() -> std::string {
            if (i + 1 >= argc) fail(a + " needs a value");
            return argv[++i];
        };
        if (a == "-h" || a == "--help") {
            usage(stdout);
            std::exit(0);
        } else if (a == "--out") o.outDir = value();
        else if (a == "--cache") o.cacheDir = value();
        else if (a == "--scenes") o.scenes = splitList(value());
        else if (a == "--methods") o.methods = splitList(value());
        else if (a == "--presets") o.presets = splitList(value());
        else if (a == "--devices") o.devices = splitList(value());
        else if (a == "--definition") {
            const std::string d = value();
            if (!parseDefinition(d, o.definition)) fail("--definition: unknown definition '" + d + "'");
        } else if (a == "--width") o.reference.width = toInt(a, value(), 8, 8192);
        else if (a == "--height") o.reference.height = toInt(a, value(), 8, 8192);
        else if (a == "--converged-rays") o.reference.convergedRays = toInt(a, value(), 1, 1 << 16);
        else if (a == "--gi-rays") o.reference.giRays = toInt(a, value(), 1, 1 << 16);
        else if (a == "--radius-scale") {
            const std::string s = value();
            o.reference.radiusScale = std::strtod(s.c_str(), nullptr);
            if (!(o.reference.radiusScale > 0)) fail("--radius-scale needs a positive number, got " + s);
        }
        else if (a == "--rt-rays") {
            o.reference.curveRays.clear();
            for (const std::string& r : splitList(value())) o.reference.curveRays.push_back(toInt(a, r, 1, 1 << 16));
        } else if (a == "--runs") o.reference.runs = toInt(a, value(), 1, 100);
        else if (a == "--run-budget") {
            const std::string s = value();
            o.reference.runBudgetSeconds = std::strtod(s.c_str(), nullptr);
            if (!(o.reference.runBudgetSeconds > 0)) fail("--run-budget needs a positive number, got " + s);
        } else if (a == "--sheet-preset") o.sheetPreset = value();
        else if (a == "--sheet-device") o.sheetDevice = value();
        else if (a == "--heat-max") {
            const std::string s = value();
            o.heatMax = std::strtod(s.c_str(), nullptr);
            if (!(o.heatMax > 0)) fail("--heat-max needs a positive number, got " + s);
        } else if (a == "--plot-script") o.plotScript = value();
        else if (a == "--python") o.python = value();
        else if (a == "--no-plot") o.plot = false;
        else if (a == "--overscan") o.overscan = toInt(a, value(), 0, 4096);
        else if (a == "--normals") {
            const std::string n = value();
            if (n != "given" && n != "depth") fail("--normals expects given or depth, got '" + n + "'");
            o.depthNormals = n == "depth";
        }
        else if (a == "--quick") {
            o.scenes = {"corner"};
            o.presets = {"low"};
            o.devices = {"cpu"};
            o.reference.width = 64;
            o.reference.height = 48;
            o.reference.convergedRays = 64;
            o.reference.giRays = 4;
            o.reference.curveRays = {1, 4};
            o.reference.runs = 1;
        } else fail("unexpected argument " + a);
    }
    if (o.scenes.empty()) o.scenes = builtInScenes();
    if (o.methods.empty()) o.methods = registeredMethods();
    if (o.presets.empty()) o.presets = presetNames();
    if (o.devices.empty()) o.devices = registeredDevices();
    requireKnown("--scenes", o.scenes, builtInScenes());
    requireKnown("--methods", o.methods, registeredMethods());
    requireKnown("--presets", o.presets, presetNames());
    requireKnown("--devices", o.devices, registeredDevices());
    if (o.cacheDir.empty()) o.cacheDir = o.outDir + "/cache";
    return o;
}

} // namespace report
