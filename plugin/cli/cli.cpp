#include "cli.h"
#include "cli/cli_options.h"
#include "cli/stop_signals.h"

#include "base/error.h"
#include "core/methods.h"
#include "io/atomic_files.h"
#include "io/frame_job.h"
#include "io/inspect.h"
#include "io/views.h"
#include "io/sequence.h"
#include "io/exr_chunk_table.h"
#include "io/write_guard.h"

#include <OpenEXR/ImfStringAttribute.h>
#include <nlohmann/json.hpp>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

namespace obscura::cli {

namespace {

// The layers written, each with its channels' last components: "obscura.AO.Y, obscura.GI.RGB"
// ("view left: obscura.AO.Y" where each view has a part of its own and the names repeat).
std::string writtenLayers(const FrameReport& r) {
    std::vector<std::pair<std::string, std::string>> layers;
    for (size_t i = 0; i < r.written.size(); ++i) {
        const std::string& c = r.written[i];
        const std::string view = i < r.writtenViews.size() && !r.writtenViews[i].empty() ? "view " + r.writtenViews[i] + ": " : "";
        const size_t dot = c.rfind('.');
        const std::string layer = view + (dot == std::string::npos ? "" : c.substr(0, dot + 1));
        const std::string channel = dot == std::string::npos ? c : c.substr(dot + 1);
        if (!layers.empty() && layers.back().first == layer) layers.back().second += channel;
        else layers.push_back({layer, channel});
    }
    std::string text;
    for (const auto& [layer, channels] : layers) text += (text.empty() ? "" : ", ") + layer + channels;
    return text.empty() ? r.aoChannel : text;
}

void printSummary(const Options& o, const FrameReport& r) {
    double total = 0;
    for (const StageTiming& t : r.stages) total += t.seconds;
    std::fprintf(stderr, "obscura: %s -> %s  [%s]  %lld px (%lld sky)  %.3f s (", o.job.input.c_str(),
                 o.job.output.c_str(), writtenLayers(r).c_str(), r.stats.pixels, r.stats.skyPixels, total);
    for (size_t i = 0; i < r.stages.size(); ++i)
        std::fprintf(stderr, "%s%s %.3f", i ? ", " : "", r.stages[i].name.c_str(), r.stages[i].seconds);
    std::fprintf(stderr, ")\n");
    std::fprintf(stderr, "obscura: camera from %s; %s%s\n", r.camera.source.c_str(), r.stats.device.c_str(),
                 r.stats.normalsFromDepth ? "; normals reconstructed from depth" : "");
    for (const std::string& w : r.warnings) std::fprintf(stderr, "obscura: warning: %s\n", w.c_str());
}

void runOneFrame(const Options& o, const FrameJob& job, const std::string& reportPath) {
    if (!reportPath.empty()) requireWritableDestination(reportPath);
    WriteBatch files;  // the output, preview and report land together or not at all
    const FrameReport report = runFrameJob(job);
    if (report.reference) {
        const ErrorMetrics& m = *report.reference;
        std::printf("reference %s: MAE %.5f  RMSE %.5f  PSNR %.2f dB  p99 %.5f  (%lld pixels)\n",
                    job.referenceLayer.c_str(), m.mae, m.rmse, m.psnr, m.p99, m.pixels);
    }
    if (!reportPath.empty()) writeTextFileAtomically(reportPath, frameReportJson(job, report));
    files.commit();
    if (!o.quiet && !isFramePattern(o.job.input)) printSummary(o, report);
}

// With --report, a frame is complete once its report is written too (it comes after the output),
// and the report is not a failure's; with --preview, once the preview exists.
// The output's headers when the frame is complete (its output, preview and report), else nullopt.
std::optional<ExrInfo> frameComplete(const FrameJob& job, const std::string& reportPath) {
    std::optional<ExrInfo> output = completeOutput(job.output, aoChannelName(job.aoLayer));
    std::error_code ec;
    if (!output || (!job.previewPath.empty() && !std::filesystem::is_regular_file(job.previewPath, ec))) return std::nullopt;
    if (reportPath.empty()) return output;
    std::ifstream f(reportPath);
    const nlohmann::json report = nlohmann::json::parse(f, nullptr, false);
    if (report.is_object() && report.contains("total_s") && !report.contains("error")) return output;
    return std::nullopt;
}

// A failed frame's report holds the error, so `obscura farm summary` can tell failed from missing.
void writeFailureReport(const FrameJob& job, int frame, const std::string& reportPath, const std::string& what) {
    if (reportPath.empty()) return;
    try {
        writeTextFileAtomically(reportPath, frameFailureJson(job, frame, what));
    } catch (const std::exception&) {
        // The frame's own error is the one to report.
    }
}

// --resume, for one frame as for a sequence: the temp files of a run killed mid-frame (a farm
// task, a dead node) are cleared, then a complete frame is skipped (true), unless it is stale
// (a job resubmitted with a new radius, a frame rendered again), which is computed again.
bool resumeSkips(const Options& o, const FrameJob& job, const std::string& reportPath) {
    if (!o.resume) return false;
    for (const std::string& path : {job.output, reportPath, job.previewPath})
        if (!path.empty()) removeStaleTemps(path);
    const std::optional<ExrInfo> output = frameComplete(job, reportPath);
    if (!output) return false;
    const std::string stale = staleOutputReason(job, *output);
    if (stale.empty()) return true;
    if (!o.quiet) std::fprintf(stderr, "obscura: %s %s; computed again (--resume)\n", job.output.c_str(), stale.c_str());
    return false;
}

// A --report or --preview that is neither a pattern nor a directory would be overwritten by
// every frame of the sequence, keeping only the last.
void requirePerFrame(const char* flag, const std::string& spec, const char* example) {
    if (spec.empty() || isFramePattern(spec)) return;
    throw UsageError(std::string(flag) + " '" + spec + "' would be rewritten by every frame: give a pattern (" + example +
                     ") or a directory");
}

// The message as one printable line: control bytes (a corrupt file's names may hold
// newlines) become '?', trailing whitespace is dropped.
static std::string printableLine(std::string s) {
    for (char& c : s)
        if ((unsigned char)c < 0x20 || c == 0x7f) c = '?';
    while (!s.empty() && s.back() == ' ') s.pop_back();
    return s;
}

// --inspect: the file, or of a sequence its first frame (or --frames' first), as every frame
// runs alike; the command then runs that frame, and a note says how to run them all.
nlohmann::json inspectSequenceOrFrame(const Options& o) {
    if (!isFramePattern(o.job.input)) return inspectFrameJson(o.job);
    const std::string& pattern = o.job.deepInput.empty() ? o.job.input : o.job.deepInput;
    const std::vector<int> frames = o.frames.empty() ? existingFrames(pattern) : parseFrames(o.frames);
    if (frames.empty()) throw FileError(o.job.input, "no frames match");
    nlohmann::json j = inspectFrameJson(sequenceFrame(o.job, frames.front()));
    j["sequence"] = {{"pattern", o.job.input}, {"frames", frames.size()}, {"described", frames.front()}};
    j["command_notes"].push_back("sequence: " + std::to_string(frames.size()) + " frame(s) of " + o.job.input +
                                 "; the command runs frame " + std::to_string(frames.front()) +
                                 ": give the pattern as the input and -o with #### to run them all");
    return j;
}

// A frame's failure as the run reports it: 'FILE': frame N: what, the number after the file.
FileError frameFailure(const FrameJob& job, int frame, const std::string& what) {
    return FileError(job.input, "frame " + std::to_string(frame) + ": " + withoutFilePrefix(what, job.input));
}

// A sequence's frames, each frame's job and report, checked as a run checks them before its first
// frame: a pattern for every per-frame file, no file written twice or over one read (every
// frame's), and the directories written into there.
struct SequenceFrames {
    std::vector<int> frames;
    std::vector<FrameJob> jobs;
    std::vector<std::string> reports;
};

SequenceFrames planSequence(const Options& o) {
    if (!isFramePattern(o.job.output)) throw UsageError("the input is a sequence: -o needs a pattern too (e.g. out.####.exr)");
    requirePerFrame("--report", o.reportPath, "out.####.json");
    requirePerFrame("--preview", o.job.previewPath, "out.####.png");
    SequenceFrames s;
    try {
        // With --flat the deep file is the input: its frames are the sequence's.
        s.frames = o.frames.empty() ? existingFrames(o.job.deepInput.empty() ? o.job.input : o.job.deepInput)
                                    : parseFrames(o.frames);
    } catch (const FileError&) {
        throw;
    } catch (const Error& e) {  // a --frames list that does not parse: the command line
        throw UsageError(e.what());
    }
    if (s.frames.empty()) throw FileError(o.job.input, "no frames match");
    std::vector<FrameFiles> files;
    for (int frame : s.frames) {
        s.jobs.push_back(sequenceFrame(o.job, frame));
        s.reports.push_back(framePath(o.reportPath, frame));
    }
    for (size_t i = 0; i < s.frames.size(); ++i) files.push_back({&s.jobs[i], s.reports[i]});
    checkFrameFiles(files, Spelling::Flag);  // every frame's files, before the first is written
    for (const std::string& written : {s.jobs.front().output, s.reports.front(), s.jobs.front().previewPath})
        if (!written.empty()) requireOutputDirectory(written);  // before the first frame is computed
    return s;
}

// A frame sequence, with a progress line and --resume; stops at the first failing frame, or with
// --keep-going runs every frame and fails at the end, naming the frames that failed.
int runSequence(const Options& o) {
    const SequenceFrames plan = planSequence(o);
    const std::vector<int>& frames = plan.frames;
    const bool tty = ::isatty(2);
    const auto start = std::chrono::steady_clock::now();
    int done = 0, skipped = 0;
    std::vector<int> failed;
    for (size_t i = 0; i < frames.size(); ++i) {
        const FrameJob& job = plan.jobs[i];
        const std::string& reportPath = plan.reports[i];
        if (resumeSkips(o, job, reportPath)) {
            ++skipped;
        } else {
            try {
                throwIfCancelled();
                runOneFrame(o, job, reportPath);
            } catch (const UsageError&) {
                throw;
            } catch (const Cancelled&) {
                if (tty && !o.quiet) std::fputc('\n', stderr);
                std::string what = "frame " + std::to_string(frames[i]) + " is not written (--resume goes on from there)";
                if (!failed.empty()) what += "; frame(s) that failed before it: " + frameSpec(failed);
                endByStopSignal(what.c_str());
            } catch (const std::exception& e) {
                if (tty && !o.quiet) std::fputc('\n', stderr);
                writeFailureReport(job, frames[i], reportPath, e.what());
                const FileError failure = frameFailure(job, frames[i], e.what());
                if (!o.keepGoing) throw failure;
                std::fprintf(stderr, "obscura: %s\n", printableLine(failure.what()).c_str());
                failed.push_back(frames[i]);
                continue;
            }
            ++done;
        }
        if (o.quiet) continue;
        const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        const double perFrame = done ? elapsed / done : 0.0;
        const int left = (int)(frames.size() - i - 1);
        const int bar = (int)(20 * (i + 1) / frames.size());
        std::fprintf(stderr, "%sobscura: [%s%s] %zu/%zu frames (%d skipped), %.2f s/frame, ETA %.0f s%s",
                     tty ? "\r" : "", std::string(bar, '#').c_str(), std::string(20 - bar, '.').c_str(), i + 1,
                     frames.size(), skipped, perFrame, perFrame * left, tty ? "" : "\n");
    }
    if (tty && !o.quiet) std::fputc('\n', stderr);
    endIfStopped(failed.empty() ? "every frame was written first"
                                : ("frame(s) that failed: " + frameSpec(failed)).c_str());
    if (!failed.empty())
        throw FileError(o.job.input, std::to_string(failed.size()) + " of " + std::to_string(frames.size()) +
                                         " frame(s) failed (--keep-going): " + frameSpec(failed));
    return 0;
}

} // namespace

// Writes are atomic, so a file that exists was written whole; the read guards against other writers.
namespace {
// Whether a part holds the AO channel (of a stereo file, in any view, by channel names).
bool holdsAo(const ExrPart& part, const std::string& aoChannel, const std::vector<std::string>& views) {
    if (part.findChannel(aoChannel) >= 0) return true;
    for (size_t v = 0; v < views.size(); ++v)
        if (part.findChannel(nameInView(aoChannel, views, v)) >= 0) return true;
    return false;
}

} // namespace

FrameJob sequenceFrame(const FrameJob& sequence, int frame) {
    FrameJob job = sequence;
    job.input = framePath(sequence.input, frame);
    job.deepInput = framePath(sequence.deepInput, frame);
    for (std::string& element : job.deepElements) element = framePath(element, frame);
    job.output = framePath(sequence.output, frame);
    job.previewPath = framePath(sequence.previewPath, frame);
    return job;
}

std::optional<ExrInfo> completeOutput(const std::string& path, const std::string& aoChannel) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) return std::nullopt;
    try {
        ExrInfo info = readExrInfo(path, kDefaultMaxPixels, true);  // append keeps deep parts
        checkChunkTables(path, info);  // every chunk there: not a file cut short after obscura wrote it
        const std::vector<std::string> views = fileViews(info);
        for (const ExrPart& part : info.parts)
            if (holdsAo(part, aoChannel, views)) return info;
    } catch (const Error&) {
    }
    return std::nullopt;
}

namespace {
// The settings and the recipe (io/frame_report.cpp) a report records, threads and device aside.
nlohmann::json comparedPart(nlohmann::json report) {
    if (!report.is_object() || !report["settings"].is_object() || !report.contains("recipe")) return nullptr;
    for (const char* key : {"threads", "device"}) report["settings"].erase(key);
    return {{"settings", report["settings"]}, {"recipe", report["recipe"]}};
}

// What the run that wrote `job.output` recorded: of the parts holding the AO, the last whose
// obscura/settings names this output (an input's earlier AO keeps its own run's, naming that
// run's output); null when none does, or it records no recipe (an older obscura's).
nlohmann::json recordedByThisOutput(const FrameJob& job, const ExrInfo& info) {
    const std::string channel = aoChannelName(job.aoLayer);
    const std::vector<std::string> views = fileViews(info);
    const std::string outputPath = recordedPath(job.output);
    nlohmann::json found;
    for (const ExrPart& part : info.parts) {
        const auto* said = holdsAo(part, channel, views)
                               ? part.header.findTypedAttribute<Imf::StringAttribute>("obscura/settings")
                               : nullptr;
        if (!said) continue;
        const nlohmann::json report = nlohmann::json::parse(said->value(), nullptr, false);
        const bool namesThisOutput =
            report.is_object() &&
            (report.value("output", "") == job.output || report.value("output_absolute", "") == outputPath);
        if (namesThisOutput && !comparedPart(report).is_null()) found = report;
    }
    return found;
}

// A file the output records reading (by its absolute path) that is another version now: of another
// size or time, earlier too (a render rolled back). "" when none is.
std::string changedSource(const nlohmann::json& recordedSources, const std::vector<std::string>& files) {
    for (const FileStamp& now : stampsOf(files))
        for (const nlohmann::json& then : recordedSources)
            if (then.value("file", "") == now.path &&
                (then.value("size", -1LL) != now.size || then.value("mtime_ns", -1LL) != now.mtimeNs))
                return now.path;
    return "";
}
} // namespace

std::string staleOutputReason(const FrameJob& job, const ExrInfo& output) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::file_time_type written = fs::last_write_time(job.output, ec);
    if (ec) return "";
    const std::vector<std::string> files = filesReadBy(job);
    for (const std::string& f : files)
        if (fs::last_write_time(f, ec) > written && !ec) return "is older than " + f;
    try {
        const nlohmann::json then = recordedByThisOutput(job, output);
        if (then.is_null()) return "";
        if (comparedPart(then) != comparedPart(nlohmann::json::parse(frameReportJson(job, FrameReport{}))))
            return "was written with other settings";
        if (then.contains("sources"))
            if (const std::string changed = changedSource(then["sources"], files); !changed.empty())
                return "was computed from another version of " + changed;
    } catch (const nlohmann::json::exception&) {  // a header attribute of another shape: cannot tell
    }
    return "";
}

RunPlan planRun(const std::vector<std::string>& args, bool reportByDefault) {
    std::vector<std::string> copy = args;
    std::vector<char*> argv{const_cast<char*>("obscura")};
    for (std::string& a : copy) argv.push_back(a.data());
    Options o = parseArgs((int)argv.size(), argv.data());
    if (o.job.output.empty()) throw UsageError("no output: give -o OUTPUT.####.exr");
    o.job.previewPath = besideOutput(o.job.previewPath, o.job.output, ".png");
    o.reportPath = besideOutput(o.reportPath, o.job.output, ".json");
    if (o.reportPath.empty() && reportByDefault)
        o.reportPath = std::filesystem::path(o.job.output).replace_extension(".json").string();
    RunPlan plan;
    if (isFramePattern(o.job.input)) plan.frameList = planSequence(o).frames;
    plan.input = o.job.input;
    plan.output = o.job.output;
    plan.frames = o.frames;
    plan.report = o.reportPath;
    plan.aoChannel = aoChannelName(o.job.aoLayer);
    plan.threads = o.job.settings.threads;
    plan.resume = o.resume;
    for (const std::string& f : {o.job.camera.sidecarPath, o.job.envPath})
        if (!f.empty() && !isFramePattern(f)) plan.readFiles.push_back(f);
    return plan;
}


int run(int argc, char** argv) {
    if (argc > 1 && std::string(argv[1]) == "farm") return runFarm(argc, argv);
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
        if (o.job.write == WriteMode::New && o.job.inPlace)
            throw UsageError("--write new and --in-place do not go together: the output holds only the new layers");
        if (o.job.input.empty()) throw UsageError("no input file (usage: obscura INPUT.exr -o OUTPUT.exr; see --help)");
        if (o.inspectJson && !o.inspect) throw UsageError("--json goes with --inspect (--report FILE.json writes a run's JSON)");
        if (o.inspect) {
            const nlohmann::json j = inspectSequenceOrFrame(o);
            std::fputs((o.inspectJson ? j.dump(2) + "\n" : inspectText(j)).c_str(), stdout);
            return 0;
        }
        if (o.job.output.empty()) throw UsageError("no output file: give -o OUTPUT.exr (or --inspect)");
        o.job.previewPath = besideOutput(o.job.previewPath, o.job.output, ".png");
        o.reportPath = besideOutput(o.reportPath, o.job.output, ".json");
        const StopSignals stop;  // from here Ctrl-C and SIGTERM stop the run cleanly
        if (isFramePattern(o.job.input)) return runSequence(o);
        if (!o.frames.empty()) throw UsageError("--frames needs an input pattern such as shot.####.exr");
        checkFrameFiles({{&o.job, o.reportPath}}, Spelling::Flag);
        if (resumeSkips(o, o.job, o.reportPath)) {
            if (!o.quiet) std::fprintf(stderr, "obscura: %s is complete; skipped (--resume)\n", o.job.output.c_str());
            return 0;
        }
        runOneFrame(o, o.job, o.reportPath);
        endIfStopped("the frame was written whole first");
        return 0;
    } catch (const Cancelled&) {
        endByStopSignal("nothing written");
    } catch (const UsageError& e) {
        std::fprintf(stderr, "obscura: %s\n", printableLine(e.what()).c_str());
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "obscura: %s\n", printableLine(e.what()).c_str());
        return 1;
    }
}

} // namespace obscura::cli
