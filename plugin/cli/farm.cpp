// `obscura farm`: a frame sequence as farm work. `slurm` writes (and submits) an sbatch array
// job, one task per chunk of frames, each task an ordinary `obscura ... --frames CHUNK --resume`
// run; `summary` merges the per-frame reports the tasks write next to the outputs.
#include "cli.h"
#include "cli/cli_options.h"

#include "io/atomic_files.h"
#include "io/frame_job.h"
#include "io/sequence.h"

#include <nlohmann/json.hpp>
#include <sys/wait.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>

namespace obscura::cli {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

const char* const kManifest = "obscura_farm.json";
const char* const kScript = "obscura_farm.sbatch";
const char* const kLogs = "obscura_farm_logs";

const char* const kFarmHelp =
    "usage: obscura farm slurm INPUT.####.exr -o OUTPUT.####.exr [obscura flags] [farm flags]\n"
    "       obscura farm summary DIR [--json]\n\n"
    "slurm: an sbatch array job over the frames (--frames, or every input frame found), one task per\n"
    "chunk; each task runs obscura on its frames with --resume, --keep-going and --report (default:\n"
    "the output pattern with .json), so a retried or resubmitted task skips finished frames. The\n"
    "tasks' files are checked first, as a run checks them. Submits, then writes DIR/obscura_farm.sbatch\n"
    "and DIR/obscura_farm.json next to the outputs (the tasks' logs: DIR/obscura_farm_logs/); one\n"
    "job per directory.\n"
    "  --chunk N          frames per task (10)\n"
    "  --dry-run          print the script; write and submit nothing\n"
    "  --job-name NAME    Slurm job name (obscura)\n"
    "  --sbatch-arg ARG   one more #SBATCH line, e.g. --sbatch-arg=--partition=render (repeatable)\n\n"
    "summary: frames done, failed, missing and stale (an earlier job's output, written with other\n"
    "settings or before its input changed), time per frame and the reference error, from the job's\n"
    "reports in DIR; --json prints it as JSON. Exit status 0 when every frame is done, else 1.\n";

std::string shellQuote(const std::string& s) {
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}


std::string selfPath() {
    std::error_code ec;
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (ec) throw Error("cannot find the obscura executable's path (/proc/self/exe)");
    return exe.string();
}

// The directory the job is submitted from as the user's shell names it ($PWD, when it is this
// directory and a plain absolute path): a project reached through a link is named by the link,
// which the nodes mount as the submitting host does, not by where the link leads.
std::string submitDirectory() {
    const fs::path here = fs::current_path();
    std::error_code ec;
    const char* pwd = std::getenv("PWD");
    if (pwd && fs::path(pwd).is_absolute() && fs::path(pwd) == fs::path(pwd).lexically_normal() &&
        fs::equivalent(pwd, here, ec))
        return pwd;
    return here.string();
}

// A path of the job (outputs, reports, logs) from the submitting directory, as it names it.
std::string absolutePath(const std::string& p) {
    return (fs::path(p).is_absolute() ? fs::path(p) : fs::path(submitDirectory()) / p).lexically_normal().string();
}

// The tasks' log files: Slurm's file pattern (%A the job, %a the task), the directory's own '%'
// doubled so that Slurm reads it as itself (a '\\' would stop Slurm reading the pattern at all).
std::string logPattern(const std::string& dir) {
    if (dir.find('\\') != std::string::npos)
        throw FileError(dir, "a directory holding a backslash cannot take Slurm's log files: write the outputs elsewhere");
    std::string escaped;
    for (char c : dir) escaped += c == '%' ? std::string("%%") : std::string(1, c);
    return escaped + "/" + kLogs + "/%A_%a.log";
}

// A path as an #SBATCH value: sbatch splits a directive's line at blanks and takes quotes as
// quotes, so the path goes in double quotes; one holding a double quote or a line break cannot.
std::string sbatchPath(const std::string& path) {
    if (path.find_first_of("\"\n\r") != std::string::npos)
        throw FileError(path, "a path holding a double quote or a line break cannot be given to sbatch");
    return "\"" + path + "\"";
}

struct SlurmJob {
    std::vector<std::string> runArgs;  // the ordinary run's command line, as given
    RunPlan plan;
    std::vector<int> frames;
    std::vector<std::vector<int>> chunks;
    std::string dir, report;  // the outputs' directory and the report pattern, absolute
    std::vector<std::string> sbatchArgs;
    std::string jobName = "obscura";
    int chunk = 10;
    bool dryRun = false;
};

int toCount(const std::string& flag, const std::string& v) {
    char* end = nullptr;
    const long n = std::strtol(v.c_str(), &end, 10);
    if (v.empty() || *end != '\0' || n < 1 || n > 1000000)
        throw UsageError(flag + " expects a whole number of at least 1, got '" + v + "'");
    return (int)n;
}

SlurmJob parseSlurm(int argc, char** argv) {
    SlurmJob job;
    for (int i = 3; i < argc; ++i) {
        std::string arg = argv[i], value;
        const size_t eq = arg.find('=');
        const std::string name = arg.rfind("--", 0) == 0 && eq != std::string::npos ? arg.substr(0, eq) : arg;
        const bool takesValue = name == "--chunk" || name == "--job-name" || name == "--sbatch-arg";
        if (takesValue) {
            if (name != arg) value = arg.substr(eq + 1);
            else if (i + 1 < argc) value = argv[++i];
            else throw UsageError(name + " needs a value");
        }
        if (name == "--chunk") job.chunk = toCount("--chunk", value);
        else if (name == "--job-name") job.jobName = value;
        else if (name == "--sbatch-arg") job.sbatchArgs.push_back(value);
        else if (arg == "--dry-run") job.dryRun = true;
        else job.runArgs.push_back(arg);
    }
    job.plan = planRun(job.runArgs, /*reportByDefault*/ true);
    if (job.plan.input.empty()) throw UsageError("farm slurm: no input sequence (see obscura farm --help)");
    if (!isFramePattern(job.plan.input) || !isFramePattern(job.plan.output))
        throw UsageError("farm slurm: INPUT and -o must be sequences (shot.####.exr or shot.%04d.exr)");
    if (job.jobName.empty() || job.jobName.find_first_of(" \t\n'\"\\$`") != std::string::npos)
        throw UsageError("--job-name must be one word, got '" + job.jobName + "'");
    for (const std::string& a : job.sbatchArgs)
        if (a.rfind("-", 0) != 0 || a.find('\n') != std::string::npos)
            throw UsageError("--sbatch-arg expects one sbatch option such as --partition=render, got '" + a + "'");
    if (!job.plan.report.empty() && !isFramePattern(job.plan.report))
        throw UsageError("farm slurm: --report must be a pattern too (e.g. out.####.json)");
    const std::string output = absolutePath(job.plan.output);
    job.dir = fs::path(output).parent_path().string();
    job.report = absolutePath(job.plan.report);
    job.frames = job.plan.frameList;
    job.chunks = chunkFrames(job.frames, job.chunk);
    return job;
}

std::string slurmScript(const SlurmJob& job) {
    std::ostringstream s;
    s << "#!/bin/bash\n"
      << "# obscura farm slurm: " << job.frames.size() << " frame(s) of " << job.plan.input << " in "
      << job.chunks.size() << " task(s) of up to " << job.chunk << " (obscura " << OBSCURA_VERSION_STRING << ").\n"
      << "# Each task is an ordinary obscura run over its chunk with --resume: a retried or resubmitted\n"
      << "# task skips the frames already complete; outputs and reports are written atomically.\n"
      << "#SBATCH --job-name=" << job.jobName << "\n"
      << "#SBATCH --array=0-" << job.chunks.size() - 1 << "\n"
      << "#SBATCH --chdir=" << sbatchPath(submitDirectory()) << "\n"
      << "#SBATCH --output=" << sbatchPath(logPattern(job.dir)) << "\n"
      << "#SBATCH --open-mode=append\n"  // a requeued task's log follows its first attempt's
      << "#SBATCH --ntasks=1\n"
      << "#SBATCH --requeue\n";
    if (job.plan.threads > 0) s << "#SBATCH --cpus-per-task=" << job.plan.threads << "\n";
    for (const std::string& a : job.sbatchArgs) s << "#SBATCH " << a << "\n";
    s << "set -u\nchunks=(";
    for (size_t i = 0; i < job.chunks.size(); ++i) s << (i ? " " : "") << frameSpec(job.chunks[i]);
    s << ")\nexec " << shellQuote(selfPath());
    for (const std::string& a : job.runArgs) s << " " << shellQuote(a);
    s << " --frames \"${chunks[$SLURM_ARRAY_TASK_ID]}\" --resume --keep-going --report " << shellQuote(job.report)
      << "\n";
    return s.str();
}

json manifest(const SlurmJob& job) {
    json chunks = json::array();
    for (const auto& c : job.chunks) chunks.push_back(frameSpec(c));
    return {{"obscura", OBSCURA_VERSION_STRING}, {"engine", "slurm"},
            {"input", absolutePath(job.plan.input)}, {"output", absolutePath(job.plan.output)},
            {"report", job.report}, {"ao_channel", job.plan.aoChannel}, {"frames", job.frames},
            {"chunks", chunks}, {"args", job.runArgs}, {"cwd", submitDirectory()}};
}

// Runs `command` through the shell, returning its exit status and its stdout.
int capture(const std::string& command, std::string& out) {
    FILE* p = ::popen(command.c_str(), "r");
    if (!p) throw Error("cannot run '" + command + "'");
    char buf[4096];
    size_t n;
    while ((n = std::fread(buf, 1, sizeof buf, p)) > 0) out.append(buf, n);
    const int status = ::pclose(p);
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128;
}

// What would make tasks fail, said before they are submitted: frames without an input, and the
// files every frame reads (--camera, --env) missing. Warnings, not refusals: a job may be
// submitted to run after the renders it reads (an sbatch dependency).
void warnOfMissingInputs(const SlurmJob& job) {
    std::vector<int> absent;
    std::error_code ec;
    for (int frame : job.frames)
        if (!fs::exists(framePath(job.plan.input, frame), ec)) absent.push_back(frame);
    if (!absent.empty())
        std::fprintf(stderr, "obscura: warning: frame(s) %s of %zu have no input (%s) yet; their tasks fail unless it "
                     "is written before they run\n", frameSpec(absent).c_str(), job.frames.size(), job.plan.input.c_str());
    for (const std::string& file : job.plan.readFiles)
        if (!fs::exists(file, ec))
            std::fprintf(stderr, "obscura: warning: '%s' does not exist; every task reads it\n", file.c_str());
}

// A manifest's frames and paths: written by `farm slurm`, or by hand for another engine (farm.md),
// whose relative paths are relative to its "cwd" when it gives one, else to its own directory.
struct Manifest {
    json raw;
    std::vector<int> frames;
    std::string output, report, channel;
};

Manifest readManifest(const fs::path& path) {
    std::ifstream f(path);
    if (!f) throw FileError(path.string(), "cannot read (obscura farm slurm writes it)");
    Manifest m;
    m.raw = json::parse(f, nullptr, false);
    const json& r = m.raw;
    if (!r.is_object() || !r.contains("frames") || !r.contains("output") || !r.contains("report"))
        throw FileError(path.string(), "not an obscura farm manifest (it needs \"frames\", \"output\" and \"report\")");
    const auto must = [&](bool ok, const std::string& what) {
        if (!ok) throw FileError(path.string(), what);
    };
    const json& frames = r["frames"];
    const auto isFrame = [](const json& v) {
        return v.is_number_integer() && v.get<long long>() >= INT_MIN && v.get<long long>() <= INT_MAX;
    };
    must(frames.is_string() || (frames.is_array() && std::all_of(frames.begin(), frames.end(), isFrame)),
         "\"frames\" must be a list of frame numbers, or a --frames text such as \"1001-1100\"");
    try {
        m.frames = frames.is_string() ? parseFrames(frames.get<std::string>()) : frames.get<std::vector<int>>();
    } catch (const Error& e) {
        throw FileError(path.string(), "\"frames\": " + std::string(e.what()));
    }
    for (const char* key : {"output", "report", "ao_channel", "cwd"})
        must(!r.contains(key) || r[key].is_string(), std::string("\"") + key + "\" must be a string");
    const fs::path base = r.contains("cwd") ? fs::path(r["cwd"].get<std::string>()) : fs::absolute(path).parent_path();
    const auto resolved = [&](const std::string& p) { return (base / p).lexically_normal().string(); };
    m.output = resolved(r["output"]);
    m.report = resolved(r["report"]);
    m.channel = r.value("ao_channel", "obscura.AO.Y");
    must(isFramePattern(m.output) && isFramePattern(m.report),
         "\"output\" and \"report\" must be frame patterns (out.####.exr, out.####.json)");
    return m;
}

// One job per directory: its manifest, script and logs are named for the directory, so a second
// job's (another output pattern) would replace the first's and its summary would judge the wrong
// frames. The same outputs, however spelled (#### or %04d, through a link), are the same job
// submitted again; a manifest that does not read is not replaced either.
void refuseAnotherJobsDirectory(const SlurmJob& job) {
    const fs::path path = fs::path(job.dir) / kManifest;
    std::error_code ec;
    if (!fs::exists(path, ec)) return;
    const Manifest m = readManifest(path);
    const int frame = job.frames.front();
    if (fs::weakly_canonical(framePath(m.output, frame), ec) !=
        fs::weakly_canonical(framePath(absolutePath(job.plan.output), frame), ec))
        throw FileError(path.string(), "holds the job for " + m.output + " (its summary and script); give " +
                                           job.plan.output + " a directory of its own");
}

int runSlurm(int argc, char** argv) {
    const SlurmJob job = parseSlurm(argc, argv);
    const std::string script = slurmScript(job);
    refuseAnotherJobsDirectory(job);
    warnOfMissingInputs(job);
    if (job.dryRun) {
        std::fputs(script.c_str(), stdout);
        return 0;
    }
    const std::string scriptPath = (fs::path(job.dir) / kScript).string(),
                      manifestPath = (fs::path(job.dir) / kManifest).string();
    for (const std::string& p : {scriptPath, manifestPath}) requireWritableDestination(p);  // before the job exists
    const fs::path logs = fs::path(job.dir) / kLogs;
    std::error_code ec;
    const bool madeLogs = fs::create_directories(logs, ec);  // before sbatch: a task may start at once
    if (ec) throw FileError(logs.string(), "cannot create the tasks' log directory: " + ec.message());
    // The script and the manifest replace an earlier submission's only once sbatch has taken the
    // job: a refused one leaves the job that ran described as it was.
    WriteBatch files;
    writeTextFileAtomically(scriptPath, script);
    std::string out;
    const int rc = capture("sbatch --parsable " + shellQuote(files.staged(scriptPath)) + " 2>&1", out);
    while (!out.empty() && (out.back() == '\n' || out.back() == ' ')) out.pop_back();
    if (rc != 0 && madeLogs) fs::remove(logs, ec);  // empty: no task of a refused job ran
    if (rc == 127) throw Error("sbatch not found (install slurm-client, or use --dry-run to print the script)");
    if (rc != 0) throw Error("sbatch failed: " + out.substr(out.find_last_of('\n') + 1));
    const std::string jobId = out.substr(out.find_last_of('\n') + 1);
    json m = manifest(job);
    m["job_id"] = jobId.substr(0, jobId.find(';'));
    try {
        writeTextFileAtomically(manifestPath, m.dump(2));
        files.commit();
    } catch (const Error& e) {  // a full disk, now: the job runs all the same
        throw Error("job " + m["job_id"].get<std::string>() + " is submitted, but its script and manifest are not "
                    "written (" + e.what() + "): do not submit it again; obscura farm summary needs the manifest");
    }
    std::printf("submitted job %s: %zu frame(s) in %zu task(s); obscura farm summary %s\n",
                m["job_id"].get<std::string>().c_str(), job.frames.size(), job.chunks.size(), job.dir.c_str());
    return 0;
}

// --- summary -------------------------------------------------------------------------------

struct Range {
    double sum = 0, lo = INFINITY, hi = -INFINITY;
    int n = 0;
    void add(double v) { sum += v, lo = std::min(lo, v), hi = std::max(hi, v), ++n; }
    json toJson() const { return n ? json{{"mean", sum / n}, {"min", lo}, {"max", hi}, {"total", sum}} : json(); }
};

// The job the manifest's tasks run (its command line, as given), to tell a frame done by this
// job from one an earlier job left; nullopt for a manifest from before it recorded the command
// line. Its paths are relative to the manifest's "cwd", as the tasks' (--chdir) and as the
// recipe each output records them: compare from there (SubmittedDirectory).
std::optional<FrameJob> submittedJob(const json& m) {
    if (!m.contains("args") || !m.contains("cwd") || !m["args"].is_array()) return std::nullopt;
    std::vector<std::string> args;
    for (const json& a : m["args"]) {
        if (!a.is_string()) return std::nullopt;
        args.push_back(a.get<std::string>());
    }
    std::vector<char*> argv{const_cast<char*>("obscura")};
    for (std::string& a : args) argv.push_back(a.data());
    try {
        return parseArgs((int)argv.size(), argv.data()).job;
    } catch (const Error&) {  // flags of another version of obscura: frames are counted as before
        return std::nullopt;
    }
}

// The working directory the job was submitted from, for as long as this lives.
struct SubmittedDirectory {
    fs::path before;
    bool moved = false;
    explicit SubmittedDirectory(const json& m) {
        std::error_code ec;
        before = fs::current_path(ec);
        if (!ec && m.contains("cwd")) fs::current_path(m["cwd"].get<std::string>(), ec), moved = !ec;
    }
    ~SubmittedDirectory() {
        std::error_code ec;
        if (moved) fs::current_path(before, ec);
    }
};

json summarise(const std::string& dir) {
    const fs::path path = fs::absolute(fs::path(dir) / kManifest);
    const Manifest manifest = readManifest(path);
    const json& m = manifest.raw;
    const std::string &output = manifest.output, &report = manifest.report, &channel = manifest.channel;
    json done = json::array(), missing = json::array(), failed = json::object(), temps = json::array();
    json stale = json::object();
    const SubmittedDirectory from(m);  // the manifest's paths are absolute; the job's, from here
    const std::optional<FrameJob> submitted = from.moved ? submittedJob(m) : std::nullopt;
    Range seconds;
    std::map<std::string, Range> error;
    std::string referenceLayer;
    for (int frame : manifest.frames) {
        const std::string out = framePath(output, frame), rep = framePath(report, frame);
        for (const std::string& p : atomicWriteTemps(out)) temps.push_back(p);
        for (const std::string& p : atomicWriteTemps(rep)) temps.push_back(p);
        std::ifstream rf(rep);
        const json r = rf ? json::parse(rf, nullptr, false) : json();
        if (r.is_object() && r.contains("error")) {
            failed[std::to_string(frame)] = r["error"];
        } else if (const std::optional<ExrInfo> written = r.is_object() && r.contains("total_s")
                                                              ? completeOutput(out, channel)
                                                              : std::nullopt) {
            // An earlier job's frame (other settings), or one whose input was rendered again.
            if (const std::string why = submitted ? staleOutputReason(sequenceFrame(*submitted, frame), *written) : "";
                !why.empty()) {
                stale[std::to_string(frame)] = why;
                continue;
            }
            done.push_back(frame);
            seconds.add(r["total_s"].get<double>());
            if (r.contains("reference")) {
                const json& e = r["reference"];
                referenceLayer = e.value("layer", "");
                for (const char* k : {"mae", "rmse", "p99_abs"}) error[k].add(e[k].get<double>());
                if (e["psnr_db"].is_number()) error["psnr_db"].add(e["psnr_db"].get<double>());
            }
        } else {
            missing.push_back(frame);
        }
    }
    json s = {{"manifest", path.string()}, {"frames", manifest.frames.size()}, {"done", done}, {"failed", failed},
              {"missing", missing}, {"stale", stale}, {"temp_files", temps}, {"seconds_per_frame", seconds.toJson()}};
    if (m.contains("job_id")) s["job_id"] = m["job_id"];
    if (!error.empty()) {
        s["reference"] = {{"layer", referenceLayer}};
        for (const auto& [k, r] : error) s["reference"][k] = r.toJson();
    }
    return s;
}

std::string summaryText(const json& s) {
    std::ostringstream os;
    char line[256];
    os << "obscura farm: " << s["manifest"].get<std::string>() << "\n";
    std::snprintf(line, sizeof line, "frames: %zu: %zu done, %zu failed, %zu missing, %zu stale\n",
                  s["frames"].get<size_t>(), s["done"].size(), s["failed"].size(), s["missing"].size(), s["stale"].size());
    os << line;
    if (const json& t = s["seconds_per_frame"]; !t.is_null()) {
        std::snprintf(line, sizeof line, "time per frame: mean %.3f s, min %.3f s, max %.3f s; %.1f s in all\n",
                      t["mean"].get<double>(), t["min"].get<double>(), t["max"].get<double>(), t["total"].get<double>());
        os << line;
    }
    if (s.contains("reference")) {
        const json& e = s["reference"];
        os << "reference " << e["layer"].get<std::string>() << " (mean / worst frame):";
        for (const char* k : {"mae", "rmse", "p99_abs"})
            if (e.contains(k)) {
                std::snprintf(line, sizeof line, " %s %.5f / %.5f", k, e[k]["mean"].get<double>(), e[k]["max"].get<double>());
                os << line << ";";
            }
        if (e.contains("psnr_db")) {
            std::snprintf(line, sizeof line, " psnr %.2f / %.2f dB", e["psnr_db"]["mean"].get<double>(),
                          e["psnr_db"]["min"].get<double>());
            os << line;
        }
        os << "\n";
    }
    for (const auto& [frame, err] : s["failed"].items()) os << "failed " << frame << ": " << err.get<std::string>() << "\n";
    for (const auto& [frame, why] : s["stale"].items())
        os << "stale " << frame << ": the output " << why.get<std::string>() << " (a task of this job computes it again)\n";
    if (!s["missing"].empty()) {
        std::vector<int> missing = s["missing"].get<std::vector<int>>();
        os << "missing: " << frameSpec(missing) << "\n";
    }
    for (const auto& t : s["temp_files"])
        os << "temp file (a write in progress, or left by a killed run): " << t.get<std::string>() << "\n";
    return os.str();
}

int runSummary(int argc, char** argv) {
    std::string dir;
    bool asJson = false;
    for (int i = 3; i < argc; ++i) {
        const std::string arg = argv[i];
        if (arg == "--json") asJson = true;
        else if (arg.rfind("-", 0) == 0) throw UsageError("farm summary: unknown option '" + arg + "'");
        else if (!dir.empty()) throw UsageError("farm summary takes one directory");
        else dir = arg;
    }
    if (dir.empty()) throw UsageError("farm summary: which directory? (obscura farm summary DIR)");
    const json s = summarise(dir);
    if (asJson) std::printf("%s\n", s.dump(2).c_str());
    else std::fputs(summaryText(s).c_str(), stdout);
    return s["done"].size() == s["frames"].get<size_t>() ? 0 : 1;
}

} // namespace

int runFarm(int argc, char** argv) {
    try {
        const std::string what = argc > 2 ? argv[2] : "", next = argc > 3 ? argv[3] : "";
        const auto isHelp = [](const std::string& a) { return a == "--help" || a == "-h"; };
        if (isHelp(what) || ((what == "slurm" || what == "summary") && isHelp(next))) {
            std::fputs(kFarmHelp, stdout);
            return 0;
        }
        if (what == "slurm") return runSlurm(argc, argv);
        if (what == "summary") return runSummary(argc, argv);
        throw UsageError("farm expects slurm or summary, got '" + what + "' (see obscura farm --help)");
    } catch (const UsageError& e) {
        std::fprintf(stderr, "obscura: %s\n", e.what());
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "obscura: %s\n", e.what());
        return 1;
    }
}

} // namespace obscura::cli
