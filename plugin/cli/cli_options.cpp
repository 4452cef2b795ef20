#include "cli/cli_options.h"

#include "cli/cli.h"
#include "core/devices.h"
#include "core/methods.h"
#include "core/settings_schema.h"
#include "io/deep_job.h"
#include "io/sequence.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

namespace obscura::cli {

namespace {


double toNumber(const std::string& flag, const std::string& v) {
    char* end = nullptr;
    const double d = std::strtod(v.c_str(), &end);
    if (v.empty() || *end != '\0' || !std::isfinite(d)) throw UsageError(flag + " expects a number, got '" + v + "'");
    return d;
}

int toInt(const std::string& flag, const std::string& v) {
    char* end = nullptr;
    const long n = std::strtol(v.c_str(), &end, 10);
    if (v.empty() || *end != '\0' || n < -1000000 || n > 1000000)
        throw UsageError(flag + " expects a whole number, got '" + v + "'");
    return (int)n;
}

// A shared numeric setting (core/settings_schema.h): parsed here, checked against core's range.
double toSetting(const std::string& flag, const std::string& v) {
    const NumberSetting& setting = numberSetting(flag);
    double x = 0;
    if (setting.integer) {
        char* end = nullptr;
        errno = 0;
        const long long n = std::strtoll(v.c_str(), &end, 10);
        if (v.empty() || *end != '\0' || errno == ERANGE) throw UsageError(flag + " expects a whole number, got '" + v + "'");
        x = (double)n;
    } else {
        x = toNumber(flag, v);
    }
    const std::string problem = numberProblem(setting, x, Spelling::Flag);
    if (!problem.empty()) throw UsageError(problem);
    return x;
}

template <class E>
E toEnum(const std::string& flag, const std::string& v, const char* choices) {
    E e{};
    if (!parse(v, e)) throw UsageError(flag + " expects " + choices + ", got '" + v + "'");
    return e;
}

// Exactly `count` comma-separated numbers.
std::vector<double> toNumbers(const std::string& flag, const std::string& v, size_t count) {
    std::vector<double> out;
    std::stringstream ss(v);
    std::string item;
    while (std::getline(ss, item, ',')) out.push_back(toNumber(flag, item));
    if (out.size() != count)
        throw UsageError(flag + " expects " + std::to_string(count) + " comma-separated numbers, got '" + v + "'");
    return out;
}


std::pair<std::string, std::string> splitAssignment(const std::string& flag, const std::string& v) {
    const size_t eq = v.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == v.size())
        throw UsageError(flag + " expects ROLE=NAME, got '" + v + "'");
    return {v.substr(0, eq), v.substr(eq + 1)};
}

struct Flag {
    const char* name;
    const char* value;  // nullptr: takes no value
    std::string help;
    std::function<void(Options&, const std::string&)> apply;
};

// "a|b|c" as "a, b or c".
std::string choiceWords(const std::string& value) {
    std::string words = value;
    const size_t last = words.rfind('|');
    if (last != std::string::npos) words.replace(last, 1, " or ");
    for (size_t i; (i = words.find('|')) != std::string::npos;) words.replace(i, 1, ", ");
    return words;
}

// A flag that takes one of an enum's names (core's parse()); `field` says where it goes.
template <class E, class Field>
Flag enumFlag(const char* name, const char* value, std::string help, Field field) {
    return {name, value, std::move(help), [=](Options& o, const std::string& v) {
                field(o) = toEnum<E>(name, v, choiceWords(value).c_str());
            }};
}

// A method's own parameter (core/methods.h) as a flag: parsed, then checked against its range.
Flag methodFlag(const MethodParam& p) {
    return {p.flag, p.value, p.help, [&p](Options& o, const std::string& v) {
                Settings& s = o.job.settings;
                if (p.boolField) {
                    s.*(p.boolField) = true;
                    return;
                }
                const NamedValue* named = findNamed(p, v);
                // A word that is neither a name nor a number: list the forms the flag takes.
                char* end = nullptr;
                std::strtod(v.c_str(), &end);
                if (!named && !p.named.empty() && (v.empty() || *end != '\0'))
                    throw UsageError(std::string(p.flag) + " expects " + p.value + ", got '" + v + "'");
                const double x = named ? named->value : p.intField ? (double)toInt(p.flag, v) : toNumber(p.flag, v);
                const std::string problem = checkParam(p, x, named != nullptr);
                if (!problem.empty()) throw UsageError(problem + ", got '" + v + "'");
                if (p.intField) s.*(p.intField) = (int)x;
                else s.*(p.floatField) = (float)x;
            }};
}

// --method and --quality list what the method table holds.
std::string methodHelp() {
    std::string h = "the occlusion method (default hbao):";
    for (const MethodInfo& m : methods())
        h += std::string("\n" + std::string(34, ' ')) + m.name + ": " + m.description + (m.gl ? "" : " [cpu only]");
    return h;
}
std::string qualityHelp() {
    std::string h = "sample-count preset per method (default medium; discs default to k 1); a method's own flags "
                    "and --blur override it, wherever they stand:";
    for (const MethodInfo& m : methods()) {
        if (m.presets.empty()) continue;
        h += std::string("\n" + std::string(34, ' ')) + m.name + ":";
        for (const MethodPreset& p : m.presets) h += std::string(" ") + p.quality + " " + p.summary + ";";
        h.pop_back();
    }
    return h;
}

std::vector<Flag> makeFlags();

const std::vector<Flag>& flags() {
    static const std::vector<Flag> table = makeFlags();
    return table;
}

// One row per flag, in --help's order: a table, so longer than a function should be.
std::vector<Flag> makeFlags() {
    std::vector<Flag> table = {
        {"-o", "OUTPUT.exr", "output file: a copy of the input with the new layers added (see --write)",
         [](Options& o, const std::string& v) { o.job.output = v; }},
        enumFlag<WriteMode>("--write", "copy|new|append",
         "copy: every input channel plus the new layers (default); new: only the new layers, with the "
         "input's windows, camera and colour attributes, and its codec unless lossy (then zip); the "
         "input's other channels are not decoded, so it is faster; append: the input's parts copied "
         "as compressed chunks, untouched, plus a part holding the new layers (fastest for a full file)",
         [](Options& o) -> auto& { return o.job.write; }),
        {"--method", "NAME", methodHelp(), [](Options& o, const std::string& v) {
             if (!findMethod(v)) throw UsageError("--method expects " + methodNames(", ") + ", got '" + v + "'");
             o.job.settings.method = v;
         }},
        {"--radius", "R", "occlusion radius in world units (default 1)",
         [](Options& o, const std::string& v) { o.job.settings.radius = (float)toSetting("--radius", v); }},
        enumFlag<Weighting>("--weighting", "uniform|cosine",
                            "solid angle (HBAO paper, default) or projected solid angle (ray-traced AO)",
                            [](Options& o) -> auto& { return o.job.settings.weighting; }),
        enumFlag<Falloff>("--falloff", "linear|none", "W(r) = 1 - r/R (default) or binary visibility within R",
                          [](Options& o) -> auto& { return o.job.settings.falloff; }),
        {"--quality", "low|medium|high|ultra", qualityHelp(),
         [](Options& o, const std::string& v) {
             Settings scratch;
             if (!applyQualityPreset(v, scratch))
                 throw UsageError("--quality expects low, medium, high or ultra, got '" + v + "'");
             o.quality = v;  // applied once every flag is read (applyQuality)
         }},
        {"--blur", "N", "geometry-aware blur radius in pixels, 0 = off (default 1, the medium preset's; ssdo: 0 and the "
                       "default are the interleave width); hbao's and ssdo's also within R/4 across the surface",
         [](Options& o, const std::string& v) { o.job.settings.blur = (int)toSetting("--blur", v); }},
        {"--fov-deg", "F", "perspective camera, horizontal field of view of the display window",
         [](Options& o, const std::string& v) { o.job.camera.fovDeg = toSetting("--fov-deg", v); }},
        {"--focal-mm", "F", "perspective camera, focal length (with --aperture-mm, as a compositing app's camera node)",
         [](Options& o, const std::string& v) { o.job.camera.focalMm = toSetting("--focal-mm", v); }},
        {"--aperture-mm", "W", "with --focal-mm: the horizontal film back, spanning the display window's width",
         [](Options& o, const std::string& v) { o.job.camera.apertureMm = toSetting("--aperture-mm", v); }},
        {"--ortho-width", "W", "orthographic camera, W world units across the display window",
         [](Options& o, const std::string& v) { o.job.camera.orthoWidth = toSetting("--ortho-width", v); }},
        {"--camera-to-world", "m00,...,m33", "16 numbers, row-major, OpenGL convention (camera looks down -Z)",
         [](Options& o, const std::string& v) {
             const std::vector<double> rows = toNumbers("--camera-to-world", v, 16);
             std::array<double, 16> m{};
             std::copy(rows.begin(), rows.end(), m.begin());
             o.job.camera.cameraToWorld = m;
         }},
        {"--camera", "FILE.json", "camera sidecar (default: NAME.json next to the input, if present)",
         [](Options& o, const std::string& v) { o.job.camera.sidecarPath = v; }},
        enumFlag<DepthEncoding>("--depth", "planar|radial|inverse|normalized",
                                "how the depth is stored (default: the renderer preset's): camera Z, distance to "
                                "the eye, 1/Z, or normalised over --depth-range",
                                [](Options& o) -> auto& { return o.job.depthEncoding; }),
        {"--depth-range", "A,B", "--depth normalized: the distances stored as 0 and 1 (A > B: white is near)",
         [](Options& o, const std::string& v) {
             const std::vector<double> ends = toNumbers("--depth-range", v, 2);
             const std::string problem = depthRangeProblem(ends[0], ends[1], Spelling::Flag);
             if (!problem.empty()) throw UsageError(problem);
             o.job.depthRange = std::array<double, 2>{ends[0], ends[1]};
         }},
        enumFlag<NormalSpace>("--normals", "world|camera|depth",
                              "normal space (default: the renderer preset's); depth: reconstructed from the depth "
                              "and the camera, as they are when the file has no normal layer",
                              [](Options& o) -> auto& { return o.job.normalSpace; }),
        {nameListSetting("--view").flag, nameListSetting("--view").value, nameListSetting("--view").help,
         [](Options& o, const std::string& v) {
             const std::vector<std::string> names = splitNameList(v);
             const std::string problem = nameListProblem(nameListSetting("--view"), names, Spelling::Flag);
             if (!problem.empty()) throw UsageError(problem);
             o.job.views = names;
         }},
        {"--sky-depth", "D", "depth at or beyond which a pixel is sky (default: the preset's, 1e9)",
         [](Options& o, const std::string& v) { o.job.skyDepth = (float)toSetting("--sky-depth", v); }},
        {"--preset", "NAME", "renderer naming: auto (default), blender, arnold, renderman, vray, karma, generic",
         [](Options& o, const std::string& v) {
             const auto& names = presetNames();
             if (std::find(names.begin(), names.end(), v) == names.end())
                 throw UsageError("--preset: unknown renderer '" + v + "' (auto, blender, arnold, renderman, vray, karma, generic)");
             o.job.preset = v;
         }},
        {"--flat", "FILE.exr",
         "the input is a deep EXR (hbao: its surfaces are occluders, up to --deep-layers); FILE gives the "
         "passes and is what the output copies (a pattern with #### for sequences; docs/deep.md)",
         [](Options& o, const std::string& v) { o.flat = v; }},
        {"--per-element-ao", nullptr,
         "deep elements (one or more deep inputs, no --flat): also an AO per element, of its own visible "
         "surface with every element as occluders, in <ao layer>.<element>.Y, the file's stem less its frame "
         "number (hbao, --falloff none; docs/deep.md)",
         [](Options& o, const std::string&) { o.job.perElementAo = true; }},
        {"--layer", "ROLE=NAME", "use layer NAME for ROLE (depth, normal, position, beauty, albedo, direct-diffuse)",
         [](Options& o, const std::string& v) {
             auto [role, name] = splitAssignment("--layer", v);
             Role r;
             if (!parseRole(role, r))
                 throw UsageError("--layer: unknown role '" + role +
                                  "' (depth, normal, position, beauty, albedo, direct-diffuse)");
             o.job.layerOverrides[r] = name;
         }},
        {"--out-layer", "ROLE=NAME",
         "name an output layer: ao (default obscura.AO, channel NAME.Y), do, gi, relit (obscura.DO/GI/relit, "
         "channels NAME.R/G/B); naming gi or relit also asks for it",
         [](Options& o, const std::string& v) {
             auto [role, name] = splitAssignment("--out-layer", v);
             const std::string problem = outLayerProblem(name);
             if (!problem.empty()) throw UsageError("--out-layer " + role + ": the name " + problem);
             o.outputs.push_back(role);
             if (role == "ao") o.job.aoLayer = name;
             else if (role == "do") o.job.doLayer = name;
             else if (role == "gi") o.job.giLayer = name, o.job.writeIndirect = true;
             else if (role == "relit") o.job.relitLayer = name, o.job.writeRelit = true;
             else throw UsageError("--out-layer: unknown output '" + role + "' (ao, do, gi, relit)");
         }},
        {"--bounce", nullptr, "ssdo, hbao: one indirect bounce (GI layer) and relit = albedo x (DO + GI) / pi (hbao: no DO)",
         [](Options& o, const std::string&) { requestBounce(o.job); }},
        {"--bounce-source", "direct-diffuse|beauty|LAYER",
         "radiance of the bouncing surfaces (default direct-diffuse, times the albedo pass)",
         [](Options& o, const std::string& v) { o.job.bounceSource = v; }},
        {"--env", "FILE", "ssdo: lat-long environment map (EXR, HDR, ...) lighting the open directions",
         [](Options& o, const std::string& v) { o.job.envPath = v; }},
        {"--env-rotate", "DEG", "turn the environment about the up axis",
         [](Options& o, const std::string& v) { o.job.settings.envRotationDeg = (float)toSetting("--env-rotate", v); }},
        {"--env-intensity", "X", "multiply the environment (or sky) radiance (default 1)",
         [](Options& o, const std::string& v) { o.job.settings.envIntensity = (float)toSetting("--env-intensity", v); }},
        {"--sky", "R,G,B", "ssdo: constant sky radiance when there is no --env (default 1,1,1)",
         [](Options& o, const std::string& v) {
             const std::vector<double> c = toNumbers("--sky", v, 3);
             for (int i = 0; i < 3; ++i) {
                 if (!withinLight(c[i]))
                     throw UsageError("--sky radiance must be between 0 and 1e9, got '" + v + "'");
                 o.job.settings.skyRadiance[i] = (float)c[i];
             }
         }},
        {"--light", "X,Y,Z,R,G,B", "ssdo: a directional light (world direction towards it, irradiance); up to 4",
         [](Options& o, const std::string& v) {
             const std::vector<double> c = toNumbers("--light", v, 6);
             if (o.job.settings.lights.size() == 4) throw UsageError("--light: at most 4 directional lights");
             if (c[0] == 0 && c[1] == 0 && c[2] == 0) throw UsageError("--light: the direction must not be 0,0,0");
             for (int i = 3; i < 6; ++i)
                 if (!withinLight(c[i]))
                     throw UsageError("--light: the irradiance must be between 0 and 1e9, got '" + v + "'");
             Settings::DirectionalLight l{};
             for (int i = 0; i < 3; ++i) l.direction[i] = (float)c[i], l.irradiance[i] = (float)c[i + 3];
             o.job.settings.lights.push_back(l);
         }},
        {"--up", "y|z", "world up axis for the environment (default: z for Blender renders, else y)",
         [](Options& o, const std::string& v) {
             if (v != "y" && v != "z") throw UsageError("--up expects y or z, got '" + v + "'");
             o.job.zUp = v == "z";
         }},
        {"--colorspace", "NAME", "colour space of the input's colour passes (default: from the EXR header)",
         [](Options& o, const std::string& v) { o.job.colourSpace = v; }},
        {"--env-colorspace", "NAME", "colour space of the environment map (default: from its metadata)",
         [](Options& o, const std::string& v) { o.job.envColourSpace = v; }},
        {"--times-albedo", nullptr, "write DO and GI as albedo x E / pi (outgoing radiance) instead of irradiance E",
         [](Options& o, const std::string&) { o.job.timesAlbedo = true; }},
        {"--relit-direct", nullptr, "relit also adds the render's own direct diffuse light (albedo x direct)",
         [](Options& o, const std::string&) { o.job.relitWithDirect = true; }},
        {"--out-type", "half|float", "pixel type of the layers written (default half)",
         [](Options& o, const std::string& v) {
             if (v != "half" && v != "float") throw UsageError("--out-type expects half or float, got '" + v + "'");
             o.job.aoFloat = v == "float";
         }},
        {"--device", "auto|cpu|gl|gl-egl|gl-osmesa",
         "where to compute (cpu): auto = a hardware EGL GPU if present, else the CPU; gl = EGL, else OSMesa",
         [](Options& o, const std::string& v) {
             if (!isDeviceName(v)) throw UsageError("--device expects " + deviceNameList() + ", got '" + v + "'");
             o.job.settings.device = v;
         }},
        {"--threads", "N", "CPU threads (default 0 = all cores; at most the cores, shared by runs in one process)",
         [](Options& o, const std::string& v) { o.job.settings.threads = (int)toSetting("--threads", v); }},
        {"--max-pixels", "N", "refuse an input or environment map with a window above N pixels, before allocating "
                               "(default 268435456 = 16384 x 16384)",
         [](Options& o, const std::string& v) {
             o.job.maxPixels = (long long)toSetting("--max-pixels", v);
         }},
        {"--bad-pixels", "error|skip", "NaN/negative depth or missing normals: fail (default) or treat as holes",
         [](Options& o, const std::string& v) {
             if (v != "error" && v != "skip") throw UsageError("--bad-pixels expects error or skip, got '" + v + "'");
             o.job.badPixels = v == "skip" ? BadPixelPolicy::Skip : BadPixelPolicy::Error;
         }},
        {"--reference", "LAYER", "print MAE, RMSE, PSNR and p99 error of the AO against LAYER over non-sky pixels",
         [](Options& o, const std::string& v) { o.job.referenceLayer = v; }},
        {"--report", "FILE.json|DIR/", "write timings per stage, settings, camera and statistics (DIR/: OUTPUT's name .json there)",
         [](Options& o, const std::string& v) { o.reportPath = v; }},
        {"--preview", "FILE.png|DIR/", "write an 8-bit sRGB PNG of the AO (a lit run, ssdo or hbao --bounce: of the relit layer "
                                           "when written, else ssdo's DO or hbao's GI)",
         [](Options& o, const std::string& v) { o.job.previewPath = v; }},
        {"--preview-exposure", "EV", "stops applied before the preview's encoding (default: AO 0; a lit run automatic, "
                                     "the 99th percentile at 0.8)",
         [](Options& o, const std::string& v) { o.job.previewExposure = (float)toSetting("--preview-exposure", v); }},
        {"--in-place", nullptr, "allow OUTPUT to be the input file (replaced atomically)",
         [](Options& o, const std::string&) { o.job.inPlace = true; }},
        {"--frames", "LIST", "frames of a sequence (INPUT and -o hold #### or %04d): 1-100, 1-100x2, 1,5,9-12 "
                             "(default: every input frame found)",
         [](Options& o, const std::string& v) { o.frames = v; }},
        {"--resume", nullptr, "skip frames whose output (and --report, --preview) already exists complete; clear a killed run's "
                           "temp files",
         [](Options& o, const std::string&) { o.resume = true; }},
        {"--keep-going", nullptr, "a sequence: go on past a failing frame (its line printed, its --report holding the "
                                  "error) and fail at the end, naming the frames that failed",
         [](Options& o, const std::string&) { o.keepGoing = true; }},
        {"--inspect", nullptr, "print the layers found, the role of each and the camera, then exit",
         [](Options& o, const std::string&) { o.inspect = true; }},
        {"--json", nullptr, "with --inspect: print the same as JSON (what Python's obscura.inspect returns)",
         [](Options& o, const std::string&) { o.inspectJson = true; }},
        {"--quiet", nullptr, "print nothing but errors", [](Options& o, const std::string&) { o.quiet = true; }},
        {"--version", nullptr, "print the version", [](Options& o, const std::string&) { o.version = true; }},
        {"--help", nullptr, "this text", [](Options& o, const std::string&) { o.help = true; }},
    };
    // Each method's own parameters, from the method table, after the shared sampling flags.
    auto at = std::find_if(table.begin(), table.end(), [](const Flag& f) { return std::string(f.name) == "--blur"; });
    std::vector<Flag> own;
    for (const MethodParam* p : allMethodParams()) own.push_back(methodFlag(*p));
    table.insert(at, own.begin(), own.end());
    return table;
}

// A flag or output the method would ignore is refused, naming the methods that read it
// (core/methods.h), so a run never exits 0 without doing what it was asked.
void refuseWhatTheMethodIgnores(const Options& o) {
    const std::string& method = o.job.settings.method;
    for (const std::string& flag : o.given) {
        const std::string problem = settingRefusal(method, flag, Spelling::Flag);
        if (!problem.empty()) throw UsageError(problem);
    }
    for (const std::string& output : o.outputs) {
        const std::string problem = outputRefusal(method, output, Spelling::Flag);
        if (!problem.empty()) throw UsageError(problem);
    }
}

// Several inputs are deep elements, merged (docs/deep.md); one stays the input, deep or flat.
void checkDeepElements(Options& o) {
    std::vector<std::string>& elements = o.job.deepElements;
    if (elements.size() > 1) {
        if (!o.flat.empty())
            throw UsageError("--flat takes one deep input; several inputs are deep elements, merged without a flat file");
        for (const std::string& e : elements)
            if (isFramePattern(e) != isFramePattern(elements[0]))
                throw UsageError("deep elements must all be frame patterns (e.g. balls.####.exr), or none");
    } else {
        elements.clear();  // one input: a flat file, or a deep element found when it is read
    }
    const std::string problem = perElementAoProblem(o.job, Spelling::Flag);
    if (!problem.empty()) throw UsageError(problem);
}

} // namespace

std::string helpText() {
    std::ostringstream os;
    os << "obscura " << OBSCURA_VERSION_STRING
       << " - screen-space ambient and directional occlusion for multilayer OpenEXR renders\n\n"
          "usage: obscura INPUT.exr -o OUTPUT.exr [options]\n"
          "       obscura ELEMENT.exr... -o OUTPUT.exr [options]   (deep elements, merged; docs/deep.md)\n"
          "       obscura INPUT.exr --inspect\n"
          "       obscura farm slurm|summary ...   (a sequence as farm work; obscura farm --help)\n\n"
          "The input's passes (depth, normals, position) are found by renderer preset; the camera comes\n"
          "from the flags, a JSON sidecar, the EXR header, or a fit to the position pass, in that order.\n"
          "The output is the input with every channel and attribute kept, plus the new layers\n"
          "(--write new: only the new layers, in a file of their own).\n\n"
          "options:\n";
    for (const Flag& f : flags()) {
        std::string left = std::string("  ") + f.name + (f.value ? std::string(" ") + f.value : "");
        if (left.size() < 34) left.resize(34, ' ');
        else left += "\n" + std::string(34, ' ');
        os << left << f.help << "\n";
    }
    os << "\nexample:\n  obscura shot.0001.exr -o shot_ao.0001.exr --radius 0.5 --weighting cosine --falloff none \\\n"
          "          --reference ViewLayer.AO --report shot_ao.0001.json\n"
          "\nexit status: 0 success, 1 failure (one line on stderr), 2 bad command line, 130 / 143 stopped by Ctrl-C /\n"
          "  SIGTERM (the frame being computed not written, no temporary file left)\n";
    return os.str();
}

// The quality level sets each method's fields but those whose flag was given, before or after
// --quality (--blur sets its own field, which wins over the level's blur in resolvedBlur).
void applyQuality(Options& o) {
    if (o.quality.empty()) return;
    Settings level = o.job.settings;
    applyQualityPreset(o.quality, level);
    const Settings& flags = o.job.settings;
    for (const MethodInfo& m : methods())
        for (const MethodParam& p : m.params) {
            if (std::find(o.given.begin(), o.given.end(), std::string(p.flag)) == o.given.end()) continue;
            if (p.intField) level.*p.intField = flags.*p.intField;
            if (p.floatField) level.*p.floatField = flags.*p.floatField;
            if (p.boolField) level.*p.boolField = flags.*p.boolField;
        }
    o.job.settings = level;
}

Options parseArgs(int argc, char** argv) {
    Options o;
    for (int i = 1; i < argc; ++i) {
        std::string arg = argv[i];
        if (arg == "-h") arg = "--help";
        if (arg.size() > 1 && arg[0] == '-' && !(arg.size() > 1 && (std::isdigit((unsigned char)arg[1]) || arg[1] == '.'))) {
            std::string value;
            bool inlineValue = false;
            const size_t eq = arg.find('=');
            if (arg.rfind("--", 0) == 0 && eq != std::string::npos) {
                value = arg.substr(eq + 1);
                arg = arg.substr(0, eq);
                inlineValue = true;
            }
            const Flag* flag = nullptr;
            for (const Flag& f : flags())
                if (arg == f.name) flag = &f;
            if (!flag) throw UsageError("unknown option '" + arg + "' (see obscura --help)");
            if (flag->value && !inlineValue) {
                if (i + 1 >= argc) throw UsageError(arg + " needs a value: " + flag->value);
                value = argv[++i];
            } else if (!flag->value && inlineValue) {
                throw UsageError(arg + " takes no value");
            }
            flag->apply(o, value);
            o.given.push_back(flag->name);
            continue;
        }
        if (o.job.input.empty()) o.job.input = arg;
        o.job.deepElements.push_back(arg);
    }
    applyQuality(o);
    checkDeepElements(o);
    if (!o.flat.empty()) {
        if (!methodReads(o.job.settings.method, "deep"))
            throw UsageError("--flat (deep input) works with --method " + methodNames(", ", "deep") + " only");
        o.job.deepInput = o.job.input;
        o.job.input = o.flat;
        // One pattern without the other would read the same deep file for every frame.
        if (isFramePattern(o.job.deepInput) != isFramePattern(o.job.input))
            throw UsageError("the deep input and --flat must both be frame patterns (e.g. shot.####.exr), or neither");
    }
    refuseWhatTheMethodIgnores(o);
    if (o.job.previewExposure && o.job.previewPath.empty()) throw UsageError("--preview-exposure needs --preview FILE.png");
    if (o.job.depthRange && o.job.depthEncoding != DepthEncoding::Normalized)
        throw UsageError("--depth-range is read by --depth normalized only");
    if (const std::string lens = lensProblem(o.job.camera, Spelling::Flag); !lens.empty()) throw UsageError(lens);
    const MethodInfo& m = *findMethod(o.job.settings.method);
    const std::string& d = o.job.settings.device;
    if (!m.gl && d != "cpu" && d != "auto")
        throw UsageError("--method " + o.job.settings.method + " runs on the CPU only (--device cpu), not --device " + d);
    return o;
}

} // namespace obscura::cli
