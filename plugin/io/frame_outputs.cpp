#include "io/frame_outputs.h"

#include "base/error.h"
#include "core/methods.h"
#include "io/colour.h"
#include "io/exr_append.h"
#include "io/preview.h"
#include "io/stage_timer.h"
#include "io/views.h"

#include <OpenEXR/ImfTileDescription.h>

#include <algorithm>
#include <cmath>
#include <map>

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
// `suffix` ("" or ".VIEW") names the layers in a view (layer.view.channel).
std::vector<std::string> addSsdoLayers(const FrameJob& job, const FramePasses& p, const OperatorOutputs& out,
                                       int outPart, Imf::PixelType type, const std::string& space, const std::string& suffix,
                                       std::vector<NewChannel>& add, std::vector<StringAttribute>& attrs) {
    std::vector<std::string> layers;
    const ColourManager& cm = colourManager();
    auto emit = [&](const std::string& name, Image rgb, const char* units) {
        const std::string layer = name + suffix;
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


// Whether a view's channel names carry the view (layer.view.channel): a view by channel names,
// not a part of its own (`view` attribute).
bool namedInView(const FramePasses& p) { return !p.view.empty() && partView(p.info.parts[p.part]).empty(); }

std::string viewedName(const FramePasses& p, const std::string& name) {
    if (!namedInView(p)) return name;
    const auto at = std::find(p.fileViews.begin(), p.fileViews.end(), p.view);
    return nameInView(name, p.fileViews, (size_t)(at - p.fileViews.begin()));
}

// The part of `target` a view's layers go to: in a copy, the input's part copyLayersPart names
// (an earlier run's, or the depth's own), else a part of their own, one for the views by channel
// names and one per view of a part of its own, which carries that part's `view` attribute
// (layersOnlyFile keeps it).
int destinationPart(const FrameJob& job, const FramePasses& p, ExrPixels& target, std::map<std::string, int>& own) {
    const bool copy = job.write == WriteMode::Copy;
    if (copy) {
        const int into = copyLayersPart(job, p.info, p.part, p.view);
        if (into >= 0) return into;
    }
    const std::string key = namedInView(p) ? "" : p.view;
    if (const auto it = own.find(key); it != own.end()) return it->second;
    int part = 0;
    if (!copy && key.empty() && target.info.parts.empty()) target = layersOnlyFile(p.info, p.part);
    else part = addLayersPart(target, p.info, p.part, key.empty() ? "obscura" : "obscura." + key);
    own[key] = part;
    return part;
}

// "'obscura.left', 'obscura.right'": the parts of their own the views with a part each would
// get; "" when no view processed has a part of its own.
std::string viewPartNames(const FrameJob& job, const ExrInfo& info) {
    std::vector<std::string> views;
    try {
        views = viewsToProcess(job, info);
    } catch (const Error&) {
        return "";  // a --view the file lacks: the run is refused before it writes
    }
    std::string names;
    for (const std::string& v : views)
        for (const ExrPart& part : info.parts)
            if (partView(part) == v) {
                names += (names.empty() ? "'" : ", '") + layersPartName(info, "obscura." + v) + "'";
                break;
            }
    return names;
}

// The first view processed whose depth is in `part` ("" for a file without views), as the
// copy's destination is decided per view.
std::string viewOfPart(const FrameJob& job, const ExrInfo& info, int part) {
    const std::string own = partView(info.parts.at(part));
    if (!own.empty()) return own;
    try {
        const std::vector<std::string> views = viewsToProcess(job, info);
        return views.empty() ? "" : views.front();
    } catch (const Error&) {
        return "";
    }
}

} // namespace

std::string describeWrite(const FrameJob& job, const ExrInfo& info, int part, bool flattened) {
    const Imf::Compression in = info.parts.at(part).header.compression();
    const Imf::Compression out = losslessFor(in);
    std::string codec = compressionName(out);
    if (out != in) codec += " (the input's " + compressionName(in) + " is lossy)";
    // Views with parts of their own get a part each where the layers do not go into the input's.
    const std::string own = viewPartNames(job, info);
    const std::string ownPart = own.empty() ? "a part of their own ('" + layersPartName(info) + "')" : "a part per view (" + own + ")";
    if (job.write == WriteMode::New) return "new: only the new layers" + (own.empty() ? "" : ", in " + ownPart) + ", " + codec;
    if (job.write == WriteMode::Append)
        return "append: the input's parts copied as compressed chunks, the new layers in " + ownPart + ", " + codec;
    const std::string copied = flattened ? "copy: the flattened image plus the new layers" : "copy: the input plus the new layers";
    const int into = flattened ? part : copyLayersPart(job, info, part, viewOfPart(job, info, part));
    if (into < 0) return copied + " in " + ownPart + ", " + codec;
    if (into != part)
        return copied + " in part '" + info.parts[into].name + "', in place of an earlier run's, " +
               compressionName(info.parts[into].header.compression());
    return copied + std::string(own.empty() ? "" : ", each view's in its part") + ", " + codec;
}

// --preview: the display window's part of the frame (overscan is not part of it) of the AO, or
// in a lit run (`ssdo`: ssdo, or hbao with --bounce) of the relit layer when it is written, else
// of ssdo's DO or hbao's GI layer, converted from the working space to sRGB's primaries where
// the config has them. AO is a fraction, shown as it is; light has no fixed scale (a sunlit
// floor is far above 1), so it is exposed automatically unless --preview-exposure says how.
// Returns the report's plan line.
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

namespace {
// A channel the input already holds under a new channel's name (an earlier run's AO): copy
// replaces it where the new layer goes into the part holding it, else the output holds both, as
// append always does. Either is what was asked, but not what a user re-running on an output
// expects without a word.
void warnOfEarlierLayers(const FrameJob& job, const ExrInfo& input, const std::vector<NewChannel>& add,
                         const std::map<int, std::string>& partViews, FrameReport& report) {
    if (job.write == WriteMode::New) return;
    std::vector<std::string> held;  // each once, with its part's view where views have parts (names repeat)
    bool kept = false;  // some earlier channel stays beside its new namesake
    for (const NewChannel& c : add) {
        // Where views have parts, a name clashes within its view only.
        const auto own = partViews.find(c.part);
        const std::string into = own != partViews.end()                ? own->second
                                 : c.part < (int)input.parts.size() ? partView(input.parts[c.part])
                                                                     : "";
        for (size_t part = 0; part < input.parts.size(); ++part) {
            const std::string view = partView(input.parts[part]);
            if (view != into || input.parts[part].findChannel(c.name) < 0) continue;
            const std::string label = c.name + (view.empty() ? "" : " (view " + view + ")");
            if (std::find(held.begin(), held.end(), label) == held.end()) held.push_back(label);
            kept = kept || job.write == WriteMode::Append || (int)part != c.part;
        }
    }
    if (held.empty()) return;
    std::string names;
    for (size_t i = 0; i < std::min<size_t>(3, held.size()); ++i) names += (i ? ", " : "") + held[i];
    report.warnings.push_back("the input already holds " + names + (held.size() > 3 ? ", ..." : "") +
                              (kept ? "; the output holds both, in different parts"
                                    : "; the output's new layers replace them") +
                              " (--out-layer ao=NAME, gi=NAME, ... names the new layers apart)");
}

// Copy encodes again the parts that take new layers (every part where the chunk tables failed their
// check: !copyChunks), and a tiled part only at its level 0: a mip-mapped (texture) input would
// lose its lower levels without a word. Parts copied chunk for chunk keep every level.
void warnOfLostLevels(const FrameJob& job, const ExrInfo& input, bool copyChunks, const std::vector<NewChannel>& add,
                      FrameReport& report) {
    if (job.write != WriteMode::Copy) return;
    for (size_t part = 0; part < input.parts.size(); ++part) {
        const Imf::Header& h = input.parts[part].header;
        const bool levels = h.hasTileDescription() && h.tileDescription().mode != Imf::ONE_LEVEL;
        const bool touched = std::any_of(add.begin(), add.end(), [&](const NewChannel& c) { return c.part == (int)part; });
        if (levels && (touched || !copyChunks))
            report.warnings.push_back("part " + std::to_string(part) + " of the input is mip-mapped; copy writes its "
                                      "level 0 only, beside the new layers (--write append keeps every level)");
    }
}

// Half float's largest value is 65504: light above it (a strong --light, sky or map) would be
// written as +inf, which no compositing operation survives. It is written as 65504, and the run
// says which layers were clipped, with the view of a part of its own (`partView`: the layers'
// names repeat in each).
void clipToHalf(std::vector<NewChannel>& add, const std::map<int, std::string>& partView, FrameReport& report) {
    constexpr float kHalfMax = 65504.0f;
    std::map<std::string, long long> clipped;  // layer: values clipped
    for (NewChannel& c : add) {
        if (c.type != Imf::HALF) continue;
        for (float& v : c.plane.pixels)
            if (std::abs(v) > kHalfMax) {  // an infinity too (the light's NaNs are gone by now)
                v = std::copysign(kHalfMax, v);
                const auto view = partView.find(c.part);
                ++clipped[c.name.substr(0, c.name.rfind('.')) +
                          (view == partView.end() ? "" : " (view " + view->second + ")")];
            }
    }
    for (const auto& [layer, values] : clipped)
        report.warnings.push_back(layer + ": " + std::to_string(values) + " value(s) above half float's largest (65504) "
                                  "are written as 65504; --out-type float keeps them");
}
} // namespace

void writeFrameOutputs(const FrameJob& job, std::vector<ViewResult>& views, FrameReport& report,
                       std::vector<NewChannel> extra) {
    const bool copy = job.write == WriteMode::Copy;
    const bool ssdo = readsColour(job);  // the light layers: ssdo's, or hbao's bounce
    const bool append = job.write == WriteMode::Append;
    StageTimer timer{append ? nullptr : &report.stages, "write"};  // append times its own stages
    const Imf::PixelType type = job.aoFloat ? Imf::FLOAT : Imf::HALF;
    const FramePasses& first = views.front().passes;
    // Copy: into the depth's part of the input (the first view's read kept every part taking
    // layers raw; the others are copied chunk for chunk), or a part of their own when that
    // part's codec is lossy (AO, DO and GI are data).
    // New and append: into a fresh file, which append adds to the input's parts.
    ExrPixels fresh;
    fresh.info.path = first.info.path;
    ExrPixels& target = copy ? views.front().passes.raw : fresh;
    std::map<std::string, int> ownParts;
    report.writeDescription = describeWrite(job, first.info, first.part, !first.carried.empty());
    // AO is data (raw); DO, GI and relit are written in the file's colour space where obscura
    // knows its primaries, so the chromaticities every part shares (an appended part's
    // included) describe them.
    const ColourManager& cm = colourManager();
    const std::string space = cm.layerSpace(report.inputColourSpace.empty()
                                                ? cm.detectColourSpace(first.info.parts[first.part].header, job.colourSpace).name
                                                : report.inputColourSpace);
    std::vector<NewChannel> add;
    std::vector<StringAttribute> attrs;
    std::map<int, std::pair<std::vector<std::string>, std::vector<std::string>>> tags;  // part: colour layers, data channels
    int firstPart = -1;
    std::map<int, std::string> partView;  // a view in a part of its own: its channels' names repeat
    for (ViewResult& v : views) {
        const FramePasses& p = v.passes;
        const int outPart = destinationPart(job, p, target, ownParts);
        if (firstPart < 0) firstPart = outPart;
        if (!namedInView(p) && !p.view.empty()) partView[outPart] = p.view;
        NewChannel ao{outPart, viewedName(p, aoChannelName(job.aoLayer)), v.out.ao, type};
        if (report.aoChannel.empty()) report.aoChannel = ao.name;
        tags[outPart].second.push_back(ao.name);
        add.push_back(std::move(ao));
        if (!ssdo) continue;
        const std::string suffix = namedInView(p) ? "." + p.view : "";
        for (std::string& layer : addSsdoLayers(job, p, v.out, outPart, type, space, suffix, add, attrs))
            tags[outPart].first.push_back(std::move(layer));
    }
    for (NewChannel& c : extra) {  // deep elements' per-element AO, data as the AO is
        c.part = firstPart;
        tags[firstPart].second.push_back(c.name);
        add.push_back(std::move(c));
    }
    FrameReport recorded;  // what --resume compares: the settings, the recipe and the files read
    recorded.sources = report.sources;
    for (const auto& [part, names] : tags) {
        attrs.push_back({part, "obscura/version", OBSCURA_VERSION_STRING});
        attrs.push_back({part, "obscura/settings", frameReportJson(job, recorded)});
        std::string note;
        for (StringAttribute& a : cm.tagOutputPart(part, space, names.first, names.second, &note)) attrs.push_back(std::move(a));
        if (!note.empty() && std::find(report.plan.begin(), report.plan.end(), note) == report.plan.end())
            report.plan.push_back(note);
    }
    for (const NewChannel& c : add) {
        report.written.push_back(c.name);
        report.writtenViews.push_back(partView.count(c.part) ? partView[c.part] : "");
    }
    clipToHalf(add, partView, report);
    warnOfEarlierLayers(job, first.info, add, partView, report);
    warnOfLostLevels(job, first.info, target.copyChunks, add, report);
    if (copy)  // deep elements: the flattened image is the copy's input
        for (NewChannel& c : views.front().passes.carried) add.push_back({firstPart, c.name, std::move(c.plane), c.type});
    if (append)
        writeAppended(job.output, first.info, target, add, attrs, job.inPlace, &report.stages);
    else
        writeExrWithNewChannels(job.output, target, add, job.inPlace, attrs);
}

} // namespace obscura
