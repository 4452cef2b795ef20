// Replay fuzzer: writes a few small valid renders (single-part, multipart, tiled, half,
// overscan, DWA/PIZ/B44 codecs, a subsampled pass-through channel), derives deterministic mutants
// (tests/fuzz/mutate.h) and runs each through the CLI's own code in a forked child:
//   failure: exit 1, exactly one stderr line "obscura: ..." naming the mutant, nothing left
//            in the output directory;
//   success: every input channel in the output, AO finite and within [0, 1], no temp file;
//   never:   a signal, a sanitizer report, or a run longer than --timeout seconds.
// Usage: obscura_fuzz [--count N] [--start I] [--dir D] [--jobs J] [--timeout S] [--seed-only K] [--verbose 1]
// OBSCURA_FUZZ_COUNT overrides --count. Bad mutants are kept in D/findings.
#include "cli/cli.h"
#include "fuzz/mutate.h"
#include "support/exr_fixtures.h"
#include "support/scenes.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfInputPart.h>
#include <OpenEXR/ImfMultiPartInputFile.h>
#include <OpenEXR/ImfTiledInputPart.h>

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace fs = std::filesystem;
using namespace obscura;
using namespace obscura::fixtures;
using obscura::fuzz::Bytes;

namespace {

const char* const kAoChannel = "obscura.AO.Y";

struct Seed {
    std::string name;
    Bytes exr;
    std::string json;  // camera sidecar
};

Bytes readBytes(const fs::path& p) {
    std::ifstream f(p, std::ios::binary);
    return Bytes(std::istreambuf_iterator<char>(f), {});
}
void writeBytes(const fs::path& p, const void* data, std::size_t n) {
    std::ofstream f(p, std::ios::binary);
    f.write(static_cast<const char*>(data), (std::streamsize)n);
}

Imath::Box2i toImath(const Box2i& b) { return {Imath::V2i(b.x0, b.y0), Imath::V2i(b.x1 - 1, b.y1 - 1)}; }

FixtureChannel plane(const std::string& name, std::shared_ptr<Image> img, int c, Box2i data, Imf::PixelType t) {
    FixtureChannel ch;
    ch.name = name;
    ch.type = t;
    ch.value = [img, c, data](int x, int y) { return img->at(x - data.x0, y - data.y0)[c]; };
    return ch;
}

// Depth "Z", normals "N.X/Y/Z" (world), optional position "P.X/Y/Z", over the studio scene.
FixturePart scenePart(const test::SceneBuffers& s, Imf::PixelType t, bool position) {
    FixturePart part;
    part.displayWindow = toImath(s.display);
    part.dataWindow = toImath(s.data);
    auto depth = std::make_shared<Image>(s.depth), normal = std::make_shared<Image>(s.normal),
         pos = std::make_shared<Image>(s.position);
    part.channels.push_back(plane("Z", depth, 0, s.data, t));
    for (int c = 0; c < 3; ++c) part.channels.push_back(plane(std::string("N.") + "XYZ"[c], normal, c, s.data, t));
    if (position)
        for (int c = 0; c < 3; ++c) part.channels.push_back(plane(std::string("P.") + "XYZ"[c], pos, c, s.data, t));
    return part;
}

std::string sidecar(const Camera& cam, int w, int h) {
    std::ostringstream j;
    j.precision(17);
    j << "{\n \"width\": " << w << ",\n \"height\": " << h << ",\n \"projection\": \"persp\",\n"
      << " \"horizontal_fov_rad\": " << 2.0 * std::atan(0.5 * w / cam.fx) << ",\n \"camera_to_world\": [";
    for (int r = 0; r < 4; ++r) {
        j << (r ? ",\n  [" : "\n  [");
        for (int c = 0; c < 4; ++c) j << (c ? ", " : "") << cam.cameraToWorld[c][r];
        j << "]";
    }
    j << "\n ]\n}\n";
    return j.str();
}

std::vector<Seed> writeSeeds(const fs::path& dir) {
    fs::create_directories(dir);
    const int w = 32, h = 24;
    const Camera cam = test::studioCamera(w, h);
    const test::SceneBuffers flat = test::renderScene(test::studioScene(), cam, w, h);
    const test::SceneBuffers over =
        test::renderScene(test::studioScene(), cam, Box2i{0, 0, w, h}, Box2i{-4, -3, w + 4, h + 3});
    const std::string json = sidecar(cam, w, h);

    std::vector<std::pair<std::string, std::vector<FixturePart>>> files;
    {  // single-part scanline float, ZIP, with a beauty and a subsampled pass-through channel
        FixturePart p = scenePart(flat, Imf::FLOAT, false);
        for (const char* c : {"R", "G", "B"}) p.channels.push_back({c, Imf::HALF, 1, 1, {}});
        p.channels.push_back({"chroma.RY", Imf::HALF, 2, 2, {}});
        files.push_back({"single_zip", {p}});
    }
    {  // multipart: a beauty part, then tiled PIZ half AOVs
        FixturePart beauty;
        beauty.name = "rgba";
        beauty.displayWindow = beauty.dataWindow = toImath(flat.data);
        for (const char* c : {"R", "G", "B", "A"}) beauty.channels.push_back({c, Imf::HALF, 1, 1, {}});
        FixturePart aovs = scenePart(flat, Imf::HALF, true);
        aovs.name = "aovs";
        aovs.tiled = true;
        aovs.tileWidth = aovs.tileHeight = 16;
        aovs.compression = Imf::PIZ_COMPRESSION;
        files.push_back({"multipart_tiled_piz", {beauty, aovs}});
    }
    {  // half, RLE, decreasing lines
        FixturePart p = scenePart(flat, Imf::HALF, true);
        p.compression = Imf::RLE_COMPRESSION;
        p.lineOrder = Imf::DECREASING_Y;
        files.push_back({"half_rle", {p}});
    }
    {  // overscan data window, float, no compression
        FixturePart p = scenePart(over, Imf::FLOAT, false);
        p.compression = Imf::NO_COMPRESSION;
        files.push_back({"overscan", {p}});
    }
    {  // DWAA with a lossy beauty; AO must go to a part of its own
        FixturePart p = scenePart(flat, Imf::FLOAT, false);
        p.compression = Imf::DWAA_COMPRESSION;
        for (const char* c : {"R", "G", "B"}) p.channels.push_back({c, Imf::HALF, 1, 1, {}});
        files.push_back({"dwaa", {p}});
    }
    {  // tiled DWAB half
        FixturePart p = scenePart(flat, Imf::HALF, false);
        p.tiled = true;
        p.compression = Imf::DWAB_COMPRESSION;
        files.push_back({"tiled_dwab", {p}});
    }
    {  // multipart scanline, B44 half beauty + ZIPS float data, uint ID
        FixturePart beauty;
        beauty.name = "beauty";
        beauty.displayWindow = beauty.dataWindow = toImath(flat.data);
        beauty.compression = Imf::B44_COMPRESSION;
        for (const char* c : {"R", "G", "B"}) beauty.channels.push_back({c, Imf::HALF, 1, 1, {}});
        FixturePart data = scenePart(flat, Imf::FLOAT, false);
        data.name = "data";
        data.compression = Imf::ZIPS_COMPRESSION;
        data.channels.push_back({"id", Imf::UINT, 1, 1, [](int x, int y) { return float(x + y); }});
        files.push_back({"multipart_b44_zips", {beauty, data}});
    }
    std::vector<Seed> seeds;
    for (const auto& [name, parts] : files) {
        const fs::path p = dir / (name + ".exr");
        writeFixture(p.string(), parts);
        seeds.push_back({name, readBytes(p), json});
    }
    return seeds;
}

// The real Blender renders of tests/data (ZIP, 23 float channels, 320 x 320 and 320 x 240).
std::vector<Seed> realSeeds() {
    std::vector<Seed> seeds;
    for (const char* name : {"room", "columns"}) {
        const fs::path exr = fs::path(OBSCURA_TEST_DATA_DIR) / (std::string(name) + ".exr");
        std::ifstream json(fs::path(OBSCURA_TEST_DATA_DIR) / (std::string(name) + ".json"));
        std::ostringstream text;
        text << json.rdbuf();
        seeds.push_back({std::string("real_") + name, readBytes(exr), text.str()});
        if (seeds.back().exr.empty()) throw std::runtime_error("cannot read " + exr.string());
    }
    return seeds;
}

// ---- the child: run the CLI, and on success check the output ----

enum Verdict { kOk = 0, kFailed = 1, kUsage = 2, kOutOfRange = 20, kLostChannel = 21, kUnreadable = 22 };

std::vector<std::set<std::string>> channelsByPart(const std::string& path) {
    Imf::MultiPartInputFile f(path.c_str());
    std::vector<std::set<std::string>> out(f.parts());
    for (int p = 0; p < f.parts(); ++p)
        for (auto it = f.header(p).channels().begin(); it != f.header(p).channels().end(); ++it)
            out[p].insert(it.name());
    return out;
}

int checkOutput(const std::string& in, const std::string& out) {
    try {
        const auto before = channelsByPart(in), after = channelsByPart(out);
        if (after.size() < before.size()) return kLostChannel;
        for (std::size_t p = 0; p < before.size(); ++p)
            for (const std::string& c : before[p])
                if (!after[p].count(c)) return kLostChannel;
        Imf::MultiPartInputFile f(out.c_str());
        for (int p = 0; p < f.parts(); ++p) {
            const Imf::Header& h = f.header(p);
            if (!h.channels().findChannel(kAoChannel)) continue;
            const Imath::Box2i dw = h.dataWindow();
            const long w = dw.max.x - dw.min.x + 1, ht = dw.max.y - dw.min.y + 1;
            std::vector<float> ao((std::size_t)w * ht, -1.0f);
            Imf::FrameBuffer fb;
            char* base = (char*)(ao.data() - dw.min.x - (long)dw.min.y * w);
            fb.insert(kAoChannel, Imf::Slice(Imf::FLOAT, base, sizeof(float), sizeof(float) * w));
            if (h.hasTileDescription()) {
                Imf::TiledInputPart t(f, p);
                t.setFrameBuffer(fb);
                t.readTiles(0, t.numXTiles(0) - 1, 0, t.numYTiles(0) - 1);
            } else {
                Imf::InputPart s(f, p);
                s.setFrameBuffer(fb);
                s.readPixels(dw.min.y, dw.max.y);
            }
            for (float v : ao)
                if (!(v >= 0.0f && v <= 1.0f)) return kOutOfRange;
            return kOk;
        }
        return kLostChannel;  // no AO channel at all
    } catch (const std::exception&) {
        return kUnreadable;
    }
}

[[noreturn]] void child(const fs::path& in, const fs::path& outDir, const fs::path& errFile, bool skipBadPixels) {
    const int err = ::open(errFile.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int nul = ::open("/dev/null", O_WRONLY);
    ::dup2(err, 2);
    ::dup2(nul, 1);
    const std::string out = (outDir / "out.exr").string();
    std::vector<std::string> args = {"obscura", in.string(), "-o", out, "--threads", "1", "--quiet"};
    if (skipBadPixels) args.insert(args.end(), {"--bad-pixels", "skip"});  // extreme values reach the kernels
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    int rc = cli::run((int)args.size(), argv.data());
    if (rc == 0) rc = checkOutput(in.string(), out);
    std::fflush(stderr);
    std::fflush(stdout);
    ::_exit(rc);
}

// ---- the parent: classify ----

struct Counts {
    long total = 0, ok = 0, failedCleanly = 0;
    std::map<std::string, long> bad;  // class -> count
};

bool contains(const std::string& s, const std::string& p) { return s.find(p) != std::string::npos; }

std::string readText(const fs::path& p) {
    std::ifstream f(p, std::ios::binary);
    std::ostringstream ss;
    ss << f.rdbuf();
    return ss.str();
}

// "" if the run is as required, else the class of the problem.
std::string classify(int status, bool timedOut, const std::string& err, const std::string& stem,
                     const fs::path& outDir) {
    if (timedOut) return "hang";
    if (WIFSIGNALED(status)) return "crash (signal " + std::to_string(WTERMSIG(status)) + ")";
    if (contains(err, "Sanitizer") || contains(err, "runtime error:")) return "crash (sanitizer)";
    std::vector<std::string> files;
    for (const auto& e : fs::directory_iterator(outDir)) files.push_back(e.path().filename().string());
    const int rc = WEXITSTATUS(status);
    switch (rc) {
    case kOk:
        if (files != std::vector<std::string>{"out.exr"}) return "leftover temp file";
        return err.empty() ? "" : "stderr on success";
    case kFailed: {
        if (!files.empty()) return "leftover temp file";
        const bool oneLine = !err.empty() && err.back() == '\n' && err.find('\n') == err.size() - 1;
        if (!oneLine) return "multi-line error";
        if (err.rfind("obscura: ", 0) != 0) return "error without 'obscura: '";
        const std::string named = "obscura: '" + (outDir.parent_path() / stem).string();
        if (err.rfind(named + ".exr': ", 0) != 0 && err.rfind(named + ".json': ", 0) != 0)
            return "error not starting with the file's name";
        for (const char* raw : {"json.exception", "Iex", "Imf_", "OIIO", "terminate"})
            if (contains(err, raw)) return "raw library text";
        return "";
    }
    case kUsage: return "exit 2 for a file";
    case kOutOfRange: return "AO out of range";
    case kLostChannel: return "lost channel";
    case kUnreadable: return "output unreadable";
    default: return "exit " + std::to_string(rc);
    }
}

struct Running {
    pid_t pid;
    long index;
    std::string what;
    fs::path dir;
    std::chrono::steady_clock::time_point start;
    bool killed = false;
};

} // namespace

int main(int argc, char** argv) {
    long count = 300, start = 0;
    int jobs = 2, timeoutSec = 30, seedOnly = -1;
    bool verbose = false;
    fs::path dir = fs::temp_directory_path() / "obscura-fuzz";
    for (int i = 1; i + 1 < argc; i += 2) {
        const std::string a = argv[i], v = argv[i + 1];
        if (a == "--count") count = std::stol(v);
        else if (a == "--start") start = std::stol(v);
        else if (a == "--dir") dir = v;
        else if (a == "--jobs") jobs = std::max(1, std::stoi(v));
        else if (a == "--timeout") timeoutSec = std::stoi(v);
        else if (a == "--seed-only") seedOnly = std::stoi(v);
        else if (a == "--verbose") verbose = v == "1";
        else {
            std::cerr << "obscura_fuzz: unknown option " << a << "\n";
            return 2;
        }
    }
    if (const char* env = std::getenv("OBSCURA_FUZZ_COUNT")) count = std::atol(env);

    fs::remove_all(dir / "work");
    const std::vector<Seed> seeds = writeSeeds(dir / "seeds"), real = realSeeds();
    const Seed* uncompressed = nullptr;  // the seed extreme payloads are written into
    for (const Seed& s : seeds)
        if (s.name == "overscan") uncompressed = &s;
    fs::create_directories(dir / "findings");
    fs::create_directories(dir / "work");

    Counts counts;
    std::vector<Running> running;
    long next = start;
    int reported = 0;
    auto finish = [&](Running& r, int status) {
        const std::string stem = "mutant-" + std::to_string(r.index);
        const std::string err = readText(r.dir / "stderr.txt");
        const std::string bad = classify(status, r.killed, err, stem, r.dir / "out");
        ++counts.total;
        if (verbose) std::cout << stem << " " << r.what << "\n    " << (err.empty() ? "(ok)\n" : err);
        if (bad.empty()) {
            if (WIFEXITED(status) && WEXITSTATUS(status) == 0) ++counts.ok;
            else ++counts.failedCleanly;
            fs::remove_all(r.dir);
            return;
        }
        ++counts.bad[bad];
        const fs::path keep = dir / "findings" / stem;
        fs::remove_all(keep);
        fs::rename(r.dir, keep);
        if (reported++ < 40)
            std::cout << stem << " [" << bad << "] " << r.what << "\n    " << err.substr(0, 400)
                      << (err.empty() || err.back() != '\n' ? "\n" : "");
    };

    const long end = start + count;
    while (next < end || !running.empty()) {
        while (next < end && (int)running.size() < jobs) {
            const long i = next++;
            // Every 10th mutant a broken sidecar, every 10th (others) extreme pixel values,
            // every 20th a real render (slow: 100k pixels, 23 channels), the rest the small seeds.
            const bool payload = seedOnly < 0 && i % 10 == 4, realSeed = seedOnly < 0 && i % 20 == 7;
            const Seed& seed = payload    ? *uncompressed
                               : realSeed ? real[(i / 20) % real.size()]
                                          : seeds[seedOnly >= 0 ? seedOnly % seeds.size() : i % seeds.size()];
            const std::string stem = "mutant-" + std::to_string(i);
            const fs::path d = dir / "work" / stem;
            fs::create_directories(d / "out");
            std::string what = seed.name + ":";
            std::string json = seed.json;
            Bytes exr = seed.exr;
            const bool skipBadPixels = payload && (i / 10) % 2 == 1;
            if (i % 10 == 9) {  // a broken sidecar beside an intact file
                json = fuzz::mutateJson(seed.json, (std::uint64_t)i, what);
            } else if (payload) {
                if (!fuzz::extremePayload(exr, (std::uint64_t)i, what))
                    throw std::runtime_error("the overscan seed takes no payload edit");
                if (skipBadPixels) what += " --bad-pixels skip";
            } else {
                exr = fuzz::mutateExr(seed.exr, (std::uint64_t)i, what);
            }
            writeBytes(d / (stem + ".exr"), exr.data(), exr.size());
            writeBytes(d / (stem + ".json"), json.data(), json.size());
            std::cout.flush();
            const pid_t pid = ::fork();
            if (pid == 0) child(d / (stem + ".exr"), d / "out", d / "stderr.txt", skipBadPixels);
            running.push_back({pid, i, what, d, std::chrono::steady_clock::now()});
        }
        int status = 0;
        const pid_t done = ::waitpid(-1, &status, WNOHANG);
        if (done > 0) {
            for (std::size_t k = 0; k < running.size(); ++k)
                if (running[k].pid == done) {
                    finish(running[k], status);
                    running.erase(running.begin() + (long)k);
                    break;
                }
            continue;
        }
        for (Running& r : running)
            if (!r.killed && std::chrono::steady_clock::now() - r.start > std::chrono::seconds(timeoutSec)) {
                ::kill(r.pid, SIGKILL);
                r.killed = true;
            }
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }

    long badTotal = 0;
    std::map<std::string, long> kinds;  // the issue's figures, each printed even when zero
    for (const auto& [k, n] : counts.bad) {
        badTotal += n;
        const std::string kind = k.rfind("crash", 0) == 0                           ? "crashes"
                                 : k == "hang"                                       ? "hangs"
                                 : k == "AO out of range"                            ? "outputs outside [0, 1] or NaN"
                                 : k == "lost channel"                               ? "lost channels"
                                 : k == "leftover temp file"                         ? "temp files left"
                                 : k.find("error") != std::string::npos || k == "raw library text" ? "bad error lines"
                                                                                     : "other";
        kinds[kind] += n;
    }
    std::cout << "mutants " << counts.total << ": " << counts.ok << " succeeded, " << counts.failedCleanly
              << " refused with one clean line, " << badTotal << " bad\n";
    for (const char* kind : {"crashes", "hangs", "outputs outside [0, 1] or NaN", "lost channels", "bad error lines",
                             "temp files left", "other"})
        std::cout << "  " << kind << ": " << kinds[kind] << "\n";
    for (const auto& [k, n] : counts.bad) std::cout << "    " << k << ": " << n << "\n";
    if (badTotal == 0) fs::remove_all(dir / "work");
    return badTotal == 0 ? 0 : 1;
}
