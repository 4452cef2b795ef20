// obscura_report: the error-against-run-time report (docs/accuracy.md).
// For each scene: a converged ray-traced reference (cached), the ray tracer's own
// error-versus-time curve, then every method x quality preset x device of obscura,
// timed (median after a warm-up) and measured against the reference over non-sky
// pixels. Writes results.csv, results.json, <scene>_sheet.png and error_vs_time.png.
#include "contact_sheet.h"
#include "lit_outputs.h"
#include "obscura_runs.h"
#include "reference_runs.h"
#include "report_options.h"
#include "results_table.h"
#include "timing.h"

#include "base/error.h"
#include "core/methods.h"
#include "core/settings.h"
#include "io/deep_file.h"

#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <thread>

namespace fs = std::filesystem;
using namespace report;

namespace {

std::string shellQuote(const std::string& s) {
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

void progress(const char* format, ...) __attribute__((format(printf, 1, 2)));
void progress(const char* format, ...) {
    va_list args;
    va_start(args, format);
    std::vprintf(format, args);
    va_end(args);
    std::fflush(stdout);
}

std::string metricsText(const obscura::ErrorMetrics& m) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "RMSE %.4f, PSNR %.1f dB, p99 %.3f", m.rmse, m.psnr, m.p99);
    return buf;
}

// Devices that can be made here; the others are skipped with the reason kept for the JSON.
std::vector<std::string> usableDevices(const std::vector<std::string>& wanted, nlohmann::json& skipped) {
    std::vector<std::string> usable;
    for (const std::string& d : wanted) {
        obscura::Settings s;
        s.device = d;
        try {
            progress("device %s: %s\n", d.c_str(), obscura::describeDevice(s).c_str());
            usable.push_back(d);
        } catch (const std::exception& e) {
            progress("device %s: unavailable, skipped (%s)\n", d.c_str(), e.what());
            skipped[d] = e.what();
        }
    }
    return usable;
}

nlohmann::json ssdoPresetTable() {
    nlohmann::json t = nlohmann::json::array();
    for (const obscura::QualityPreset& p : obscura::qualityPresets())
        t.push_back({{"name", p.name}, {"samples", ssdoSamplesForPreset(p.name)}, {"interleave", 2},
                     {"blur", 2}, {"samples_per_pixel", ssdoSamplesForPreset(p.name) / 4},
                     {"noint_samples_per_pixel", ssdoSamplesForPreset(p.name)}});
    return t;
}

nlohmann::json presetTable() {
    nlohmann::json t = nlohmann::json::array();
    for (const obscura::QualityPreset& p : obscura::qualityPresets())
        t.push_back({{"name", p.name}, {"directions", p.directions}, {"steps", p.steps}, {"blur", p.blur},
                     {"samples_per_pixel", p.directions * p.steps}});
    return t;
}

// The display window's part of an image of the data window `overscan` pixels larger each way.
obscura::Image displayWindowOf(const obscura::Image& data, int overscan, int width, int height) {
    obscura::Image out(width, height, data.channels);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            for (int c = 0; c < data.channels; ++c) out.at(x, y)[c] = data.at(x + overscan, y + overscan)[c];
    return out;
}

// The rows' shared fields, the scene's tag for progress lines, and where rows go.
struct SceneRows {
    const char* tag;
    ResultRow base;
    std::vector<ResultRow>& rows;
};

ResultRow litRow(const ResultRow& from, const std::string& quantity, const std::string& definition, const LitError& e) {
    ResultRow r = from;
    r.quantity = quantity;
    r.definition = definition;
    r.metrics = e.metrics;
    r.relativeRmse = e.relativeRmse;
    r.meanRatio = e.meanRatio;
    return r;
}

void printLit(const SceneRows& out, const ResultRow& r) {
    progress("%s %s %-8s %-9s: %-12s rel. RMSE %.3f, mean / reference %.3f\n", out.tag, r.method.c_str(),
             r.preset.c_str(), r.device.c_str(), r.quantity.c_str(), r.relativeRmse, r.meanRatio);
}

// The ray tracer's own curves: AO (every definition in play) and DO from the same renders; GI from renders
// with that many GI rays when a method bounces.
void traceCurves(const SceneRig& rig, const ReferenceSettings& rs,
                 const std::vector<std::pair<AoDefinition, const obscura::Image*>>& definitions,
                 const LoadedFrame& frame, const LitReferences* lit, bool bounce, SceneRows& out) {
    for (int rays : rs.curveRays) {
        const TracedAo t = traceAo(rig, rs, rays);
        ResultRow r = out.base;
        r.method = "raytrace";
        r.preset = "rays-" + std::to_string(rays);
        r.device = "cpu-embree";
        r.deviceDetail = "Embree 3, " + std::to_string(std::max(1u, std::thread::hardware_concurrency())) +
                         " threads; both weightings traced";
        r.rays = rays;
        r.runs = t.runs;
        r.timeMs = 1e3 * t.medianSeconds;
        r.stageMs = {{"render", r.timeMs}};
        for (const auto& [def, reference] : definitions) {
            ResultRow a = r;
            a.definition = def.name;
            a.metrics = nonSkyError(t.ao[def.referenceLayer], *reference, frame);
            progress("%s raytrace %4d rays (%s): %9.2f ms, %s\n", out.tag, rays, def.name.c_str(), a.timeMs,
                     metricsText(a.metrics).c_str());
            out.rows.push_back(a);
        }
        if (lit) {
            out.rows.push_back(litRow(r, "do", "do_sky_sun", litError(t.directional, lit->directional, frame)));
            printLit(out, out.rows.back());
        }
        if (!lit || !bounce) continue;
        const TracedGi g = traceGi(rig, rs, rays);
        ResultRow gr = r;
        gr.runs = g.runs;
        gr.timeMs = 1e3 * g.medianSeconds;
        gr.stageMs = {{"render", gr.timeMs}};
        gr.deviceDetail = "Embree 3; one AO ray per weighting, the lights' shadow rays, GI rays";
        out.rows.push_back(litRow(gr, "gi", "gi_within_r", litError(g.gi, lit->gi, frame)));
        printLit(out, out.rows.back());
    }
}

// The deep reference's layers over the frame's data window, and for a bounce variant (hbao+deep+bounce)
// their colours: each hidden surface's DiffDir x DiffCol, from the coloured deep render.
struct DeepInput {
    obscura::Image layers, colour;
};

DeepInput loadDeepInput(const SceneRig& rig, const ReferenceSettings& rs, const ReportOptions& o, const LoadedFrame& used,
                        const char* tag) {
    const bool coloured = anyMethod(o.methods, [](const std::string& m) { return usesDeep(m) && hasBounce(m); });
    if (coloured && o.overscan > 0)
        throw obscura::Error("hbao+deep+bounce does not take --overscan (its light reads the frame's own passes)");
    const std::string path = ensureDeepReference(rig, rs, o.cacheDir, coloured);
    obscura::DeepLayers deep = obscura::readDeepLayers(path, obscura::Settings().deepLayers, {},
                                                       obscura::kDefaultMaxPixels, coloured);
    progress("%s deep reference: %d layers%s, %lld empty pixels -> %s\n", tag, deep.layers,
             deep.colour.empty() ? "" : " with colour", deep.emptyPixels, path.c_str());
    if (coloured && deep.colour.empty()) throw obscura::Error("'" + path + "' has no R, G, B: delete it to render it again");
    DeepInput out;
    if (coloured) out.colour = obscura::deepPlanesOver(std::move(deep.colour), deep.data, used.passes.data, 0.0f);
    out.layers = obscura::deepPlanesOver(std::move(deep), used.passes.data);
    return out;
}

// DO and GI rows of an obscura run (the AO row is already in).
void addLitRows(const TimedOperator& t, const ResultRow& aoRow, const LitReferences& lit, const LoadedFrame& f,
                SceneRows& out) {
    if (!t.directional.empty()) {
        out.rows.push_back(litRow(aoRow, "do", "do_sky_sun", litError(t.directional, lit.directional, f)));
        printLit(out, out.rows.back());
    }
    if (t.indirect.empty()) return;
    out.rows.push_back(litRow(aoRow, "gi", "gi_within_r", litError(t.indirect, lit.gi, f)));
    printLit(out, out.rows.back());
    out.rows.push_back(litRow(aoRow, "gi_unlimited", "gi_unlimited", litError(t.indirect, lit.giUnlimited, f)));
    printLit(out, out.rows.back());
}

} // namespace

int main(int argc, char** argv) {
    const ReportOptions o = parseReportOptions(argc, argv);
    const ReferenceSettings& rs = o.reference;
    const Clock::time_point start = Clock::now();
    try {
        fs::create_directories(o.outDir);
        fs::create_directories(o.cacheDir);
        nlohmann::json skippedDevices = nlohmann::json::object();
        const std::vector<std::string> devices = usableDevices(o.devices, skippedDevices);
        std::vector<ResultRow> rows;
        nlohmann::json scenes = nlohmann::json::array();
        bool labels = true;
        const int sceneCount = int(o.scenes.size());
        for (int si = 0; si < sceneCount; ++si) {
            const std::string& name = o.scenes[si];
            char tag[96];
            std::snprintf(tag, sizeof tag, "[scene %d/%d %s]", si + 1, sceneCount, name.c_str());
            progress("%s building the scene and its BVH\n", tag);
            const SceneRig rig(name, rs.width, rs.height);

            progress("%s converged reference: %d AO rays per pixel at %dx%d ...\n", tag, rs.convergedRays, rs.width,
                     rs.height);
            const ConvergedReference conv = ensureConvergedReference(rig, rs, o.cacheDir);
            if (conv.cached) progress("%s   reused %s\n", tag, conv.path.c_str());
            else progress("%s   rendered in %.1f s -> %s\n", tag, conv.seconds, conv.path.c_str());
            const LoadedFrame frame = loadFrame(conv.path, o.definition.exrLayer());
            const obscura::Image& truth = frame.passes.reference;
            // The lit methods' inputs (SSDO, GI methods): the bounce source (DiffDir x DiffCol), the scene's sky
            // as the map and its sun; their AO definition's reference (cosine_linear) and Reference.DO / GI.
            const bool anyLit = anyMethod(o.methods, isLit), anyBounce = anyMethod(o.methods, hasBounce);
            AoDefinition ssdoDefinition;
            parseDefinition("cosine_linear", ssdoDefinition);
            const LoadedFrame ssdoFrame = anyLit ? loadFrame(conv.path, ssdoDefinition.exrLayer(), true) : LoadedFrame();
            const LitReferences lit = anyLit ? loadLitReferences(conv.path) : LitReferences();
            const obscura::Image sky = skyEnvironment(rig.scene);
            // The AO definitions in play (the report's, and cosine_linear when SSDO runs), for the ray tracer's curve.
            std::vector<std::pair<AoDefinition, const obscura::Image*>> definitions = {{o.definition, &truth}};
            if (anyLit && ssdoDefinition.name != o.definition.name)
                definitions.emplace_back(ssdoDefinition, &ssdoFrame.passes.reference);

            SceneRows out{tag, ResultRow(), rows};
            out.base.scene = name;
            out.base.definition = o.definition.name;
            out.base.width = rs.width;
            out.base.height = rs.height;
            out.base.radius = frame.radius;
            const ResultRow& base = out.base;
            traceCurves(rig, rs, definitions, frame, anyLit ? &lit : nullptr, anyBounce, out);

            // --overscan: the same frame's passes with a margin past the display window; obscura's AO
            // is cropped back to the display window, so the reference and the non-sky mask are the frame's.
            LoadedFrame overscanFrame;
            if (o.overscan > 0) {
                const std::string path = ensureOverscanPasses(rig, rs, o.overscan, o.cacheDir);
                progress("%s   passes with %d px overscan: %s\n", tag, o.overscan, path.c_str());
                overscanFrame = loadFrame(path, o.definition.exrLayer());
            }
            const LoadedFrame& used = o.overscan > 0 ? overscanFrame : frame;
            const obscura::OperatorInputs in = operatorInputs(used, false, o.depthNormals);
            // hbao+deep: the same inputs plus the deep reference's layers, read as the CLI's --flat reads them.
            const DeepInput deep = anyMethod(o.methods, usesDeep) ? loadDeepInput(rig, rs, o, used, tag) : DeepInput();
            obscura::OperatorInputs deepIn = in;
            if (!deep.layers.empty()) deepIn.deepLayers = deep.layers.view();
            obscura::Image sheetAo;
            const obscura::Image* sheetTruth = &truth;
            std::string sheetLabel;
            for (const std::string& method : o.methods)
                for (const std::string& preset : o.presets)
                    for (const std::string& device : devices) {
                        const bool ssdo = isSsdoMethod(method), bounce = hasBounce(method), lights = isLit(method);
                        const AoDefinition def = definitionFor(method, o.definition);
                        const LoadedFrame& f = ssdo ? ssdoFrame : frame;
                        obscura::Settings s;
                        s.radius = float(f.radius);
                        configureMethod(method, preset, s);
                        if (device != "cpu" && !obscura::findMethod(s.method)->gl) continue;  // e.g. rtao: CPU only
                        s.weighting = def.weighting;  // HBAO's; SSDO's AO is cosine_linear whatever these say
                        s.falloff = def.falloff;
                        s.skyDepth = f.skyDepth;
                        s.device = device;
                        obscura::OperatorInputs runIn = ssdo ? operatorInputs(f, bounce, o.depthNormals) : usesDeep(method) ? deepIn : in;
                        if (lights) {
                            applySceneLights(rig.scene, s);
                            if (!ssdo) runIn = operatorInputs(ssdoFrame, true, o.depthNormals);  // + the bounce source
                            if (usesDeep(method)) {  // hbao+deep+bounce: the layers, and the hidden ones' light
                                runIn.deepLayers = deep.layers.view();
                                if (!deep.colour.empty()) runIn.deepColour = deep.colour.view();
                            }
                            runIn.environment = &sky;
                        }
                        TimedOperator t = timeOperator(runIn, s, rs.runs, rs.runBudgetSeconds);
                        ResultRow r = base;
                        r.method = method;
                        r.preset = preset;
                        r.device = device;
                        r.definition = def.name;
                        r.deviceDetail = t.deviceDetail;
                        r.blur = obscura::resolvedBlur(s);
                        if (ssdo) {
                            r.samples = s.ssdoSamples;
                            r.interleave = s.interleave;
                        } else if (s.method == "hbao") {
                            r.directions = s.directions;
                            r.steps = s.steps;
                        } else {
                            r.samples = obscura::findMethod(s.method)->samplesPerPixel(s);  // points or rays
                        }
                        if (o.overscan > 0 && !ssdo && !lights) {  // the lit runs read the frame's own passes
                            t.ao = displayWindowOf(t.ao, o.overscan, rs.width, rs.height);
                            r.overscan = o.overscan;
                        }
                        r.runs = t.runs;
                        r.timeMs = 1e3 * t.medianSeconds;
                        for (const auto& [stage, seconds] : t.stageMedians) r.stageMs.emplace_back(stage, 1e3 * seconds);
                        r.metrics = nonSkyError(t.ao, f.passes.reference, f);
                        progress("%s %s %-6s %-9s: %9.2f ms, AO (%s) %s\n", tag, method.c_str(), preset.c_str(),
                                 device.c_str(), r.timeMs, def.name.c_str(), metricsText(r.metrics).c_str());
                        rows.push_back(r);
                        if (lights) addLitRows(t, r, lit, f, out);
                        const bool wanted = method == o.methods.front() && preset == o.sheetPreset && device == o.sheetDevice;
                        if (sheetAo.empty() || wanted) {
                            sheetAo = std::move(t.ao);
                            sheetTruth = &f.passes.reference;
                            sheetLabel = "obscura " + method + " " + preset + " " + device;
                        }
                    }

            if (!sheetAo.empty()) {
                SheetPanels panels;
                panels.exrPath = conv.path;
                panels.ao = &sheetAo;
                panels.reference = sheetTruth;
                panels.depth = &frame.passes.depth;
                panels.skyDepth = frame.skyDepth;
                panels.aoLabel = sheetLabel;
                panels.referenceLabel = "ray traced, " + std::to_string(rs.convergedRays) + " rays";
                panels.heatMax = o.heatMax;
                const std::string sheet = (fs::path(o.outDir) / (name + "_sheet.png")).string();
                labels = writeContactSheet(sheet, panels) && labels;
                progress("%s contact sheet -> %s\n", tag, sheet.c_str());
            }
            scenes.push_back({{"scene", name}, {"radius", frame.radius}, {"reference", conv.path},
                              {"reference_cached", conv.cached}, {"reference_render_s", conv.seconds},
                              {"sheet_ao", sheetLabel}});
        }

        nlohmann::json meta = {
            {"definition", o.definition.name},
            {"reference_layer", o.definition.exrLayer() + ".Y"},
            {"width", rs.width},
            {"height", rs.height},
            {"converged_rays", rs.convergedRays},
            {"converged_seed", 1},
            {"curve_rays", rs.curveRays},
            {"curve_seed", 2},
            {"runs", rs.runs},
            {"run_budget_s", rs.runBudgetSeconds},
            {"hardware_threads", std::max(1u, std::thread::hardware_concurrency())},
            {"presets", presetTable()},
            {"ssdo_presets", ssdoPresetTable()},
            {"preset_order", o.presets},
            {"methods", o.methods},
            {"devices", devices},
            {"skipped_devices", skippedDevices},
            {"scenes", scenes},
            {"sheet_labels", labels},
            {"timing",
             "obscura: median wall time of runOperator over `runs` runs after one warm-up run (fewer, at least one, "
             "once the timed runs of a point have taken run_budget_s; the row's runs column says how many); it is "
             "the compute "
             "stage only (reading and writing EXR files are not part of this comparison). stage_ms holds the "
             "operator's own stages (cpu: scan, hbao, blur; gl: scan, gl-upload, gl-compute, gl-readback). "
             "raytrace: median wall time (same run rule, no warm-up) of reference_render's frame loop with AO only "
             "(no GI), Embree BVH built "
             "beforehand; it traces the uniform and the cosine AO rays (both weightings) plus the light's shadow "
             "rays, so it is an upper bound for one definition."},
            {"error",
             "MAE, RMSE, PSNR (20 log10(1/RMSE), dB) and the 99th-percentile absolute error over non-sky pixels, "
             "against the converged reference layer; the raytrace rows use an independent seed. quantity 'ao': "
             "the row's definition (HBAO: the report's --definition; SSDO: cosine_linear, which its AO is by "
             "construction); the ray tracer's curve appears once per definition in play (same renders). quantity "
             "'do' (SSDO) and 'gi' (ssdo+bounce and any GI method): Rec. 709 luminance of the RGB irradiance "
             "against Reference.DO (the scene's sky as a lat-long map through the open directions, linear "
             "falloff, plus its sun unless blocked within R; obscura gets the same map and the sun as a light) "
             "and Reference.GI (one bounce from surfaces within R radiating albedo x direct irradiance / pi, "
             "gi_rays paths per pixel); 'gi_unlimited': the same GI against Reference.GI_unlimited (every "
             "surface, = pi x DiffInd). rel_rmse = RMSE / mean(reference) over non-sky pixels is their "
             "normalised error; mean_ratio = mean(result) / mean(reference) their bias. The ray tracer's DO "
             "comes from its AO renders' cosine rays, its GI from renders with that many GI rays."},
        };
        const std::string csv = (fs::path(o.outDir) / "results.csv").string();
        const std::string json = (fs::path(o.outDir) / "results.json").string();
        meta["total_seconds"] = secondsSince(start);
        writeCsv(csv, rows);
        writeJson(json, rows, meta);
        progress("wrote %s and %s (%zu rows)\n", csv.c_str(), json.c_str(), rows.size());
        if (!labels) progress("note: OpenImageIO found no font; the contact sheets have no labels (panel order: "
                              "beauty, obscura AO / reference AO, |error|)\n");

        if (o.plot) {
            const std::string png = (fs::path(o.outDir) / "error_vs_time.png").string();
            const std::string command =
                shellQuote(o.python) + " " + shellQuote(o.plotScript) + " " + shellQuote(json) + " " + shellQuote(png);
            // (the script also writes error_vs_time_gi.png when there are GI rows)
            progress("plotting: %s\n", command.c_str());
            if (std::system(command.c_str()) != 0) {
                std::fprintf(stderr, "obscura_report: the plot script failed (is python3-matplotlib installed?)\n");
                return 1;
            }
        }
        progress("done in %.1f s\n", secondsSince(start));
    } catch (const std::exception& e) {
        std::fprintf(stderr, "obscura_report: %s\n", e.what());
        return 1;
    }
    return 0;
}
