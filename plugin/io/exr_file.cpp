#include "io/exr_file.h"

#include "base/error.h"
#include "io/atomic_files.h"
#include "io/exr_chunk_table.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfInputPart.h>
#include <OpenEXR/ImfMultiPartInputFile.h>
#include <OpenEXR/ImfMultiPartOutputFile.h>
#include <OpenEXR/ImfOutputPart.h>
#include <OpenEXR/ImfPartType.h>
#include <OpenEXR/ImfStandardAttributes.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <OpenEXR/ImfThreading.h>
#include <OpenEXR/ImfTiledInputPart.h>
#include <OpenEXR/ImfTiledOutputPart.h>
#include <Imath/half.h>
#include <OpenEXR/openexr.h>

#include <algorithm>
#include <climits>
#include <cstdint>
#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <thread>
#include <unistd.h>

namespace fs = std::filesystem;

namespace obscura {
namespace {

std::atomic<bool> g_threadsSet{false};

// OpenEXR messages can span lines; users get one.
std::string oneLine(std::string s) {
    for (char& c : s)
        if (c == '\n' || c == '\r') c = ' ';
    while (!s.empty() && s.back() == ' ') s.pop_back();
    return s;
}

} // namespace

void ensureExrThreads() {
    if (!g_threadsSet.load()) setExrThreads(0);
}

std::string exrErrorDetail(const std::exception& e) {
    std::string s = oneLine(e.what());
    size_t q = s.find(" file \""), end = q == std::string::npos ? q : s.find("\". ", q);
    if (end != std::string::npos && end + 3 < s.size()) s = s.substr(end + 3);
    return s;
}

namespace {

std::string quoted(const std::string& p) { return "'" + p + "'"; }

size_t bytesPerSample(Imf::PixelType t) { return t == Imf::HALF ? 2 : 4; }

float sampleToFloat(const char* p, Imf::PixelType t) {
    switch (t) {
    case Imf::HALF: { half h; std::memcpy(&h, p, 2); return float(h); }
    case Imf::UINT: { unsigned u; std::memcpy(&u, p, 4); return float(u); }
    default: { float f; std::memcpy(&f, p, 4); return f; }
    }
}

// Samples of `ch` over the part's data window.
size_t channelSamples(const ExrPart& part, const ExrChannel& ch) {
    return (size_t)sampleCount(part.dataWindow.x0, part.dataWindow.x1, ch.xSampling) *
           (size_t)sampleCount(part.dataWindow.y0, part.dataWindow.y1, ch.ySampling);
}

// Slice over a tightly packed buffer of `ch`'s samples (display coords -> EXR coords via header).
Imf::Slice makeSlice(const ExrPart& part, const ExrChannel& ch, Imf::PixelType type, const char* data) {
    const Imath::Box2i& dw = part.header.dataWindow();
    size_t bps = bytesPerSample(type);
    size_t nx = (size_t)sampleCount(dw.min.x, dw.max.x + 1, ch.xSampling);
    return Imf::Slice::Make(type, data, dw, bps, bps * nx, ch.xSampling, ch.ySampling);
}

// Level 0 of a tiled part, or all of a scanline part.
void readPart(Imf::MultiPartInputFile& file, int p, const ExrPart& part, const Imf::FrameBuffer& fb) {
    if (part.tiled) {
        Imf::TiledInputPart in(file, p);
        in.setFrameBuffer(fb);
        in.readTiles(0, in.numXTiles(0) - 1, 0, in.numYTiles(0) - 1, 0, 0);
    } else {
        Imf::InputPart in(file, p);
        in.setFrameBuffer(fb);
        const Imath::Box2i& dw = part.header.dataWindow();
        in.readPixels(dw.min.y, dw.max.y);
    }
}

bool partComplete(Imf::MultiPartInputFile& file, int p, bool tiled) {
    if (tiled) return Imf::TiledInputPart(file, p).isComplete();
    return Imf::InputPart(file, p).isComplete();
}

// A raw (possibly subsampled) channel -> full-resolution float plane over the data window.
Image toFloatPlane(const ExrPart& part, const ExrChannel& ch, const char* raw, Imf::PixelType type) {
    const Box2i& d = part.dataWindow;
    const Imath::Box2i& dw = part.header.dataWindow();
    Image img(d.width(), d.height(), 1);
    size_t bps = bytesPerSample(type);
    int nx = sampleCount(dw.min.x, dw.max.x + 1, ch.xSampling);
    auto floorDiv = [](int a, int b) { return a >= 0 ? a / b : -((-a + b - 1) / b); };
    int sx0 = floorDiv(dw.min.x + ch.xSampling - 1, ch.xSampling);
    int sy0 = floorDiv(dw.min.y + ch.ySampling - 1, ch.ySampling);
    for (int y = 0; y < d.height(); ++y) {
        int sy = floorDiv(dw.min.y + y, ch.ySampling) - sy0;
        if (sy < 0) sy = 0;
        for (int x = 0; x < d.width(); ++x) {
            int sx = floorDiv(dw.min.x + x, ch.xSampling) - sx0;
            if (sx < 0) sx = 0;
            img.pixels[(size_t)y * d.width() + x] = sampleToFloat(raw + ((size_t)sy * nx + sx) * bps, type);
        }
    }
    return img;
}

} // namespace

void checkExrMagic(const std::string& path) {
    // Before opening: opening a pipe with no writer blocks, where no stop check can reach.
    std::error_code ec;
    const fs::file_status st = fs::status(path, ec);
    if (fs::exists(st) && !fs::is_regular_file(st) && !fs::is_directory(st))
        throw FileError(path, "cannot open: not a regular file (a pipe, socket or device); give an EXR file on disk");
    std::ifstream f(path, std::ios::binary);
    if (!f) {
        int err = errno;
        if (!fs::exists(path)) throw FileError(path, "cannot open: no such file");
        throw FileError(path, std::string("cannot open: ") + std::strerror(err));
    }
    if (fs::is_directory(path)) throw FileError(path, "cannot open: it is a directory");
    unsigned char m[4] = {0, 0, 0, 0};
    f.read(reinterpret_cast<char*>(m), 4);
    unsigned magic = m[0] | (m[1] << 8) | (m[2] << 16) | ((unsigned)m[3] << 24);
    if (f.gcount() != 4 || magic != 20000630u)
        throw FileError(path, "not an OpenEXR file");
}

int sampleCount(int lo, int hiExclusive, int sampling) {
    // Samples sit at coordinates divisible by `sampling` (EXR's rule).
    if (sampling <= 1) return hiExclusive - lo;
    auto floorDiv = [](int a, int b) { return a >= 0 ? a / b : -((-a + b - 1) / b); };
    return floorDiv(hiExclusive - 1, sampling) - floorDiv(lo + sampling - 1, sampling) + 1;
}

int ExrPart::findChannel(const std::string& n) const {
    for (size_t i = 0; i < channels.size(); ++i)
        if (channels[i].name == n) return (int)i;
    return -1;
}

Box2i toDisplayBox(const Imath::Box2i& w, const Imath::Box2i& disp) {
    return Box2i{w.min.x - disp.min.x, w.min.y - disp.min.y, w.max.x + 1 - disp.min.x,
                 w.max.y + 1 - disp.min.y};
}

bool isLossy(Imf::Compression c) {
    switch (c) {
    case Imf::PXR24_COMPRESSION:
    case Imf::B44_COMPRESSION:
    case Imf::B44A_COMPRESSION:
    case Imf::DWAA_COMPRESSION:
    case Imf::DWAB_COMPRESSION: return true;
    default: return false;
    }
}

Imf::Compression losslessFor(Imf::Compression c) { return isLossy(c) ? Imf::ZIP_COMPRESSION : c; }

bool layersGoInPlace(const ExrPart& p) {
    const Imf::Header& h = p.header;
    const bool levels = h.hasTileDescription() && h.tileDescription().mode != Imf::ONE_LEVEL;
    return !isLossy(h.compression()) && !levels;
}

std::string compressionName(Imf::Compression c) {
    static const char* const names[] = {"none", "rle", "zips", "zip", "piz", "pxr24", "b44", "b44a", "dwaa", "dwab"};
    return c >= 0 && c < Imf::NUM_COMPRESSION_METHODS ? names[c] : "unknown";
}

ExrPixels layersOnlyFile(const ExrInfo& info, int p) {
    if (p < 0 || p >= (int)info.parts.size())
        throw Error("internal: no part " + std::to_string(p) + " in " + quoted(info.path));
    ExrPart part = info.parts[p];
    part.header = headerWithout(part.header, [](const char* name) {
        return std::strcmp(name, "name") == 0 || std::strcmp(name, "chunkCount") == 0 ||
               std::strcmp(name, "dwaCompressionLevel") == 0 || std::strncmp(name, "cryptomatte/", 12) == 0;
    });
    Imf::Header& h = part.header;
    h.channels() = Imf::ChannelList();
    h.compression() = losslessFor(h.compression());
    part.name.clear();
    part.channels.clear();
    ExrPixels out;
    out.info.path = info.path;
    out.info.parts = {std::move(part)};
    out.raw.resize(1);
    return out;
}

std::string layersPartName(const ExrInfo& info, const std::string& base) {
    auto taken = [&](const std::string& name) {
        for (const ExrPart& part : info.parts)
            if (part.name == name) return true;
        return false;
    };
    std::string name = base;
    for (int i = 2; taken(name); ++i) name = base + "." + std::to_string(i);
    return name;
}

int addLayersPart(ExrPixels& file, const ExrInfo& info, int from, const std::string& base) {
    ExrPixels own = layersOnlyFile(info, from);
    ExrPart& part = own.info.parts[0];
    part.name = layersPartName(file.info, base);
    part.header.setName(part.name);
    for (ExrPart& other : file.info.parts) {
        if (other.name.empty()) {
            other.name = "render";
            other.header.setName(other.name);
        }
        if (!other.header.hasType()) other.header.setType(other.tiled ? Imf::TILEDIMAGE : Imf::SCANLINEIMAGE);
    }
    if (!part.header.hasType()) part.header.setType(part.tiled ? Imf::TILEDIMAGE : Imf::SCANLINEIMAGE);
    file.info.parts.push_back(std::move(part));
    file.info.multipart = true;
    file.raw.emplace_back();
    return (int)file.info.parts.size() - 1;
}

int addLayersPart(ExrPixels& file, int from) {
    const ExrInfo source = file.info;
    return addLayersPart(file, source, from, "obscura");
}

void setExrThreads(int n) {
    if (n <= 0) n = (int)std::max(1u, std::thread::hardware_concurrency());
    // Files opened after this decode and encode chunks on n threads. One thread means the
    // frame's own (OpenEXR's count 0): a pool of one would be shared by every frame a
    // threaded host (a Dask worker) runs at once, queueing their I/O behind one thread.
    // Resizing the pool costs thread start-ups, and a host may run frames concurrently:
    // only when it changes.
    if (n == 1) n = 0;
    if (Imf::globalThreadCount() != n) Imf::setGlobalThreadCount(n);
    g_threadsSet = true;
}

ExrInfo readExrInfo(const std::string& path, long long maxPixels, bool allowDeep) {
    checkExrMagic(path);
    checkAttributeSizes(path);
    checkWindowsBeforeOpening(path, maxPixels);
    ensureExrThreads();
    ExrInfo info;
    info.path = path;
    try {
        Imf::MultiPartInputFile file(path.c_str());
        int n = file.parts();
        info.multipart = n > 1;
        for (int p = 0; p < n; ++p) {
            const Imf::Header& h = file.header(p);
            std::string type = h.hasType() ? h.type() : Imf::SCANLINEIMAGE;
            const bool deep = type == Imf::DEEPSCANLINE || type == Imf::DEEPTILE;
            // Again here: a header the core API refused was not checked before opening.
            checkWindow(path, "data", h.dataWindow(), maxPixels, 0, -1);
            checkWindow(path, "display", h.displayWindow(), maxPixels, 0, -1);
            ExrPart part;
            part.header = h;
            part.name = h.hasName() ? h.name() : "";
            part.tiled = type == Imf::TILEDIMAGE || type == Imf::DEEPTILE || (!h.hasType() && h.hasTileDescription());
            part.deep = deep;
            for (auto it = h.channels().begin(); !deep && it != h.channels().end(); ++it)
                part.channels.push_back({it.name(), it.channel().type, it.channel().xSampling,
                                         it.channel().ySampling});
            part.displayWindow = toDisplayBox(h.displayWindow(), h.displayWindow());
            part.dataWindow = toDisplayBox(h.dataWindow(), h.displayWindow());
            info.parts.push_back(std::move(part));
        }
    } catch (const Error&) {
        throw;
    } catch (const std::exception& e) {
        throw FileError(path, "truncated or corrupt: cannot read its header (" + exrErrorDetail(e) + ")");
    }
    if (!allowDeep) requireFlatParts(info);
    return info;
}

void requireFlatParts(const ExrInfo& info) {
    for (size_t p = 0; p < info.parts.size(); ++p)
        if (info.parts[p].deep)
            throw FileError(info.path, "holds deep data (part " + std::to_string(p) +
                                           ") where flat passes are read; a deep file is an input of its own (docs/deep.md)");
}

std::vector<Image> readExrChannels(const std::string& path, const ExrInfo& info,
                                   const std::vector<ChannelRef>& wanted, const std::vector<int>& rawParts,
                                   ExrPixels* out) {
    const int nParts = (int)info.parts.size();
    // Resolve wanted channels before touching pixel data: a typo is not corruption.
    std::vector<int> wantedIdx;
    for (const ChannelRef& r : wanted) {
        if (r.part < 0 || r.part >= nParts)
            throw FileError(path, "no part " + std::to_string(r.part));
        int c = info.parts[r.part].findChannel(r.name);
        if (c < 0) throw FileError(path, "no channel '" + r.name + "'" +
                               (info.multipart ? " in part " + std::to_string(r.part) : std::string()));
        wantedIdx.push_back(c);
    }
    if (!rawParts.empty() && !out) throw Error("internal: readExrChannels keeping raw parts needs an output");
    ensureExrThreads();

    // Raw buffers: every channel of a part kept raw; else float buffers for the wanted ones only.
    std::vector<std::vector<std::vector<char>>> raw(nParts);
    std::vector<bool> keep(nParts, false);
    for (int p : rawParts)
        if (p >= 0 && p < nParts) keep[p] = true;
    std::vector<std::vector<char>> floats(wanted.size());
    std::vector<Imf::FrameBuffer> fbs(nParts);
    std::vector<bool> readIt(nParts, false);
    for (int p = 0; p < nParts; ++p) {
        const ExrPart& part = info.parts[p];
        raw[p].resize(part.channels.size());
        if (!keep[p] || part.deep) continue;  // deep parts list no channels: nothing to decode
        readIt[p] = true;
        for (size_t c = 0; c < part.channels.size(); ++c) {
            const ExrChannel& ch = part.channels[c];
            raw[p][c].resize(channelSamples(part, ch) * bytesPerSample(ch.type));
            fbs[p].insert(ch.name, makeSlice(part, ch, ch.type, raw[p][c].data()));
        }
    }
    for (size_t i = 0; i < wanted.size(); ++i) {
        if (keep[wanted[i].part]) continue;  // read raw, converted below
        const ExrPart& part = info.parts[wanted[i].part];
        const ExrChannel& ch = part.channels[wantedIdx[i]];
        floats[i].resize(channelSamples(part, ch) * 4);
        fbs[wanted[i].part].insert(ch.name, makeSlice(part, ch, Imf::FLOAT, floats[i].data()));
        readIt[wanted[i].part] = true;
    }

    try {
        Imf::MultiPartInputFile file(path.c_str());
        if (file.parts() != nParts) throw FileError(path, "changed while being read");
        for (int p = 0; p < nParts; ++p) {
            if (!readIt[p] || info.parts[p].dataWindow.empty()) continue;
            if (!partComplete(file, p, info.parts[p].tiled))
                throw FileError(path, "truncated or corrupt: part " + std::to_string(p) +
                            " is missing pixel data");
            readPart(file, p, info.parts[p], fbs[p]);
        }
    } catch (const Error&) {
        throw;
    } catch (const std::exception& e) {
        throw FileError(path, "truncated or corrupt: " + exrErrorDetail(e));
    }

    std::vector<Image> result;
    for (size_t i = 0; i < wanted.size(); ++i) {
        const ExrPart& part = info.parts[wanted[i].part];
        const ExrChannel& ch = part.channels[wantedIdx[i]];
        if (keep[wanted[i].part])
            result.push_back(toFloatPlane(part, ch, raw[wanted[i].part][wantedIdx[i]].data(), ch.type));
        else
            result.push_back(toFloatPlane(part, ch, floats[i].data(), Imf::FLOAT));
    }
    if (out) {
        out->info = info;
        out->raw = std::move(raw);
    }
    return result;
}

std::vector<Image> readExrChannels(const std::string& path, const ExrInfo& info,
                                   const std::vector<ChannelRef>& wanted, bool keepAll, ExrPixels* out) {
    std::vector<int> parts;
    for (int p = 0; keepAll && p < (int)info.parts.size(); ++p) parts.push_back(p);
    return readExrChannels(path, info, wanted, parts, out);
}

namespace {

std::vector<char> encodePlane(const Image& img, Imf::PixelType type) {
    size_t bps = bytesPerSample(type);
    std::vector<char> buf(img.pixels.size() * bps);
    for (size_t i = 0; i < img.pixels.size(); ++i) {
        float v = img.pixels[i];
        char* p = buf.data() + i * bps;
        if (type == Imf::HALF) {
            half h(v);
            std::memcpy(p, &h, 2);
        } else if (type == Imf::UINT) {
            unsigned u = v > 0 ? (v < 4294967295.0f ? (unsigned)v : 4294967295u) : 0u;  // NaN -> 0
            std::memcpy(p, &u, 4);
        } else {
            std::memcpy(p, &v, 4);
        }
    }
    return buf;
}

bool replacedBy(const std::vector<const NewChannel*>& add, const std::string& name) {
    for (const NewChannel* nc : add)
        if (nc->name == name) return true;
    return false;
}

// The attributes OpenEXR requires the parts of one file to share (MultiPartOutputFile checks
// each part's against the first's): the display window, the pixel aspect ratio, and when
// present the chromaticities and the time code (looked up under both spellings OpenEXR uses).
bool isSharedAttribute(const char* name) {
    return std::strcmp(name, "chromaticities") == 0 || std::strcmp(name, "timeCode") == 0 ||
           std::strcmp(name, "timecode") == 0;
}

// Every part after the first takes the first's shared attributes: a part obscura adds is a
// copy of the depth's part, whose values a valid input shares already; an input whose parts
// disagree gets the first part's.
void shareFirstPartsAttributes(std::vector<Imf::Header>& headers) {
    for (size_t i = 1; i < headers.size(); ++i) {
        Imf::Header h = headerWithout(headers[i], isSharedAttribute);
        h.displayWindow() = headers[0].displayWindow();
        h.pixelAspectRatio() = headers[0].pixelAspectRatio();
        for (auto it = headers[0].begin(); it != headers[0].end(); ++it)
            if (isSharedAttribute(it.name())) h.insert(it.name(), it.attribute());
        headers[i] = std::move(h);
    }
}

// Whether part p gets nothing new: its compressed chunks are then copied as they are. Encoding them
// again would lose more of a lossy codec's (DWAA, B44) and keep only a mip-mapped part's level 0.
bool untouched(int p, const std::vector<std::vector<const NewChannel*>>& byPart, const std::vector<StringAttribute>& attrs) {
    return byPart[p].empty() && std::none_of(attrs.begin(), attrs.end(), [p](const StringAttribute& a) { return a.part == p; });
}

void writeParts(const std::string& tmp, const ExrPixels& in,
                const std::vector<std::vector<const NewChannel*>>& byPart,
                const std::vector<StringAttribute>& attrs) {
    const int nParts = (int)in.info.parts.size();
    // One choice per part, for its header and its pixels alike: encoded again (level 0, as read)
    // or copied chunk for chunk (the input's header, every level).
    std::vector<bool> encoded(nParts);
    std::vector<Imf::Header> headers;
    for (int p = 0; p < nParts; ++p) {
        encoded[p] = !untouched(p, byPart, attrs) || !in.copyChunks;
        headers.push_back(encoded[p] ? headerWithNewChannels(in.info.parts[p], byPart[p], attrs, p)
                                     : headerWithout(in.info.parts[p].header,
                                                     [](const char* n) { return std::strcmp(n, "chunkCount") == 0; }));
    }
    shareFirstPartsAttributes(headers);
    Imf::MultiPartOutputFile file(tmp.c_str(), headers.data(), nParts);
    std::optional<Imf::MultiPartInputFile> source;
    for (int p = 0; p < nParts; ++p) {
        if (encoded[p]) {
            writePartPixels(file, p, in.info.parts[p], in.raw[p], byPart[p]);
            continue;
        }
        if (!source) {
            // The file's own parts (a part obscura adds is not among them): a table OpenEXR would
            // rebuild by scanning is refused.
            if (!in.chunkTablesChecked)
                checkChunkTables(in.info.path, readExrInfo(in.info.path, std::numeric_limits<long long>::max(), true));
            source.emplace(in.info.path.c_str());
        }
        if (p >= source->parts()) throw FileError(in.info.path, "changed while being read");
        copyPartChunks(*source, file, p);
    }
}

bool samePath(const std::string& a, const std::string& b) {
    std::error_code ec;
    if (fs::exists(a, ec) && fs::exists(b, ec)) return fs::equivalent(a, b, ec);
    return fs::weakly_canonical(a, ec) == fs::weakly_canonical(b, ec);
}

} // namespace

Imf::Header headerWithNewChannels(const ExrPart& part, const std::vector<const NewChannel*>& add,
                                  const std::vector<StringAttribute>& attrs, int p) {
    // chunkCount: the writer counts its own, and a corrupt input's may have the wrong type.
    Imf::Header h = headerWithout(part.header, [](const char* name) { return std::strcmp(name, "chunkCount") == 0; });
    Imf::ChannelList list;  // ChannelList has no erase: rebuild it, dropping replaced channels
    for (auto it = h.channels().begin(); it != h.channels().end(); ++it)
        if (!replacedBy(add, it.name())) list.insert(it.name(), it.channel());
    for (const NewChannel* nc : add) list.insert(nc->name, Imf::Channel(nc->type));
    h.channels() = list;
    for (const StringAttribute& a : attrs)
        if (a.part == p) h.insert(a.name, Imf::StringAttribute(a.value));
    if (h.hasTileDescription() && h.tileDescription().mode != Imf::ONE_LEVEL) {
        // Only level 0 was read; lower levels would have to be rebuilt.
        Imf::TileDescription td = h.tileDescription();
        td.mode = Imf::ONE_LEVEL;
        h.setTileDescription(td);
    }
    return h;
}

void writePartPixels(Imf::MultiPartOutputFile& file, int p, const ExrPart& part,
                     const std::vector<std::vector<char>>& raw, const std::vector<const NewChannel*>& add) {
    // OpenEXR does not convert on output: new planes go to their channel's type first.
    std::vector<std::vector<char>> converted;
    for (const NewChannel* nc : add) converted.push_back(encodePlane(nc->plane, nc->type));
    Imf::FrameBuffer fb;
    for (size_t c = 0; c < part.channels.size(); ++c) {
        const ExrChannel& ch = part.channels[c];
        if (!replacedBy(add, ch.name)) fb.insert(ch.name, makeSlice(part, ch, ch.type, raw[c].data()));
    }
    for (size_t i = 0; i < add.size(); ++i) {
        const ExrChannel ch{add[i]->name, add[i]->type, 1, 1};
        fb.insert(ch.name, makeSlice(part, ch, ch.type, converted[i].data()));
    }
    if (part.dataWindow.empty()) return;
    if (part.tiled) {
        Imf::TiledOutputPart out(file, p);
        out.setFrameBuffer(fb);
        out.writeTiles(0, out.numXTiles(0) - 1, 0, out.numYTiles(0) - 1, 0, 0);
    } else {
        Imf::OutputPart out(file, p);
        out.setFrameBuffer(fb);
        out.writePixels(part.dataWindow.height());
    }
}

std::vector<std::vector<const NewChannel*>> newChannelsByPart(const std::string& outPath, const ExrInfo& info,
                                                              const std::vector<NewChannel>& add,
                                                              const std::vector<StringAttribute>& attrs) {
    const int nParts = (int)info.parts.size();
    std::vector<std::vector<const NewChannel*>> byPart(nParts);
    for (const NewChannel& nc : add) {
        if (nc.part < 0 || nc.part >= nParts)
            throw FileError(outPath, "cannot add channel '" + nc.name + "': no part " + std::to_string(nc.part));
        const Box2i& d = info.parts[nc.part].dataWindow;
        if (nc.name.empty() || nc.plane.channels != 1 || nc.plane.width != d.width() || nc.plane.height != d.height())
            throw FileError(outPath, "cannot add channel '" + nc.name + "'" +
                                         ": it needs a name and a 1-channel plane of " + std::to_string(d.width()) +
                                         "x" + std::to_string(d.height()) + " (the data window)");
        if (replacedBy(byPart[nc.part], nc.name))
            throw FileError(outPath, "cannot add channel '" + nc.name + "' twice");
        byPart[nc.part].push_back(&nc);
    }
    for (const StringAttribute& a : attrs)
        if (a.part < 0 || a.part >= nParts)
            throw FileError(outPath, "cannot add attribute '" + a.name + "': no part " + std::to_string(a.part));
    return byPart;
}

void writeFileAtomically(const std::string& outPath, const std::string& inputPath, bool allowOverwriteInput,
                         const std::function<void(const std::string& tmp)>& write) {
    if (!allowOverwriteInput && samePath(outPath, inputPath))
        throw FileError(inputPath, "refusing to overwrite the input (use --in-place)");
    ensureExrThreads();
    writeAtomically(outPath, [&](const std::string& tmp) {
        try {
            write(tmp);
        } catch (const Error&) {
            throw;
        } catch (const std::exception& e) {
            throw FileError(outPath, "cannot write: " + exrErrorDetail(e));
        }
    });
}

void writeExrWithNewChannels(const std::string& outPath, const ExrPixels& in,
                             const std::vector<NewChannel>& add, bool allowOverwriteInput,
                             const std::vector<StringAttribute>& attrs) {
    const ExrInfo& info = in.info;
    const int nParts = (int)info.parts.size();
    if (nParts == 0 || (int)in.raw.size() != nParts)
        throw Error("internal: no pixels kept for pass-through of " + quoted(info.path));
    const std::vector<std::vector<const NewChannel*>> byPart = newChannelsByPart(outPath, info, add, attrs);
    for (int p = 0; p < nParts; ++p) {  // a part encoded again needs all its pixels
        if (untouched(p, byPart, attrs) && in.copyChunks) continue;
        const ExrPart& part = info.parts[p];
        if (in.raw[p].size() != part.channels.size())
            throw Error("internal: pixels of " + quoted(info.path) + " were not all kept");
        for (size_t c = 0; c < part.channels.size(); ++c)
            if (in.raw[p][c].size() != channelSamples(part, part.channels[c]) * bytesPerSample(part.channels[c].type))
                throw Error("internal: pixels of " + quoted(info.path) + " were not all kept");
    }
    writeFileAtomically(outPath, info.path, allowOverwriteInput,
                        [&](const std::string& tmp) { writeParts(tmp, in, byPart, attrs); });
}

} // namespace obscura
