#include "io/exr_append.h"

#include "base/error.h"
#include "io/exr_chunk_table.h"

#include <OpenEXR/ImfMultiPartInputFile.h>
#include <OpenEXR/ImfMultiPartOutputFile.h>
#include <OpenEXR/ImfPartType.h>

#include <chrono>
#include <cstring>

namespace obscura {
namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// Part p of the input as copied: unchanged but for the name and type a multipart file needs.
Imf::Header copiedHeader(const Imf::Header& in) {
    Imf::Header h = in;
    if (!h.hasName()) h.setName("render");
    if (!h.hasType()) h.setType(h.hasTileDescription() ? Imf::TILEDIMAGE : Imf::SCANLINEIMAGE);
    return h;
}

// The new part's header: `own` with `first`'s shared attributes (OpenEXR refuses a file whose
// parts disagree on them; a time code or chromaticities `first` lacks is dropped).
Imf::Header appendedHeader(const Imf::Header& own, const Imf::Header& first, const std::string& name, bool tiled) {
    Imf::Header h;
    for (auto it = own.begin(); it != own.end(); ++it)  // copied one by one: see headerWithout in exr_file.cpp
        if (std::strcmp(it.name(), "timeCode") != 0 && std::strcmp(it.name(), "chromaticities") != 0)
            h.insert(it.name(), it.attribute());
    for (const char* shared : {"timeCode", "chromaticities"})
        if (first.find(shared) != first.end()) h.insert(shared, first[shared]);
    h.displayWindow() = first.displayWindow();
    h.pixelAspectRatio() = first.pixelAspectRatio();
    h.setName(name);
    if (!h.hasType()) h.setType(tiled ? Imf::TILEDIMAGE : Imf::SCANLINEIMAGE);
    return h;
}

} // namespace

void writeAppended(const std::string& outPath, const ExrInfo& input, const ExrPixels& layers,
                   const std::vector<NewChannel>& add, const std::vector<StringAttribute>& attrs,
                   bool allowOverwriteInput, std::vector<StageTiming>* stages) {
    if (input.parts.empty() || layers.info.parts.empty())
        throw Error("internal: appending to " + input.path + " needs its parts and a part of new layers");
    const auto byPart = newChannelsByPart(outPath, layers.info, add, attrs);
    const auto t0 = Clock::now();
    checkChunkTables(input.path, input);
    double copySeconds = secondsSince(t0);
    writeFileAtomically(outPath, input.path, allowOverwriteInput, [&](const std::string& tmp) {
        Imf::MultiPartInputFile in(input.path.c_str());
        const int n = in.parts();
        if (n != (int)input.parts.size()) throw FileError(input.path, "changed while being read");
        std::vector<Imf::Header> headers;
        for (int p = 0; p < n; ++p) headers.push_back(copiedHeader(in.header(p)));
        const int added = (int)layers.info.parts.size();
        for (int p = 0; p < added; ++p) {
            const ExrPart& own = layers.info.parts[p];
            const std::string name = layersPartName(input, own.name.empty() ? "obscura" : own.name);
            headers.push_back(appendedHeader(headerWithNewChannels(own, byPart[p], attrs, p), in.header(0), name, own.tiled));
        }
        Imf::MultiPartOutputFile out(tmp.c_str(), headers.data(), n + added);
        const auto c0 = Clock::now();
        for (int p = 0; p < n; ++p) copyPartChunks(in, out, p);
        copySeconds += secondsSince(c0);
        for (int p = 0; p < added; ++p) writePartPixels(out, n + p, layers.info.parts[p], {}, byPart[p]);
    });
    if (stages) {
        stages->push_back({"copy", copySeconds});
        stages->push_back({"append", secondsSince(t0) - copySeconds});
    }
}

} // namespace obscura
