#include "io/frame_outputs.h"

#include "base/error.h"
#include "core/methods.h"
#include "io/colour.h"
#include "io/exr_append.h"
#include "io/preview.h"
#include "io/stage_timer.h"

namespace obscura {

namespace {

// Three channels <layer>.R/G/B of an RGB image.
void addRgbLayer(std::vector<NewChannel>& add, int part, const std::string& layer, const Image& rgb, Imf::PixelType type) {
    for (int c = 0; c < 3; ++c) {
        NewChannel ch;
        ch.part = part;
        ch.name = layer + "." + "RGB"[c];
        ch.plane = Image(rgb.width, rgb.height, 1);
        for (size_t i = 0; i < ch.plane.pixels.size(); ++i) ch.plane.pixels[i] = rgb.pixels[3 * i + c];
        ch.type = type;
        add.push_back(std::move(ch));
    }
}

// DO or GI as its layer holds it: irradiance E, or with --times-albedo albedo x E / pi.
Image ssdoLayerImage(const FrameJob& job, const FramePasses& p, const Image& e) {
    Image r = e;
    if (job.timesAlbedo)
        for (size_t i = 0; i < r.pixels.size(); ++i) r.pixels[i] *= p.albedo.pixels[i] * (float)(1.0 / M_PI);
    return r;
}

// albedo x (DO + GI) / pi, plus the render's direct diffuse light with --relit-direct; HBAO's
// bounce has no DO (albedo x GI / pi: the bounce alone, or added to the direct light).
Image relitImage(const FrameJob& job, const FramePasses& p, const OperatorOutputs& out) {
    Image relit = out.directional.empty() ? Image(out.indirect.width, out.indirect.height, 3, 0.0f) : out.directional;
    for (size_t i = 0; i < relit.pixels.size(); ++i) {
        relit.pixels[i] = p.albedo.pixels[i] * (relit.pixels[i] + out.indirect.pixels[i]) * (float)(1.0 / M_PI);
        if (job.relitWithDirect) relit.pixels[i] += p.albedo.pixels[i] * p.directDiffuse.pixels[i];
    }
    return relit;
}

// DO, GI and relit as the request asks. Irradiance E by default; --times-albedo writes
// albedo x E / pi, the outgoing radiance of the diffuse receiver. relit = albedo (DO + GI) / pi
// (+ albedo x direct diffuse), the units a renderer's beauty uses for diffuse light.
// Each layer is converted from the working space into `space` (ColourManager::layerSpace).
std::vector<std::string> addSsdoLayers(const FrameJob& job, const FramePasses& p, const OperatorOutputs& out,
                                       int outPart, Imf::PixelType type, const std::string& space,
                                       std::vector<NewChannel>& add, std::vector<StringAttribute>& attrs) {
    std::vector<std::string> layers;
    const ColourManager& cm = colourManager();
    auto emit = [&](const std::string& layer, Image rgb, const char* units) {
        cm.convert(rgb, cm.workingSpace(), space);
        addRgbLayer(add, outPart, layer, rgb, type);
        layers.push_back(layer);
        if (units) attrs.push_back({outPart, "obscura/" + layer + "/units", units});
    };
    const char* units = job.timesAlbedo ? "radiance (albedo E / pi)" : "irradiance E";
    if (job.writeDirectional && !out.directional.empty()) emit(job.doLayer, ssdoLayerImage(job, p, out.directional), units);
    if (job.writeIndirect) emit(job.giLayer, ssdoLayerImage(job, p, out.indirect), units);
    if (job.writeRelit) emit(job.relitLayer, relitImage(job, p, out), nullptr);
    return layers;
}

// The part of a data-window plane inside the display window (all of it when they do not meet).
Image displayPart(const Image& img, const FramePasses& p) {
    const Box2i crop = intersect(p.data, p.display).empty() ? p.data : intersect(p.data, p.display);
    Image part(crop.width(), crop.height(), img.channels);
    for (int y = 0; y < crop.height(); ++y)
        for (int x = 0; x < crop.width(); ++x)
            for (int c = 0; c < img.channels; ++c)
                part.at(x, y)[c] = img.at(x + crop.x0 - p.data.x0, y + crop.y0 - p.data.y0)[c];
    return part;
}


} // namespace

std::string describeWrite(const FrameJob& job, const ExrInfo& info, int part) {
    const Imf::Compression in = info.parts.at(part).header.compression();
    const Imf::Compression out = losslessFor(in);
    std::string codec = compressionName(out);
    if (out != in) codec += " (the input's " + compressionName(in) + " is lossy)";
    if (job.write == WriteMode::New) return "new: only the new layers, " + codec;
    if (job.write == WriteMode::Append)
        return "append: the input's parts copied as compressed chunks, the new layers in a part of their own ('" +
               layersPartName(info) + "'), " + codec;
    if (out != in) return "copy: the input plus the new layers in a part of their own ('" + layersPartName(info) + "'), " + codec;
    return "copy: the input plus the new layers, " + codec;
}

// --preview: the display window's part of the frame (overscan is not part of it) of the AO, or
// for ssdo of the relit layer when it is written, else of the DO layer, converted from the
// working space to sRGB's primaries where the config has them. AO is a fraction, shown as it
// is; light has no fixed scale (a sunlit floor is far above 1), so it is exposed automatically
// unless --preview-exposure says how. Returns the report's plan line.
std::string writeFramePreview(const FrameJob& job, const FramePasses& p, const OperatorOutputs& out, bool ssdo) {
    const Image& light = out.directional.empty() ? out.indirect : out.directional; // hbao's bounce: GI
    const Image colour = !ssdo ? Image() : job.writeRelit ? relitImage(job, p, out) : ssdoLayerImage(job, p, light);
    Image view = displayPart(ssdo ? colour : out.ao, p);
    if (ssdo) {
        const ColourManager& cm = colourManager();
        if (const std::string rec709 = cm.resolve("lin_rec709"); !rec709.empty()) cm.convert(view, cm.workingSpace(), rec709);
    }
    const float ev = job.previewExposure ? *job.previewExposure : ssdo ? autoExposureEv(view) : 0.0f;
    writePreviewPng(job.previewPath, view, ev);
    char line[160];
    std::snprintf(line, sizeof line, "preview: %s, exposure %+.2f EV%s", !ssdo ? "AO" : job.writeRelit ? "relit" : out.directional.empty() ? "GI" : "DO",
                  ev, job.previewExposure || !ssdo ? "" : " (auto: the 99th percentile of the largest channel at 0.8)");
    return line;
}

void writeFrameOutputs(const FrameJob& job, FramePasses& p, const OperatorOutputs& out, FrameReport& report) {
    const bool copy = job.write == WriteMode::Copy;
    const bool ssdo = readsColour(job);  // the light layers: ssdo's, or hbao's bounce
    const bool append = job.write == WriteMode::Append;
    {
        StageTimer timer{append ? nullptr : &report.stages, "write"};  // append times its own stages
        const Imf::PixelType type = job.aoFloat ? Imf::FLOAT : Imf::HALF;
        // Copy: into the depth's part of the input, or a part of their own when that part's
        // codec is lossy (AO, DO and GI are data). New and append: into the one part of a fresh
        // file, which append adds to the input's parts.
        ExrPixels fresh;
        if (!copy) fresh = layersOnlyFile(p.info, p.part);
        ExrPixels& target = copy ? p.raw : fresh;
        const bool ownPart = !copy || isLossy(p.info.parts[p.part].header.compression());
        const int outPart = !copy ? 0 : ownPart ? addLayersPart(target, p.part) : p.part;
        report.writeDescription = describeWrite(job, p.info, p.part);
        std::vector<NewChannel> add(1);
        add[0].part = outPart;
        add[0].name = report.aoChannel;
        add[0].plane = out.ao;
        add[0].type = type;
        std::vector<StringAttribute> attrs = {
            {outPart, "obscura/version", OBSCURA_VERSION_STRING},
            {outPart, "obscura/settings", frameReportJson(job, FrameReport{})},
        };
        // AO is data (raw); DO, GI and relit are written in the file's colour space where
        // obscura knows its primaries, so the chromaticities every part shares (an appended
        // part's included) describe them.
        const ColourManager& cm = colourManager();
        const std::string space = cm.layerSpace(report.inputColourSpace.empty()
                                                    ? cm.detectColourSpace(p.info.parts[p.part].header, job.colourSpace).name
                                                    : report.inputColourSpace);
        std::vector<std::string> colourLayers;
        if (ssdo) colourLayers = addSsdoLayers(job, p, out, outPart, type, space, add, attrs);
        std::string note;
        for (StringAttribute& a : cm.tagOutputPart(outPart, space, colourLayers, {report.aoChannel}, &note))
            attrs.push_back(std::move(a));
        if (!note.empty()) report.plan.push_back(note);
        for (const NewChannel& c : add) report.written.push_back(c.name);
        if (append)
            writeAppended(job.output, p.info, target, add, attrs, job.inPlace, &report.stages);
        else
            writeExrWithNewChannels(job.output, target, add, job.inPlace, attrs);
    }
}

} // namespace obscura
