// EXR file layer: headers, pixel reading (wanted channels as float, everything
// else raw for pass-through) and atomic writing of a copy with new channels.
#pragma once
#include "base/image.h"

#include <OpenEXR/ImfCompression.h>
#include <OpenEXR/ImfForward.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfPixelType.h>

#include <exception>
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace obscura {

struct ExrChannel {
    std::string name;
    Imf::PixelType type = Imf::FLOAT;
    int xSampling = 1, ySampling = 1;
};

// A copy of `h` without the attributes `drop(name)` is true for. Copied one by one rather than
// erased: OpenEXR 3.1's Header::erase leaks the attribute (fixed upstream in 2023, PR #1520),
// which stops ASan runs.
template <class Drop>
Imf::Header headerWithout(const Imf::Header& h, Drop drop) {
    Imf::Header out;
    for (auto it = h.begin(); it != h.end(); ++it)
        if (!drop(it.name())) out.insert(it.name(), it.attribute());
    return out;
}

struct ExrPart {
    Imf::Header header;            // full header, every attribute kept for pass-through
    std::string name;              // part name ("" for a single part without a name)
    std::vector<ExrChannel> channels;  // sorted by name, as in the file
    Box2i displayWindow, dataWindow;   // display coords: display min = (0,0), half-open
    bool tiled = false;
    bool deep = false;             // read with allowDeep: its channels are not listed (never decoded)

    int findChannel(const std::string& name) const;  // index or -1
};

struct ExrInfo {
    std::string path;
    std::vector<ExrPart> parts;
    bool multipart = false;
};

// EXR's Box2i (inclusive) -> display-coordinate Box2i (half-open, display min = 0,0).
Box2i toDisplayBox(const Imath::Box2i& window, const Imath::Box2i& displayWindow);

// The default bound on the pixels of one window (16384 x 16384), checked before allocating.
constexpr long long kDefaultMaxPixels = 16384LL * 16384;

// "'path': <which> window [x0,y0 - x1,y1] is <why>" when a window of w x h pixels is empty or
// inverted, holds more than maxPixels, or (fileBytes >= 0) claims more chunks than the
// fileBytes could hold: a header must not make obscura allocate without a bound.
void checkWindow(const std::string& path, const char* which, const Imath::Box2i& window, long long maxPixels,
                 long long minFileBytes = -1, long long fileBytes = -1);

// Every part's data and display windows through checkWindow, before any reader (OpenEXR's or
// OpenImageIO's, deep parts too) allocates what they claim. A file that is not an EXR passes:
// its reader reports it.
void checkWindowsBeforeOpening(const std::string& path, long long maxPixels);

// FileError when `path` cannot be opened, is a directory or lacks OpenEXR's magic number.
void checkExrMagic(const std::string& path);
// Every attribute's size against the file's: OpenEXR's C++ API allocates and fills what a size
// field claims (a 2 GB string attribute takes it half a minute) before it finds the file short.
// Only the sizes are checked; anything else malformed is left to the libraries to report.
void checkAttributeSizes(const std::string& path);

// Headers only. Errors: missing file, not an EXR (magic number), deep data (unless allowDeep:
// then deep parts are listed without channels, for a writer that copies them untouched),
// unreadable header, a data or display window above maxPixels or larger than the file's size
// can hold.
ExrInfo readExrInfo(const std::string& path, long long maxPixels = kDefaultMaxPixels, bool allowDeep = false);
// readExrInfo's deep-data error, for headers read with allowDeep where flat passes are wanted.
void requireFlatParts(const ExrInfo& info);

struct ChannelRef {
    int part = 0;
    std::string name;
};

// A file's pixels for pass-through: the parts a write encodes again, raw in their own pixel type;
// the others are copied from the file chunk for chunk.
struct ExrPixels {
    ExrInfo info;
    // [part][channel]: tightly packed samples over the data window (subsampled grid if sampled);
    // empty for a part that was not kept.
    std::vector<std::vector<std::vector<char>>> raw;
    // Whether a part that takes no new layer may be copied chunk for chunk: false where the
    // file's chunk tables failed checkChunkTables (OpenEXR rebuilds such a table when it reads),
    // and every part was then kept raw to be encoded again. checked: that check was made already.
    bool copyChunks = true;
    bool chunkTablesChecked = false;
};

// Whether a copy writes new layers into part `p` itself: only where its codec is lossless, for
// AO, DO and GI are data, and where it has one level, for a part the layers go into is encoded
// again at level 0 only (elsewhere they go to a part of their own, and the part is copied chunk
// for chunk, every level kept).
bool layersGoInPlace(const ExrPart& p);

// Number of samples of a channel along x / y over a part's data window.
int sampleCount(int lo, int hiExclusive, int sampling);

// Reads pixel data once. `wanted` come back as 1-channel float planes over their part's data
// window (subsampled channels are replicated to full resolution). Every channel of the parts in
// `rawParts` is also kept raw in *out (the parts a copy writes new layers into); of the others
// only the wanted channels are decoded, and *out holds none of theirs.
// Truncated/corrupt data -> Error("'path' is truncated or corrupt: <detail>").
std::vector<Image> readExrChannels(const std::string& path, const ExrInfo& info,
                                   const std::vector<ChannelRef>& wanted, const std::vector<int>& rawParts,
                                   ExrPixels* out);
// The same with every part kept raw (keepAll), or none.
std::vector<Image> readExrChannels(const std::string& path, const ExrInfo& info,
                                   const std::vector<ChannelRef>& wanted, bool keepAll, ExrPixels* out);

struct NewChannel {
    int part = 0;
    std::string name;
    Image plane;                    // 1 channel over that part's data window
    Imf::PixelType type = Imf::HALF;
};

struct StringAttribute {
    int part = 0;
    std::string name, value;
};

// Writes every input part/channel/attribute/compression unchanged plus `add` (a new channel
// with the name of an existing one replaces it) and `attrs`. Tiled mip/rip-mapped parts are
// written as ONE_LEVEL (only level 0 is read). In a multipart file every part gets the first
// part's display window, pixel aspect ratio, chromaticities and time code, the attributes
// OpenEXR requires parts to share. Written to "<out>.tmp-<pid>" and renamed; on
// failure the temp file is removed. Refuses to replace the input unless allowOverwriteInput.
void writeExrWithNewChannels(const std::string& outPath, const ExrPixels& in,
                             const std::vector<NewChannel>& add, bool allowOverwriteInput,
                             const std::vector<StringAttribute>& attrs = {});

// ---- Pieces of writeExrWithNewChannels, for writers that assemble a file part by part ----

// `add` grouped by part of `info` (a part's channels in the order given), each checked to be
// named, once, and a 1-channel plane over its part's data window; `attrs` checked to name a
// part. Errors name outPath.
std::vector<std::vector<const NewChannel*>> newChannelsByPart(const std::string& outPath, const ExrInfo& info,
                                                              const std::vector<NewChannel>& add,
                                                              const std::vector<StringAttribute>& attrs);
// Part p's output header: `part`'s own, less chunkCount, plus `add` (replacing channels of the
// same name) and the attributes of `attrs` for part p; mip/rip-mapped tiles become ONE_LEVEL.
Imf::Header headerWithNewChannels(const ExrPart& part, const std::vector<const NewChannel*>& add,
                                  const std::vector<StringAttribute>& attrs, int p);
// Writes part p of `file` (opened with headerWithNewChannels): `raw` holds the part's own
// channels as readExrChannels keeps them (empty when it has none), `add` the new ones.
void writePartPixels(Imf::MultiPartOutputFile& file, int p, const ExrPart& part,
                     const std::vector<std::vector<char>>& raw, const std::vector<const NewChannel*>& add);
// Calls write("<outPath>.tmp-<pid>") and renames the temp file to outPath; on failure removes it
// and throws FileError(outPath, "cannot write: ..."). Refuses outPath == inputPath unless
// allowOverwriteInput, and a directory that does not exist, before calling write.
void writeFileAtomically(const std::string& outPath, const std::string& inputPath, bool allowOverwriteInput,
                         const std::function<void(const std::string& tmp)>& write);

// DWAA, DWAB, B44, B44A and PXR24 alter values: never used for AO/DO/GI, which are data.
bool isLossy(Imf::Compression c);
// The codec new layers are written with: `c` when it is lossless, else ZIP.
Imf::Compression losslessFor(Imf::Compression c);
// "zip", "dwaa", ... as OpenEXR names them, for --inspect and the report.
std::string compressionName(Imf::Compression c);

// A file with no channels yet, for writeExrWithNewChannels to add the computed layers to:
// one part with `part`'s windows, tiling and attributes (camera, chromaticities, colour
// tags, ...) but not its name, channels, chunk count or cryptomatte manifests (they describe
// channels it will not hold), and compression losslessFor(part's). `info.path` stays the
// input's, so writing it over the input is refused as for a copy.
ExrPixels layersOnlyFile(const ExrInfo& info, int part);

// The name of the part addLayersPart would add to `info`: `base` ("obscura"), made unique.
std::string layersPartName(const ExrInfo& info, const std::string& base = "obscura");
// Appends to `file` a part of its own for new layers (layersOnlyFile of its part `from`,
// named layersPartName) and returns its index. The file becomes multipart, so its other
// parts get the name and type OpenEXR requires of one ("render" when unnamed).
int addLayersPart(ExrPixels& file, int from);
// The same with the part made from part `from` of `info` (the input, for a file of new layers
// only), named layersPartName(file.info, base).
int addLayersPart(ExrPixels& file, const ExrInfo& info, int from, const std::string& base);

// OpenEXR's decode/encode thread pool, used by every file opened afterwards (scanline and
// tiled, single and multipart); n <= 0 means all cores. Used lazily with all cores if never
// called.
void setExrThreads(int n);
// setExrThreads(0) unless a host has set the count: called before a file is opened.
void ensureExrThreads();
// An OpenEXR exception's message on one line, less its leading sentence naming the file (the
// caller's FileError names it).
std::string exrErrorDetail(const std::exception& e);

} // namespace obscura
