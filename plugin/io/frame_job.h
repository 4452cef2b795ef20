// One frame, file to file: read the passes a request needs, resolve the camera,
// run the operator, write a copy of the input with the new layers. Shared by the
// CLI and the Python module; the operator itself never sees a file.
#pragma once
#include "base/cancel.h"
#include "base/error.h"
#include "core/metrics.h"
#include "core/operator.h"
#include "io/atomic_files.h"
#include "io/camera_sources.h"
#include "io/deep_file.h"
#include "io/depth_encoding.h"
#include "io/exr_file.h"
#include "io/layers.h"
#include "io/source_files.h"

#include <array>
#include <map>
#include <new>
#include <optional>
#include <string>
#include <vector>

namespace obscura {

// What to do with pixels no renderer should write: NaN/negative depth, zero or
// non-finite normals on surface pixels.
enum class BadPixelPolicy { Error, Skip };

// Copy: the input with the new layers added (every channel decoded and re-encoded).
// New: a file holding only the new layers; the input's other channels are never decoded.
// Append: the input's parts copied as compressed chunks (never decoded), the new layers in a
// part of their own (io/exr_append.h).
enum class WriteMode { Copy, New, Append };
bool parse(const std::string& s, WriteMode& out);
const char* toString(WriteMode m);

struct FrameJob {
    std::string input, output;
    // A deep EXR whose surfaces hbao adds as occluders (docs/deep.md); `input` is then the
    // flat file beside it that gives the passes and receives the AO.
    std::string deepInput;
    // Deep elements with no flat file (docs/deep.md): merged, they are the input (`input` is the
    // first). A single deep input with no deepInput is one too (io/deep_job.h).
    std::vector<std::string> deepElements;
    bool perElementAo = false;            // also an AO per element, for its own visible surface
    bool inPlace = false;                 // allow output == input
    std::string preset = "auto";
    std::map<Role, std::string> layerOverrides;
    std::optional<DepthEncoding> depthEncoding;        // --depth: overrides the preset's planar or radial
    std::optional<std::array<double, 2>> depthRange;   // --depth-range A,B: normalized's 0 and 1
    std::optional<NormalSpace> normalSpace;  // Depth: reconstruct them even where a normal pass exists
    std::optional<float> skyDepth;        // overrides the preset's sky threshold
    CameraRequest camera;                 // sidecarPath "" = NAME.json next to the input, if any
    Settings settings;
    std::string aoLayer = "obscura.AO";   // layer name; the channel is "<layer>.Y"
    bool aoFloat = false;                 // --out-type float (default half)
    std::string previewPath;              // PNG of the AO (a lit run: relit when written, else DO or GI), optional
    std::optional<float> previewExposure; // stops before the preview's encoding; unset: ssdo's automatic, AO's 0
    std::string referenceLayer;           // compare against this layer, optional
    BadPixelPolicy badPixels = BadPixelPolicy::Error;
    WriteMode write = WriteMode::Copy;
    long long maxPixels = kDefaultMaxPixels;  // per window of the input and of the environment map
    // --view: the views of a multi-view input to process (io/views.h); empty: every view with a depth.
    std::vector<std::string> views;

    // ---- method ssdo: what to write and where its light comes from ----
    bool writeDirectional = true;         // DO (ssdo always computes it; this only decides the layer)
    bool writeIndirect = false;           // GI: runs the bounce pass
    bool writeRelit = false;              // albedo x (DO + GI) / pi
    bool relitWithDirect = false;         // ... plus the render's own direct diffuse light
    bool timesAlbedo = false;             // DO/GI written as albedo x E / pi (outgoing radiance) instead of E
    std::string doLayer = "obscura.DO", giLayer = "obscura.GI", relitLayer = "obscura.relit";
    std::string bounceSource = "direct-diffuse";  // "direct-diffuse", "beauty" or a layer name
    std::string envPath;                  // lat-long EXR/HDR/...; "" = constant sky (settings.skyRadiance)
    std::optional<bool> zUp;              // world up axis for the environment; default from the preset
    std::string colourSpace;              // --colorspace: the input's colour passes; "" = from the header
    std::string envColourSpace;           // --env-colorspace; "" = from the map's metadata
};

// The passes of one frame in memory, as the operator wants them.
struct FramePasses {
    ExrInfo info;
    LayerPlan plan;
    int part = 0;                         // the part holding depth
    bool normalsFromDepth = false;        // no normal pass read: the operator reconstructs them
    bool depthFromPosition = false;       // no depth layer: the depth comes from the position pass and the camera
    DepthEncoding depthEncoding = DepthEncoding::Planar;  // how the file stored it; `depth` is decoded
    DepthStatistics depthStats;           // of the depth as stored (from the position pass: as computed)
    Box2i display, data;
    double pixelAspect = 1.0;
    Image depth, normal, position, reference;  // position/reference empty when not read
    Image radiance, albedo, directDiffuse;      // SSDO inputs, read only when the request needs them
    ExrPixels raw;                        // a copy's pass-through: the parts taking new layers, raw (exr_file.h)
    std::vector<NewChannel> carried;      // deep elements: the flattened image, written with the new layers
    // A multi-view input: the view these passes are of ("" for the whole file) and the file's views.
    std::string view;
    std::vector<std::string> fileViews;
};

struct FrameReport {
    std::string aoChannel;                // the first view's, when several are written
    std::vector<std::string> views;       // the views processed; empty for a file without views
    std::vector<std::string> written;     // every channel added to the output
    std::vector<std::string> writtenViews;  // each one's view where the views have parts of their own (names repeat), else ""
    std::string writeDescription;         // how the output was written (mode, codec)
    std::vector<std::string> plan;        // what ran, in order (passes read, kernels, maps loaded)
    std::string inputColourSpace;         // of the colour passes, when any was read
    Camera camera;
    DepthKind depthKind = DepthKind::Planar;       // as the operator read it
    DepthEncoding depthEncoding = DepthEncoding::Planar;  // as the file stored it
    NormalSpace normalSpace = NormalSpace::World;
    float skyDepth = 1e9f;
    OperatorStats stats;
    long long nonUnitNormalPixels = 0;    // normalised on the fly; counted for the report
    // Deep input (docs/deep.md): layers used, and what the reader skipped, sorted or merged.
    int deepElements = 0;                 // deep elements merged (0: none, or --flat)
    int deepLayers = 0;
    long long deepEmptyPixels = 0, deepDroppedSamples = 0, deepUnsortedPixels = 0, deepTruncatedPixels = 0;
    std::vector<FileStamp> sources;       // the files read, as they were when the frame began (--resume)
    std::vector<StageTiming> stages;      // read, camera, compute, write (append: copy, append), preview
    std::optional<ErrorMetrics> reference;
    std::vector<std::string> warnings;
};

// Whether the normals come from the depth: --normals depth (Python normals='depth'), or the file
// has no normal layer.
bool normalsFromDepth(const FrameJob& job, const LayerPlan& plan);
// "normals: reconstructed from depth (no normal layer)", or the layer used and its space: the
// line the report's plan, --inspect and the log give.
std::string normalsSourceLine(const FrameJob& job, const LayerPlan& plan);

// --bounce and Python's bounce=True: relight the frame. One rule for both hosts: the bounce asks
// for the GI layer and the relit image, albedo x (DO + GI) / pi, since relighting is what the one
// bounce is for; relit needs an albedo pass. Naming an output (--out-layer gi=NAME) asks for that
// layer alone.
void requestBounce(FrameJob& job);
// What is wrong with `name` as an output layer's name, "" for nothing: it must be dot-separated
// words (no empty one: "a..b", ".x") of at most 200 characters, so that with a view and a
// channel its channels' names stay within OpenEXR's 255 (it cuts longer ones, merging views).
std::string outLayerProblem(const std::string& name);
// Whether the job reads colour passes and writes light: ssdo always, hbao with the bounce.
bool readsColour(const FrameJob& job);
// Whether the job's deep layers need their colour: a method that reads them lights with a bounce.
bool readsDeepColour(const FrameJob& job);
// The warning that deep input's layers go unused with linear falloff, where the method reads them.
void warnIfDeepLayersIgnored(const FrameJob& job, FrameReport& report);
// The report's line on the deep layers' colour (`coloured`: the deep input has R, G and B).
void noteDeepColour(bool coloured, FrameReport& report);

// The colour passes an SSDO request reads (R, G, B, in the part that holds each); empty for HBAO.
struct SsdoReads {
    std::vector<ChannelRef> radiance;       // the bounce source, when GI or relit is asked for
    std::vector<ChannelRef> albedo;         // sender albedo (direct-diffuse source), relit, --times-albedo
    std::vector<ChannelRef> directDiffuse;  // --relit-direct
    bool senderAlbedo = false;               // senders radiate source x albedo
};
SsdoReads planSsdoReads(const FrameJob& job, const FramePasses& passes);

// The views of a multi-view input the job processes, in the file's order: job.views (each checked
// to be in the file: an Error names the file's views), else every view whose channels give a
// depth (or a position pass). Empty when the file has no views, or none with a depth: the file
// then runs as one image.
std::vector<std::string> viewsToProcess(const FrameJob& job, const ExrInfo& info);
// The layers of `view` of the file ("": the whole file), channel names as the file spells them.
LayerPlan planViewLayers(const FrameJob& job, const ExrInfo& info, const std::string& view);

// Reads headers, plans layers and reads the pixels `job` needs, plus every channel of the parts in
// `rawParts` raw (a copy's parts that take new layers).
// alwaysReadPosition: read the position pass whenever it covers the depth's pixels, not only
// when the camera must be fitted from it (Python's read_passes returns it). `headers`: the
// input's, when the caller has read them and refused deep parts as readExrInfo would (else they
// are read here).
FramePasses loadFramePasses(const FrameJob& job, const std::vector<int>& rawParts, std::vector<StageTiming>* stages = nullptr,
                            bool alwaysReadPosition = false, const ExrInfo* headers = nullptr);
// Single-channel planes [first, first + channels) interleaved into one image.
Image interleavePlanes(const std::vector<Image>& planes, size_t first, int channels);
// The camera this job would use for these passes.
Camera resolveFrameCamera(const FrameJob& job, const FramePasses& passes);
// The job's deep file (--flat), with the channel names of the flat passes' preset; errors name the
// file. `windowsOnly`: checked and its windows read, no sample (readDeepLayerWindows).
DeepLayers readJobDeepLayers(const FrameJob& job, const FramePasses& passes, bool windowsOnly = false);
// Runs f(); an error that names no file (a camera, flag or operator problem, a library's
// exception) is re-thrown as a FileError naming `input`, so every failure reads 'FILE': what.
// A host's stop (Cancelled) passes through.
template <class F>
auto blameInput(const std::string& input, F&& f) -> decltype(f()) {
    try {
        return f();
    } catch (const FileError&) {
        throw;
    } catch (const UsageError&) {
        throw;  // the request's, not the file's
    } catch (const Cancelled&) {
        throw;  // the host stopped the run: nothing failed
    } catch (const std::bad_alloc&) {
        throw FileError(input, "out of memory");
    } catch (const std::exception& e) {
        throw FileError(input, firstLineOf(e.what()));
    }
}
// The full pipeline. Throws obscura::Error (one line) on any failure; nothing is left on disk then.
FrameReport runFrameJob(const FrameJob& job);
// --report: settings, camera, timings and statistics as JSON text.
std::string frameReportJson(const FrameJob& job, const FrameReport& report);
// A failed frame's report instead: the frame, its files and the one-line error.
std::string frameFailureJson(const FrameJob& job, int frame, const std::string& error);
// How `job` writes its output for this input: the mode, and the codec of the new layers.
// `flattened`: the input is deep elements, whose flattened image (FramePasses::carried) a copy
// writes in place of the input's channels.
std::string describeWrite(const FrameJob& job, const ExrInfo& info, int part, bool flattened = false);
// "<layer>.Y", or the name itself when it already ends in a single-letter channel.
std::string aoChannelName(const std::string& layer);
// The input part a copy writes a view's new layers into: the part an earlier run left them in,
// under the names this run writes, so that a run again (--in-place on a farm) replaces them
// rather than adding a part each time; else the depth's part `depthPart`; -1 where neither can
// take them (a lossy or mip-mapped part, layersGoInPlace): they get a part of their own.
int copyLayersPart(const FrameJob& job, const ExrInfo& info, int depthPart, const std::string& view);

} // namespace obscura
