#include "cli.h"

#include "core/error.h"
#include "gpu/gl_backend.h"
#include "io/frame_job.h"

#include <unistd.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

namespace obscura::cli {

namespace {

struct UsageError : Error {
    using Error::Error;
};

struct Options {
    FrameJob job;
    bool inspect = false, quiet = false, help = false, version = false;
    std::string reportPath;
};

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

template <class E>
E toEnum(const std::string& flag, const std::string& v, const char* choices) {
    E e{};
    if (!parse(v, e)) throw UsageError(flag + " expects " + choices + ", got '" + v + "'");
    return e;
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
    const char* help;
    std::function<void(Options&, const std::string&)> apply;
};

const std::vector<Flag>& flags() {
    static const std::vector<Flag> table = {
        {"-o", "OUTPUT.exr", "output file: a copy of the input with the AO layer added",
         [](Options& o, const std::string& v) { o.job.output = v; }},
        {"--method", "hbao", "occlusion method (default hbao)",
         [](Options& o, const std::string& v) { o.job.settings.method = v; }},
        {"--radius", "R", "occlusion radius in world units (default 1)",
         [](Options& o, const std::string& v) {
             o.job.settings.radius = (float)toNumber("--radius", v);
             if (!(o.job.settings.radius > 0.0f)) throw UsageError("--radius must be positive, got '" + v + "'");
         }},
        {"--directions", "N", "directions (slices) per pixel (default 8)",
         [](Options& o, const std::string& v) { o.job.settings.directions = toInt("--directions", v); }},
        {"--steps", "N", "samples per direction (default 8)",
         [](Options& o, const std::string& v) { o.job.settings.steps = toInt("--steps", v); }},
        {"--weighting", "uniform|cosine", "solid angle (HBAO paper, default) or projected solid angle (ray-traced AO)",
         [](Options& o, const std::string& v) {
             o.job.settings.weighting = toEnum<Weighting>("--weighting", v, "uniform or cosine");
         }},
        {"--falloff", "linear|none", "W(r) = 1 - r/R (default) or binary visibility within R",
         [](Options& o, const std::string& v) { o.job.settings.falloff = toEnum<Falloff>("--falloff", v, "linear or none"); }},
        {"--quality", "low|medium|high|ultra",
         "sample-count preset: 4x4+blur 2, 8x8+blur 1, 16x12, 32x24 (directions x steps); later flags override",
         [](Options& o, const std::string& v) {
             if (!applyQualityPreset(v, o.job.settings))
                 throw UsageError("--quality expects low, medium, high or ultra, got '" + v + "'");
         }},
        {"--blur", "N", "geometry-aware blur radius in pixels (default 0, off)",
         [](Options& o, const std::string& v) { o.job.settings.blur = toInt("--blur", v); }},
        {"--fov-deg", "F", "perspective camera, horizontal field of view of the display window",
         [](Options& o, const std::string& v) { o.job.camera.fovDeg = toNumber("--fov-deg", v); }},
        {"--ortho-width", "W", "orthographic camera, W world units across the display window",
         [](Options& o, const std::string& v) { o.job.camera.orthoWidth = toNumber("--ortho-width", v); }},
        {"--camera-to-world", "m00,...,m33", "16 numbers, row-major, OpenGL convention (camera looks down -Z)",
         [](Options& o, const std::string& v) {
             std::array<double, 16> m{};
             std::stringstream ss(v);
             std::string item;
             int n = 0;
             while (std::getline(ss, item, ',')) {
                 if (n == 16) throw UsageError("--camera-to-world expects 16 comma-separated numbers");
                 m[n++] = toNumber("--camera-to-world", item);
             }
             if (n != 16) throw UsageError("--camera-to-world expects 16 comma-separated numbers, got " + std::to_string(n));
             o.job.camera.cameraToWorld = m;
         }},
        {"--camera", "FILE.json", "camera sidecar (default: NAME.json next to the input, if present)",
         [](Options& o, const std::string& v) { o.job.camera.sidecarPath = v; }},
        {"--depth", "planar|radial", "depth convention (default: the renderer preset's)",
         [](Options& o, const std::string& v) { o.job.depthKind = toEnum<DepthKind>("--depth", v, "planar or radial"); }},
        {"--normals", "world|camera", "normal space (default: the renderer preset's)",
         [](Options& o, const std::string& v) {
             o.job.normalSpace = toEnum<NormalSpace>("--normals", v, "world or camera");
         }},
        {"--sky-depth", "D", "depth at or beyond which a pixel is sky (default: the preset's, 1e9)",
         [](Options& o, const std::string& v) { o.job.skyDepth = (float)toNumber("--sky-depth", v); }},
        {"--preset", "NAME", "renderer naming: auto (default), blender, arnold, renderman, vray, karma, generic",
         [](Options& o, const std::string& v) {
             const auto& names = presetNames();
             if (std::find(names.begin(), names.end(), v) == names.end())
                 throw UsageError("--preset: unknown renderer '" + v + "' (auto, blender, arnold, renderman, vray, karma, generic)");
             o.job.preset = v;
         }},
        {"--layer", "ROLE=NAME", "use layer NAME for ROLE (depth, normal, position, beauty, albedo, direct-diffuse)",
         [](Options& o, const std::string& v) {
             auto [role, name] = splitAssignment("--layer", v);
             Role r;
             if (!parseRole(role, r))
                 throw UsageError("--layer: unknown role '" + role +
                                  "' (depth, normal, position, beauty, albedo, direct-diffuse)");
             o.job.layerOverrides[r] = name;
         }},
        {"--out-layer", "ao=NAME", "name of the AO layer written (default obscura.AO; channel NAME.Y)",
         [](Options& o, const std::string& v) {
             auto [role, name] = splitAssignment("--out-layer", v);
             if (role != "ao") throw UsageError("--out-layer: unknown output '" + role + "' (available: ao)");
             o.job.aoLayer = name;
         }},
        {"--out-type", "half|float", "pixel type of the AO channel (default half)",
         [](Options& o, const std::string& v) {
             if (v != "half" && v != "float") throw UsageError("--out-type expects half or float, got '" + v + "'");
             o.job.aoFloat = v == "float";
         }},
        {"--device", "auto|cpu|gl|gl-egl|gl-osmesa",
         "where to compute (cpu): auto = a hardware EGL GPU if present, else the CPU; gl = EGL, else OSMesa",
         [](Options& o, const std::string& v) {
             if (!gpu::isDeviceName(v))
                 throw UsageError("--device expects auto, cpu, gl, gl-egl or gl-osmesa, got '" + v + "'");
             o.job.settings.device = v;
         }},
        {"--threads", "N", "CPU threads (default 0 = all cores)",
         [](Options& o, const std::string& v) { o.job.settings.threads = toInt("--threads", v); }},
        {"--bad-pixels", "error|skip", "NaN/negative depth or missing normals: fail (default) or treat as holes",
         [](Options& o, const std::string& v) {
             if (v != "error" && v != "skip") throw UsageError("--bad-pixels expects error or skip, got '" + v + "'");
             o.job.badPixels = v == "skip" ? BadPixelPolicy::Skip : BadPixelPolicy::Error;
         }},
        {"--reference", "LAYER", "print MAE, RMSE, PSNR and p99 error of the AO against LAYER over non-sky pixels",
         [](Options& o, const std::string& v) { o.job.referenceLayer = v; }},
        {"--report", "FILE.json", "write timings per stage, settings, camera and statistics",
         [](Options& o, const std::string& v) { o.reportPath = v; }},
        {"--preview", "FILE.png", "write an 8-bit PNG of the AO",
         [](Options& o, const std::string& v) { o.job.previewPath = v; }},
        {"--in-place", nullptr, "allow OUTPUT to be the input file (replaced atomically)",
         [](Options& o, const std::string&) { o.job.inPlace = true; }},
        {"--inspect", nullptr, "print the layers found, the role of each and the camera, then exit",
         [](Options& o, const std::string&) { o.inspect = true; }},
        {"--quiet", nullptr, "print nothing but errors", [](Options& o, const std::string&) { o.quiet = true; }},
        {"--version", nullptr, "print the version", [](Options& o, const std::string&) { o.version = true; }},
        {"--help", nullptr, "this text", [](Options& o, const std::string&) { o.help = true; }},
    };
    return table;
}

std::string helpText() {
    std::ostringstream os;
    os << "obscura " << OBSCURA_VERSION_STRING
       << " - screen-space ambient occlusion for multilayer OpenEXR renders\n\n"
          "usage: obscura INPUT.exr -o OUTPUT.exr [options]\n"
          "       obscura INPUT.exr --inspect\n\n"
          "The input's passes (depth, normals, position) are found by renderer preset; the camera comes\n"
          "from the flags, a JSON sidecar, the EXR header, or a fit to the position pass, in that order.\n"
          "The output is the input with every channel and attribute kept, plus the AO layer.\n\n"
          "options:\n";
    for (const Flag& f : flags()) {
        std::string left = std::string("  ") + f.name + (f.value ? std::string(" ") + f.value : "");
        if (left.size() < 34) left.resize(34, ' ');
        else left += "\n" + std::string(34, ' ');
        os << left << f.help << "\n";
    }
    os << "\nexample:\n  obscura shot.0001.exr -o shot_ao.0001.exr --radius 0.5 --weighting cosine --falloff none \\\n"
          "          --reference ViewLayer.AO --report shot.0001.json\n"
          "\nexit status: 0 success, 1 failure (one line on stderr), 2 bad command line\n";
    return os.str();
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
            continue;
        }
        if (!o.job.input.empty()) throw UsageError("more than one input file given ('" + o.job.input + "', '" + arg + "')");
        o.job.input = arg;
    }
    return o;
}

void printSummary(const Options& o, const FrameReport& r) {
    double total = 0;
    for (const StageTiming& t : r.stages) total += t.seconds;
    std::fprintf(stderr, "obscura: %s -> %s  [%s]  %lld px (%lld sky)  %.3f s (", o.job.input.c_str(),
                 o.job.output.c_str(), r.aoChannel.c_str(), r.stats.pixels, r.stats.skyPixels, total);
    for (size_t i = 0; i < r.stages.size(); ++i)
        std::fprintf(stderr, "%s%s %.3f", i ? ", " : "", r.stages[i].name.c_str(), r.stages[i].seconds);
    std::fprintf(stderr, ")\n");
    std::fprintf(stderr, "obscura: camera from %s; %s\n", r.camera.source.c_str(), r.stats.device.c_str());
    for (const std::string& w : r.warnings) std::fprintf(stderr, "obscura: warning: %s\n", w.c_str());
}

void writeTextFile(const std::string& path, const std::string& text) {
    const std::string tmp = path + ".tmp-" + std::to_string(::getpid());
    {
        std::ofstream f(tmp, std::ios::binary);
        f << text << "\n";
        if (!f.good()) {
            std::remove(tmp.c_str());
            throw Error("cannot write '" + path + "'");
        }
    }
    if (std::rename(tmp.c_str(), path.c_str()) != 0) {
        std::remove(tmp.c_str());
        throw Error("cannot write '" + path + "'");
    }
}

} // namespace

int run(int argc, char** argv) {
    Options o;
    try {
        o = parseArgs(argc, argv);
        if (o.help) {
            std::fputs(helpText().c_str(), stdout);
            return 0;
        }
        if (o.version) {
            std::printf("obscura %s\n", OBSCURA_VERSION_STRING);
            return 0;
        }
        if (o.job.input.empty()) throw UsageError("no input file (usage: obscura INPUT.exr -o OUTPUT.exr; see --help)");
        if (o.inspect) {
            std::fputs(inspectFrame(o.job).c_str(), stdout);
            return 0;
        }
        if (o.job.output.empty()) throw UsageError("no output file: give -o OUTPUT.exr (or --inspect)");
        if (!o.reportPath.empty()) requireOutputDirectory(o.reportPath);
        const FrameReport report = runFrameJob(o.job);
        if (report.reference) {
            const ErrorMetrics& m = *report.reference;
            std::printf("reference %s: MAE %.5f  RMSE %.5f  PSNR %.2f dB  p99 %.5f  (%lld pixels)\n",
                        o.job.referenceLayer.c_str(), m.mae, m.rmse, m.psnr, m.p99, m.pixels);
        }
        if (!o.reportPath.empty()) writeTextFile(o.reportPath, frameReportJson(o.job, report));
        if (!o.quiet) printSummary(o, report);
        return 0;
    } catch (const UsageError& e) {
        std::fprintf(stderr, "obscura: %s\n", e.what());
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "obscura: %s\n", e.what());
        return 1;
    }
}

} // namespace obscura::cli
