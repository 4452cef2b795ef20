// Nothing a user has is overwritten (issue 31): every path the CLI would write (-o, --report,
// --preview) against every path it reads (the input, the camera sidecar, --camera, --env,
// --flat and its deep input, the OpenColorIO config) and against each other, by name, by
// another spelling, through a symlink and through a hard link, for one frame and for
// sequences. Every case must exit 2 with one line naming both roles, and leave every file in
// the directory byte-identical, with no file added.
#include "support/cli_runner.h"
#include "support/exr_fixtures.h"
#include "support/scratch.h"

#include <gtest/gtest.h>

#include <sys/stat.h>

#include <algorithm>
#include <cstdlib>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using obscura::test::CliResult;

namespace {

const std::string kData = OBSCURA_TEST_DATA_DIR;

CliResult cli(const std::vector<std::string>& args) { return obscura::test::runProgram(OBSCURA_CLI_PATH, args); }

std::string describe(const CliResult& r) {
    return "exit " + std::to_string(r.exitCode) + "\n--- stdout ---\n" + r.out + "--- stderr ---\n" + r.err;
}

std::string slurp(const fs::path& p) {
    std::ifstream f(p, std::ios::binary);
    std::ostringstream s;
    s << f.rdbuf();
    return s.str();
}

// Every entry under `dir`: a file's bytes, a symlink's target, a directory's name.
std::map<std::string, std::string> snapshot(const fs::path& dir) {
    std::map<std::string, std::string> files;
    for (const auto& e : fs::recursive_directory_iterator(dir)) {
        const std::string key = fs::relative(e.path(), dir).string();
        if (e.is_symlink()) files[key] = "-> " + fs::read_symlink(e.path()).string();
        else if (e.is_regular_file()) files[key] = slurp(e.path());
        else files[key] = "dir";
    }
    return files;
}

// The scratch directory every case runs in: the files a user has.
struct Workspace {
    fs::path dir;
    explicit Workspace(const fs::path& d) : dir(d) {
        fs::copy_file(kData + "/room.exr", dir / "in.exr");
        fs::copy_file(kData + "/room.json", dir / "in.json");  // found as the input's sidecar
        fs::copy_file(kData + "/room.json", dir / "cam.json");
        fs::copy_file(kData + "/room.exr", dir / "flat.exr");
        fs::copy_file(kData + "/room.exr", dir / "deep.exr");  // stands for a deep file: nothing is read
        fs::copy_file(kData + "/room.exr", dir / "earlier.exr");  // an earlier run's output
        obscura::fixtures::writeSimple((dir / "env.exr").string(), {"R", "G", "B"}, 16, 8);
        fs::copy_file(fs::path(OBSCURA_SOURCE_DIR) / "ocio" / "config.ocio", dir / "config.ocio");
        for (int f : {1, 2}) {
            fs::copy_file(kData + "/room.exr", dir / ("seq." + std::to_string(f * 1000 + 1) + ".exr"));
            fs::copy_file(kData + "/room.json", dir / ("seq." + std::to_string(f * 1000 + 1) + ".json"));
        }
        fs::create_directory(dir / "sub");
    }
    std::string operator()(const std::string& name) const { return (dir / name).string(); }
};

// How a written path reaches the file it collides with.
enum class Link { Name, Spelling, Symlink, Hardlink };
const char* linkName(Link l) {
    return l == Link::Name ? "name" : l == Link::Spelling ? "spelling" : l == Link::Symlink ? "symlink" : "hardlink";
}

// A path that reaches `target` by `link`, named with `extension` where a new name is made.
std::string reach(const Workspace& w, const std::string& target, Link link, const std::string& extension) {
    switch (link) {
    case Link::Name: return w(target);
    case Link::Spelling: return w("sub/../" + target);
    case Link::Symlink: fs::create_symlink(w(target), w("link" + extension)); return w("link" + extension);
    case Link::Hardlink: fs::create_hard_link(w(target), w("hard" + extension)); return w("hard" + extension);
    }
    return "";
}

struct Written {
    const char* role;       // as the error line names it
    const char* flag;
    const char* extension;  // what the role's own name ends in
};
const Written kWritten[] = {{"-o", "-o", ".exr"}, {"--report", "--report", ".json"}, {"--preview", "--preview", ".png"}};

struct Read {
    const char* role;
    const char* file;                 // in the workspace
    std::vector<std::string> input;   // the input and the flags that make the run read `file`
    bool ocio = false;                // read through $OCIO
};
const std::vector<Read>& reads() {
    static const std::vector<Read> r = {
        {"the input", "in.exr", {"in.exr"}},
        {"the camera sidecar", "in.json", {"in.exr"}},
        {"--camera", "cam.json", {"in.exr", "--camera", "cam.json"}},
        {"--env", "env.exr", {"in.exr", "--method", "ssdo", "--env", "env.exr"}},
        {"--flat", "flat.exr", {"deep.exr", "--flat", "flat.exr"}},
        {"the input", "deep.exr", {"deep.exr", "--flat", "flat.exr"}},
        {"the OpenColorIO config", "config.ocio", {"in.exr"}, true},
    };
    return r;
}

// Runs `args` in `w` and expects the refusal: exit 2, one line naming both roles, nothing changed.
void expectRefused(const Workspace& w, std::vector<std::string> args, const std::vector<std::string>& roles,
                   const std::string& what, bool ocio = false) {
    for (std::string& a : args)  // file names live in the workspace
        if (a[0] != '-' && a.find('.') != std::string::npos) a = w(a);
    if (ocio) ::setenv("OCIO", w("config.ocio").c_str(), 1);
    const auto before = snapshot(w.dir);
    const CliResult r = cli(args);
    ::unsetenv("OCIO");
    SCOPED_TRACE(what);
    EXPECT_EQ(r.exitCode, 2) << describe(r);
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << describe(r);
    for (const std::string& role : roles) EXPECT_NE(r.err.find(role), std::string::npos) << role << "\n" << describe(r);
    EXPECT_TRUE(snapshot(w.dir) == before) << "files changed\n" << describe(r);
}

fs::path freshDir() { return obscura::test::testDir("overwrite"); }

} // namespace

TEST(NothingOverwritten, EveryWrittenPathAgainstEveryReadPath) {
    int cases = 0;
    for (const Written& out : kWritten)
        for (const Read& in : reads())
            for (Link link : {Link::Name, Link::Spelling, Link::Symlink, Link::Hardlink}) {
                const Workspace w(freshDir());
                std::vector<std::string> args = in.input;
                const std::string target = reach(w, in.file, link, out.extension);
                if (std::string(out.flag) != "-o") args.insert(args.end(), {"-o", w("out.exr")});
                args.insert(args.end(), {out.flag, target});
                expectRefused(w, args, {out.role, in.role},
                              std::string(out.flag) + " onto " + in.role + " by " + linkName(link), in.ocio);
                ++cases;
            }
    EXPECT_EQ(cases, 3 * 7 * 4);
}

TEST(NothingOverwritten, WrittenPathsAgainstEachOther) {
    for (size_t a = 0; a < 3; ++a)
        for (size_t b = a + 1; b < 3; ++b)
            for (Link link : {Link::Name, Link::Symlink, Link::Hardlink}) {
                const Workspace w(freshDir());
                const Written& first = kWritten[a];
                const Written& second = kWritten[b];
                // The hard link needs a file to link to: an earlier run's output.
                const std::string one = link == Link::Hardlink ? w("earlier.exr") : w(std::string("x") + first.extension);
                std::string two = one;
                if (link == Link::Symlink) fs::create_symlink(one, two = w(std::string("link") + second.extension));
                if (link == Link::Hardlink) fs::create_hard_link(one, two = w(std::string("hard") + second.extension));
                std::vector<std::string> args = {"in.exr"};
                if (std::string(first.flag) != "-o") args.insert(args.end(), {"-o", w("out.exr")});
                args.insert(args.end(), {first.flag, one, second.flag, two});
                expectRefused(w, args, {first.role, second.role},
                              std::string(first.flag) + " and " + second.flag + " by " + linkName(link));
            }
}

TEST(NothingOverwritten, SequencesCompareEveryFrame) {
    struct Case {
        std::vector<std::string> args;
        std::vector<std::string> roles;
    };
    const std::vector<Case> cases = {
        {{"seq.####.exr", "-o", "out.####.exr", "--report", "seq.####.json"}, {"--report", "the camera sidecar"}},
        {{"seq.####.exr", "-o", "seq.####.exr"}, {"-o", "the input"}},
        {{"seq.####.exr", "-o", "sub/../seq.####.exr"}, {"-o", "the input"}},
        {{"seq.####.exr", "-o", "out.####.exr", "--preview", "out.####.exr"}, {"--preview", "-o"}},
        {{"seq.####.exr", "-o", "out.####.exr", "--report", "one.json"}, {"--report", "every frame"}},
        {{"seq.####.exr", "-o", "out.####.exr", "--preview", "one.png"}, {"--preview", "every frame"}},
        {{"seq.####.exr", "-o", "out.####.exr", "--frames", "1001,2001", "--report", "in.json"}, {"--report", "every frame"}},
    };
    for (const Case& c : cases) {
        const Workspace w(freshDir());
        std::string what;
        for (const std::string& a : c.args) what += a + " ";
        expectRefused(w, c.args, c.roles, what);
    }
    // Through a symlinked directory: alias/seq.####.json are the sidecars.
    const Workspace w(freshDir());
    fs::create_directory_symlink(w.dir, w("alias"));
    expectRefused(w, {"seq.####.exr", "-o", "out.####.exr", "--report", w("alias/seq.####.json")},
                  {"--report", "the camera sidecar"}, "through a symlinked directory");
}

TEST(NothingOverwritten, InPlaceReplacesTheInputAndNothingElse) {
    const Workspace w(freshDir());
    expectRefused(w, {"in.exr", "-o", "in.exr", "--in-place", "--report", "in.json"}, {"--report", "the camera sidecar"},
                  "--in-place does not free the sidecar");
    expectRefused(w, {"in.exr", "-o", "in.exr", "--in-place", "--preview", "in.exr"}, {"--preview", "the input"},
                  "--in-place does not free the input for the preview");
    // The one replacement asked for: the input alone changes, atomically, and the sidecar stays.
    const std::string sidecar = slurp(w("in.json"));
    const CliResult r = cli({w("in.exr"), "-o", w("in.exr"), "--in-place", "--quiet"});
    EXPECT_EQ(r.exitCode, 0) << describe(r);
    EXPECT_EQ(slurp(w("in.json")), sidecar);
}

TEST(NothingOverwritten, MisnamedOutputsAreRefused) {
    const Workspace w(freshDir());
    expectRefused(w, {"in.exr", "-o", "a.png"}, {"-o", ".exr"}, "-o a.png");
    expectRefused(w, {"in.exr", "-o", "a.exr", "--report", "a.txt"}, {"--report", ".json"}, "--report a.txt");
    expectRefused(w, {"in.exr", "-o", "a.exr", "--preview", "a.jpg"}, {"--preview", ".png"}, "--preview a.jpg");
}

// A distinct name for each file is not refused: the cases above fail for the collision alone.
TEST(NothingOverwritten, DistinctPathsRun) {
    const Workspace w(freshDir());
    const CliResult r = cli({w("in.exr"), "-o", w("out.exr"), "--report", w("out.json"), "--preview", w("out.png"), "--quiet"});
    EXPECT_EQ(r.exitCode, 0) << describe(r);
    for (const char* f : {"out.exr", "out.json", "out.png"}) EXPECT_TRUE(fs::is_regular_file(w(f))) << f;
    // A directory for the report and preview: each takes the output's name.
    const CliResult d = cli({w("in.exr"), "-o", w("o2.exr"), "--report", w("sub") + "/", "--preview", w("sub"), "--quiet"});
    EXPECT_EQ(d.exitCode, 0) << describe(d);
    EXPECT_TRUE(fs::is_regular_file(w("sub/o2.json")));
    EXPECT_TRUE(fs::is_regular_file(w("sub/o2.png")));
}

mode_t modeOf(const std::string& path) {
    struct stat st {};
    ::stat(path.c_str(), &st);
    return st.st_mode & 07777;
}

// An earlier output replaced as the user keeps it: through its symlink (the link stays, the file
// it leads to is replaced) and with its permission bits (a private file stays private).
TEST(NothingOverwritten, AnEarlierOutputIsReplacedThroughItsLinkWithItsMode) {
    const Workspace w(freshDir());
    fs::create_directory(w("renders"));
    fs::copy_file(w("earlier.exr"), w("renders/ao.exr"));
    ::chmod(w("renders/ao.exr").c_str(), 0600);
    fs::create_symlink("renders/ao.exr", w("ao.exr"));
    const CliResult r = cli({w("in.exr"), "-o", w("ao.exr"), "--preview", w("ao.png"), "--quiet"});
    ASSERT_EQ(r.exitCode, 0) << describe(r);
    EXPECT_TRUE(fs::is_symlink(w("ao.exr")));
    EXPECT_NE(slurp(w("renders/ao.exr")), slurp(w("earlier.exr")));
    EXPECT_EQ(modeOf(w("renders/ao.exr")), 0600u);
    // --in-place keeps the input's mode too.
    ::chmod(w("in.exr").c_str(), 0640);
    const CliResult in = cli({w("in.exr"), "-o", w("in.exr"), "--in-place", "--quiet"});
    ASSERT_EQ(in.exitCode, 0) << describe(in);
    EXPECT_EQ(modeOf(w("in.exr")), 0640u);
    for (const auto& e : fs::recursive_directory_iterator(w.dir))
        EXPECT_EQ(e.path().filename().string().find(".tmp-"), std::string::npos) << e.path();
}

// A read-only earlier output (-o, --report or --preview; even for root, who may write it) is a
// file the user protected: one line naming it, exit 1, and nothing written.
TEST(NothingOverwritten, AReadOnlyEarlierOutputIsKept) {
    for (const char* role : {"-o", "--report", "--preview"}) {
        SCOPED_TRACE(role);
        const Workspace w(freshDir());
        const std::string kept = std::string(role) == "-o" ? "out.exr" : std::string(role) == "--report" ? "out.json" : "out.png";
        std::ofstream(w(kept)) << "an earlier run's";
        ::chmod(w(kept).c_str(), 0444);
        const auto before = snapshot(w.dir);
        const CliResult r = cli({w("in.exr"), "-o", w("out.exr"), "--report", w("out.json"), "--preview", w("out.png")});
        EXPECT_EQ(r.exitCode, 1) << describe(r);
        EXPECT_NE(r.err.find(kept + "': is read-only"), std::string::npos) << describe(r);
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << describe(r);
        EXPECT_EQ(snapshot(w.dir), before);
    }
}

// A run that fails after its output is written (here its report: a name within a few characters
// of the file system's limit leaves its temp file no room) leaves nothing, not the output alone.
TEST(NothingOverwritten, AFailureAfterTheOutputLeavesNothing) {
    const Workspace w(freshDir());
    const std::string report = w(std::string(250, 'r') + ".json");
    for (const bool earlier : {false, true}) {
        SCOPED_TRACE(earlier ? "over an earlier output" : "a new output");
        if (earlier) fs::copy_file(w("earlier.exr"), w("out.exr"));
        const auto before = snapshot(w.dir);
        const CliResult r = cli({w("in.exr"), "-o", w("out.exr"), "--preview", w("out.png"), "--report", report});
        EXPECT_EQ(r.exitCode, 1) << describe(r);
        EXPECT_NE(r.err.find(std::string(250, 'r')), std::string::npos) << describe(r);
        EXPECT_EQ(snapshot(w.dir), before);
    }
}

TEST(Resume, OneFrameSkipsAFinishedOutputAndClearsADeadWritersTemp) {
    const Workspace w(freshDir());
    const CliResult first = cli({w("in.exr"), "-o", w("out.exr"), "--report", w("out.json"), "--quiet"});
    ASSERT_EQ(first.exitCode, 0) << describe(first);
    struct stat before {};
    ::stat(w("out.exr").c_str(), &before);
    // A writer that died mid-frame: no process has this pid (pid_max is at most 2^22).
    std::ofstream(w("out.exr.tmp-9999999")) << "partial";
    const CliResult again = cli({w("in.exr"), "-o", w("out.exr"), "--report", w("out.json"), "--resume"});
    EXPECT_EQ(again.exitCode, 0) << describe(again);
    EXPECT_NE(again.err.find("skipped"), std::string::npos) << describe(again);
    struct stat after {};
    ::stat(w("out.exr").c_str(), &after);
    EXPECT_EQ(before.st_mtim.tv_sec, after.st_mtim.tv_sec);
    EXPECT_EQ(before.st_mtim.tv_nsec, after.st_mtim.tv_nsec);
    EXPECT_EQ(before.st_ino, after.st_ino);  // not replaced by a rename either
    EXPECT_FALSE(fs::exists(w("out.exr.tmp-9999999")));
    // An output that is not complete (no AO channel) is computed again.
    fs::copy_file(w("in.exr"), w("plain.exr"));
    const CliResult redo = cli({w("in.exr"), "-o", w("plain.exr"), "--resume", "--quiet"});
    EXPECT_EQ(redo.exitCode, 0) << describe(redo);
    EXPECT_NE(slurp(w("plain.exr")), slurp(w("in.exr")));
}

// A job resubmitted with other settings: --resume computes a finished frame again, saying so;
// with the same settings and another thread count it is still skipped.
TEST(Resume, RecomputesAFrameWrittenWithOtherSettings) {
    const Workspace w(freshDir());
    const CliResult first = cli({w("in.exr"), "-o", w("out.exr"), "--radius", "0.5", "--quiet"});
    ASSERT_EQ(first.exitCode, 0) << describe(first);
    const std::string written = slurp(w("out.exr"));
    const CliResult same = cli({w("in.exr"), "-o", w("out.exr"), "--radius", "0.5", "--threads", "1", "--resume"});
    EXPECT_EQ(same.exitCode, 0) << describe(same);
    EXPECT_NE(same.err.find("skipped"), std::string::npos) << describe(same);
    const CliResult other = cli({w("in.exr"), "-o", w("out.exr"), "--radius", "0.25", "--resume"});
    EXPECT_EQ(other.exitCode, 0) << describe(other);
    EXPECT_NE(other.err.find("out.exr was written with other settings; computed again (--resume)"), std::string::npos)
        << describe(other);
    EXPECT_NE(slurp(w("out.exr")), written);
    const CliResult now = cli({w("in.exr"), "-o", w("out.exr"), "--radius", "0.25", "--resume"});
    EXPECT_NE(now.err.find("skipped"), std::string::npos) << describe(now);
    // How the passes are read counts as the settings do: normals from the depth.
    const CliResult normals = cli({w("in.exr"), "-o", w("out.exr"), "--radius", "0.25", "--normals", "depth", "--resume"});
    EXPECT_NE(normals.err.find("written with other settings"), std::string::npos) << describe(normals);
    // A frame rendered again, or its camera edited, after its output was written.
    for (const char* source : {"in.exr", "in.json"}) {
        const fs::file_time_type written = fs::last_write_time(w("out.exr"));
        for (const char* f : {"in.exr", "in.json"}) fs::last_write_time(w(f), written - std::chrono::seconds(100));
        fs::last_write_time(w(source), written + std::chrono::seconds(2));
        const CliResult again = cli({w("in.exr"), "-o", w("out.exr"), "--radius", "0.25", "--normals", "depth", "--resume"});
        EXPECT_NE(again.err.find("out.exr is older than " + w(source) + "; computed again (--resume)"), std::string::npos)
            << describe(again);
    }
}

// An input rolled back to an older render (its link pointed at an earlier version, or a copy that
// kept its older time): no file is newer than the output, but the output records another file.
TEST(Resume, RecomputesAFrameWhoseInputWasRolledBack) {
    const Workspace w(freshDir());
    fs::copy_file(w("in.exr"), w("v1.exr"));
    fs::copy_file(w("in.exr"), w("v2.exr"));
    fs::copy_file(w("in.json"), w("cur.json"));
    fs::create_symlink("v2.exr", w("cur.exr"));
    ASSERT_EQ(cli({w("cur.exr"), "-o", w("out.exr"), "--quiet"}).exitCode, 0);
    const fs::file_time_type written = fs::last_write_time(w("out.exr"));
    fs::last_write_time(w("v1.exr"), written - std::chrono::seconds(100));
    fs::remove(w("cur.exr"));
    fs::create_symlink("v1.exr", w("cur.exr"));
    const CliResult linked = cli({w("cur.exr"), "-o", w("out.exr"), "--resume"});
    EXPECT_NE(linked.err.find("out.exr was computed from another version of " + w("cur.exr") + "; computed again"),
              std::string::npos) << describe(linked);
    // The same file, copied over with the time it had (cp -p): its size or time is not the output's.
    fs::remove(w("cur.exr"));
    fs::copy_file(w("v2.exr"), w("cur.exr"));
    fs::last_write_time(w("cur.exr"), written - std::chrono::seconds(50));
    const CliResult copied = cli({w("cur.exr"), "-o", w("out.exr"), "--resume"});
    EXPECT_NE(copied.err.find("was computed from another version of " + w("cur.exr")), std::string::npos)
        << describe(copied);
    const CliResult now = cli({w("cur.exr"), "-o", w("out.exr"), "--resume"});
    EXPECT_NE(now.err.find("skipped"), std::string::npos) << describe(now);
}

// A project moved with its files' times (mv, cp -a) and run again from where it is now, with the
// paths spelled as before (relative): the outputs are of the same versions, and are skipped.
TEST(Resume, AProjectMovedWithItsTimesIsSkipped) {
    const Workspace w(freshDir());
    const fs::path before = fs::current_path();
    fs::current_path(w.dir);
    ASSERT_EQ(cli({"in.exr", "-o", "out.exr", "--quiet"}).exitCode, 0);
    const fs::path moved = w.dir.string() + "_moved";
    fs::rename(w.dir, moved);
    fs::current_path(moved);
    const CliResult there = cli({"in.exr", "-o", "out.exr", "--resume"});
    fs::current_path(before);
    fs::rename(moved, w.dir);
    EXPECT_NE(there.err.find("out.exr is complete; skipped"), std::string::npos) << describe(there);
}

// --resume run from another directory, the paths spelled from there: the output's record is found
// (by its absolute path), so other settings compute the frame again.
TEST(Resume, FindsTheRecordFromAnotherDirectory) {
    const Workspace w(freshDir());
    const fs::path before = fs::current_path();
    fs::current_path(w.dir);
    ASSERT_EQ(cli({"in.exr", "-o", "out.exr", "--radius", "0.5", "--quiet"}).exitCode, 0);
    fs::current_path(w.dir / "sub");
    const CliResult other = cli({"../in.exr", "-o", "../out.exr", "--radius", "0.9", "--resume"});
    fs::current_path(before);
    EXPECT_NE(other.err.find("../out.exr was written with other settings; computed again"), std::string::npos)
        << describe(other);
}

// An input that holds an earlier run's AO in a part of its own (append): --resume reads the
// settings of the part this output's run wrote, not of the first part holding an AO.
TEST(Resume, ReadsThePartThisOutputsRunWrote) {
    const Workspace w(freshDir());
    fs::copy_file(w("in.json"), w("a.json"));
    fs::copy_file(w("in.json"), w("b.json"));
    const auto run = [&](const std::string& in, const std::string& out, const char* radius, bool resume) {
        std::vector<std::string> args = {w(in), "-o", w(out), "--write", "append", "--radius", radius};
        if (resume) args.push_back("--resume");
        return cli(args);
    };
    ASSERT_EQ(run("in.exr", "a.exr", "0.5", false).exitCode, 0);
    ASSERT_EQ(run("a.exr", "b.exr", "1", false).exitCode, 0);
    const CliResult same = run("a.exr", "b.exr", "1", true);
    EXPECT_NE(same.err.find("b.exr is complete; skipped"), std::string::npos) << describe(same);
    const CliResult other = run("a.exr", "b.exr", "0.5", true);
    EXPECT_NE(other.err.find("b.exr was written with other settings"), std::string::npos) << describe(other);
}

// Two spellings of one sidecar (./ and a/../) are one recipe: the frame is skipped.
TEST(Resume, TakesTwoSpellingsOfAPathAsOne) {
    const Workspace w(freshDir());
    ASSERT_EQ(cli({w("in.exr"), "-o", w("out.exr"), "--camera", w("cam.json"), "--quiet"}).exitCode, 0);
    fs::create_directory(w.dir / "sub");
    const std::string spelled = (w.dir / "." / "sub" / ".." / "cam.json").string();
    const CliResult again = cli({w("in.exr"), "-o", w("out.exr"), "--camera", spelled, "--resume"});
    EXPECT_NE(again.err.find("complete; skipped"), std::string::npos) << describe(again);
}

// A new user runs --help's example exactly as printed, beside a render and its sidecar: it
// works, and every file they started with is byte-identical afterwards.
TEST(NothingOverwritten, HelpsExampleKeepsEveryFile) {
    const Workspace w(freshDir());
    fs::copy_file(kData + "/room.exr", w("shot.0001.exr"));
    fs::copy_file(kData + "/room.json", w("shot.0001.json"));
    const CliResult help = cli({"--help"});
    const size_t at = help.out.find("example:\n");
    ASSERT_NE(at, std::string::npos) << help.out;
    std::string example = help.out.substr(at + 9, help.out.find("\n\n", at) - at - 9);
    std::vector<std::string> args;
    std::istringstream words(example);
    for (std::string word; words >> word;)
        if (word != "\\") args.push_back(word);
    ASSERT_EQ(args.front(), "obscura");
    args.erase(args.begin());
    const auto before = snapshot(w.dir);
    const fs::path cwd = fs::current_path();
    fs::current_path(w.dir);  // the example's file names, exactly as printed
    const CliResult r = cli(args);
    fs::current_path(cwd);
    EXPECT_EQ(r.exitCode, 0) << describe(r);
    const auto after = snapshot(w.dir);
    for (const auto& [name, bytes] : before) EXPECT_TRUE(after.count(name) && after.at(name) == bytes) << name;
}
