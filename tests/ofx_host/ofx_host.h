// A small OpenFX host for tests: loads a built .ofx.bundle with dlopen, exactly as a
// host would, implements the host side of the suites obscura's plugin fetches
// (property, image effect, parameter, message), and drives the actions.
//
// Strict where it matters: typed properties (a get of the wrong type or a missing
// property fails), handles checked by magic, every image fetch recorded with its
// region so a test can hold the plugin to the regions of interest it declared, and
// every image counted so leaks show up. Like a host built on the official HostSupport
// library it keeps canonical coordinates (RoD, RoI, fetch regions) apart from pixels at
// the render scale (render windows, image bounds) for any pixel aspect ratio, delivers
// exactly the region of interest a tile asked for, re-runs clip preferences when a slave
// parameter changes, refuses a clip preference it did not define (HostSupport's fixed specs),
// and can act as an OFX 1.5 colour-managed host.
#pragma once
#include "ofx/ofx_api.h"

#include <atomic>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <vector>

namespace obscura::ofxhost {

// ---------------------------------------------------------------------------
// Properties
// ---------------------------------------------------------------------------

struct Property {
    enum Type { String, Double, Int, Pointer } type = String;
    std::vector<std::string> s;
    std::vector<double> d;
    std::vector<int> i;
    std::vector<void*> p;
    int size() const;
};

struct PropertySet {
    unsigned magic = 0x0f5e7001u;
    mutable std::mutex mutex;
    std::map<std::string, Property> props;
    // Closed: the plugin may set only what the host defined (kOfxStatErrUnknown otherwise), as
    // the official HostSupport library builds an action's out-arguments from fixed property specs.
    bool closed = false;

    PropertySet() = default;
    PropertySet(const PropertySet& o) : props(o.copy()) {}
    PropertySet& operator=(const PropertySet& o) {
        if (this != &o) {
            auto c = o.copy();
            std::lock_guard<std::mutex> lock(mutex);
            props = std::move(c);
        }
        return *this;
    }
    std::map<std::string, Property> copy() const {
        std::lock_guard<std::mutex> lock(mutex);
        return props;
    }
    OfxPropertySetHandle handle() { return reinterpret_cast<OfxPropertySetHandle>(this); }

    // Host-side conveniences (no type checks against an existing property: they define it).
    void setString(const std::string& name, std::vector<std::string> v);
    void setDouble(const std::string& name, std::vector<double> v);
    void setInt(const std::string& name, std::vector<int> v);
    void setPointer(const std::string& name, void* v);
    void erase(const std::string& name);
    bool has(const std::string& name) const;
    std::vector<std::string> strings(const std::string& name) const;
    std::vector<double> doubles(const std::string& name) const;
    std::vector<int> ints(const std::string& name) const;
    std::string string(const std::string& name, int index = 0) const;
    int integer(const std::string& name, int index = 0, int fallback = 0) const;
};

// ---------------------------------------------------------------------------
// Images: float pixels over a rectangle in OFX pixel coordinates (y up).
// ---------------------------------------------------------------------------

struct HostImage {
    OfxRectI bounds{0, 0, 0, 0};
    int components = 4;             // 4 (RGBA) or 1 (Alpha)
    std::vector<float> pixels;      // row-major, row 0 = bounds.y1 (bottom row)

    HostImage() = default;
    HostImage(OfxRectI b, int comps, float fill = 0.0f);
    int width() const { return bounds.x2 - bounds.x1; }
    int height() const { return bounds.y2 - bounds.y1; }
    float* at(int x, int y) { return pixels.data() + ((size_t)(y - bounds.y1) * width() + (x - bounds.x1)) * components; }
    const float* at(int x, int y) const {
        return pixels.data() + ((size_t)(y - bounds.y1) * width() + (x - bounds.x1)) * components;
    }
};

// ---------------------------------------------------------------------------
// Parameters, clips, effects
// ---------------------------------------------------------------------------

struct Param {
    unsigned magic = 0x0f5e7002u;
    std::string type, name;
    PropertySet props;
    int i = 0;
    double d = 0;
    double rgb[3] = {0, 0, 0};  // kOfxParamTypeRGB
    std::string s;
};

struct ParamSet {
    unsigned magic = 0x0f5e7003u;
    PropertySet props;
    std::vector<std::unique_ptr<Param>> params;  // in definition order
    Param* find(const std::string& name) const;
};

struct Effect;

struct ImageFetch {
    std::string clip;
    OfxRectD region{0, 0, 0, 0};  // as requested (canonical); the RoD when the plugin passed none
    bool regionGiven = false;
};

struct Clip {
    unsigned magic = 0x0f5e7004u;
    std::string name;
    PropertySet props;
    Effect* effect = nullptr;
    const HostImage* input = nullptr;   // an input clip's pixels (nullptr: not connected)
};

struct Effect {
    unsigned magic = 0x0f5e7005u;
    PropertySet props;
    ParamSet params;
    std::vector<std::unique_ptr<Clip>> clips;  // in definition order
    bool descriptor = true;
    double par = 1, renderScale = 1;  // the project's pixel aspect ratio; the render scale
    std::atomic<long long> liveImages{0};  // images of this instance not yet released
    Clip* clip(const std::string& name) const;
    OfxImageEffectHandle handle() { return reinterpret_cast<OfxImageEffectHandle>(this); }
};

// ---------------------------------------------------------------------------
// The host
// ---------------------------------------------------------------------------

struct ProjectSetup {
    int width = 0, height = 0;  // project size in full-resolution pixels (extent = size * (PAR, 1))
    double pixelAspect = 1.0;
    double renderScale = 1.0;   // input images are pixels at this scale; so are render windows
    int outputComponents = 4;   // the Output clip: 4 (RGBA) or 1 (Alpha), until clip preferences set it
    // The project's PAR as the effect reports it (0: pixelAspect). HostSupport gives the clips the
    // inputs' PAR, which need not be the project's (an anamorphic render in a square-pixel project).
    double projectPar = 0;
};

class Host;

// One effect instance, driven action by action.
class Instance {
public:
    ~Instance();
    Effect& effect() { return *effect_; }

    OfxStatus setInt(const std::string& param, int v);
    OfxStatus setDouble(const std::string& param, double v);
    OfxStatus setString(const std::string& param, const std::string& v);
    OfxStatus setRGB(const std::string& param, double r, double g, double b);

    // kOfxImageEffectActionGetClipPreferences; the out args as the plugin left them. The
    // Output clip takes the premultiplication, and a colour-managed host then runs
    // GetOutputColourspace; both happen again whenever a slave parameter changes.
    OfxStatus clipPreferences(PropertySet& out);
    int clipPreferencesRuns = 0;
    // OFX 1.5 kOfxImageEffectActionGetOutputColourspace; on OK the Output clip's colourspace.
    OfxStatus outputColourspace(const std::vector<std::string>& preferred, std::string& space);
    OfxStatus regionOfDefinition(OfxRectD& rod);
    // Regions of interest for an output region (canonical), per input clip name.
    OfxStatus regionsOfInterest(const OfxRectD& region, std::map<std::string, OfxRectD>& rois);
    // kOfxStatOK and the clip's name if the plugin says the window is an identity.
    OfxStatus isIdentity(const OfxRectI& window, std::string& clipName);
    // Renders `window` (pixels) into `frame` (which must cover it). Rows of the Output image
    // are laid out top-down (negative rowBytes) when `negativeRowBytes`.
    // With `rois` and Host::exactRegions, an input image covers no more than the clip's RoI.
    OfxStatus render(const OfxRectI& window, HostImage& frame, std::vector<ImageFetch>* fetches = nullptr,
                     const std::map<std::string, OfxRectD>* rois = nullptr);

    // The whole RoD rendered in tiles of tileW x tileH pixels (0 = one tile), on `threads` threads
    // at once. For each tile, checks that every image the plugin fetched lies inside the
    // region of interest it declared for that tile; violations are appended to `problems`.
    HostImage renderFrame(int tileW, int tileH, int threads, std::vector<std::string>& problems);

    int outputComponents = 4;

private:
    friend class Host;
    Instance() = default;
    Host* host_ = nullptr;
    std::unique_ptr<Effect> effect_;
    bool created_ = false;
};

class Host {
public:
    // Loads <bundle>/Contents/<arch>/obscura.ofx (arch: Linux-x86-64 on x86_64).
    explicit Host(const std::string& bundlePath);
    ~Host();
    Host(const Host&) = delete;
    Host& operator=(const Host&) = delete;

    const std::string& error() const { return error_; }     // why loading failed, "" if it did not
    int numberOfPlugins() const { return numPlugins_; }
    OfxPlugin* plugin() const { return plugin_; }
    std::string binaryPath() const { return binaryPath_; }

    OfxStatus load();        // kOfxActionLoad
    OfxStatus describe();    // kOfxActionDescribe + DescribeInContext(General)
    OfxStatus describeInContext(const std::string& context);  // again, in any context
    // An OFX 1.5 host offering this colour-management style; "" (the default): a 1.4 host.
    // Set before describe().
    void setColourManagementStyle(const std::string& style);
    Effect& descriptor() { return *descriptor_; }

    // Clip name -> pixels for each connected input; the others stay disconnected.
    std::unique_ptr<Instance> createInstance(const ProjectSetup& project,
                                             const std::map<std::string, const HostImage*>& inputs, OfxStatus* status);

    OfxStatus action(const char* name, Effect* effect, PropertySet* in, PropertySet* out);

    std::vector<std::string> fetchedSuites() const;
    // Every message posted, transient ("<type>: <text>") or persistent ("persistent <type>: <text>").
    std::vector<std::string> messages() const;
    // The persistent message the node shows now ("<type>: <text>"), "" when none or cleared.
    std::string persistentMessage() const;
    long long liveImages() const { return liveImages_.load(); }
    bool negativeRowBytes = true;  // lay fetched input images out top-down
    bool exactRegions = true;      // input images cover only what the tile's RoI asked for
    // kOfxStatFailed for an input image with nothing in the region asked for, or for a clip with
    // no image at that time: what the specification lets a host answer ("assume black").
    bool failEmptyFetch = false;
    bool messageSuiteV2 = true;    // offer version 2 of the message suite (persistent messages)
    int abortFromCall = 0;         // the effect suite's abort answers 1 from this call on (0: never)

    // Host internals used by the suite implementations.
    std::atomic<long long> liveImages_{0};
    std::atomic<int> abortCalls_{0};
    std::set<std::thread::id> abortThreads_;  // the threads that called abort (under logMutex_)
    mutable std::mutex logMutex_;
    std::vector<std::string> suites_, messages_;
    std::string persistent_;
    std::set<const PropertySet*> images_;  // images handed to the plugin, not yet released
    PropertySet hostProps_;

private:
    void* library_ = nullptr;
    std::string binaryPath_, error_;
    int numPlugins_ = 0;
    OfxPlugin* plugin_ = nullptr;
    OfxHost ofxHost_{};
    std::unique_ptr<Effect> descriptor_;
    bool loaded_ = false;
};

} // namespace obscura::ofxhost
