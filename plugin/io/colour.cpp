#include "io/colour.h"

#include "base/error.h"
#include "cpu/parallel.h"
#include "io/preview.h"

#include <OpenColorIO/OpenColorIO.h>
#include <OpenEXR/ImfStandardAttributes.h>
#include <OpenEXR/ImfStringAttribute.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <dlfcn.h>
#include <filesystem>
#include <functional>
#include <mutex>
#include <sstream>
#include <system_error>
#include <thread>

namespace OCIO = OCIO_NAMESPACE;

namespace obscura {
namespace {

std::string firstLine(const std::string& s) { return firstLineOf(s, "unknown OpenColorIO error"); }

// "ACES - ACEScg" -> "acesacescg": lower case, letters and digits only, so spellings
// differing in case, spaces, '-', '_', '.', '(' compare equal.
std::string squash(const std::string& s) {
    std::string r;
    for (unsigned char c : s)
        if (std::isalnum(c)) r += static_cast<char>(std::tolower(c));
    return r;
}

// Colour spaces obscura knows by their primaries and by the names other software gives
// them. `names` are tried against the config (first found wins); `spellings` are
// squash()ed forms of what files carry in oiio:ColorSpace / colorInteropID.
struct KnownSpace {
    const char* label;  // for messages: "Rec.709", "AP1", ...
    bool hasPrimaries;  // linear with these primaries (matched against `chromaticities`)
    float rx, ry, gx, gy, bx, by, wx, wy;
    std::vector<const char*> names;
    std::vector<const char*> spellings;
};

const std::vector<KnownSpace>& knownSpaces() {
    static const std::vector<KnownSpace> k = {
        {"Rec.709", true, 0.64f, 0.33f, 0.30f, 0.60f, 0.15f, 0.06f, 0.3127f, 0.3290f,
         {"lin_rec709", "Linear Rec.709 (sRGB)", "Utility - Linear - sRGB", "Utility - Linear - Rec.709",
          "lin_srgb", "Linear", "linear"},
         {"linrec709", "linear", "scenelinear", "linsrgb", "linearsrgb", "srgblinear", "linearrec709",
          "rec709linear", "linearrec709srgb", "linrec709srgb", "linrec709scene", "utilitylinearsrgb",
          "utilitylinearrec709", "scenelinearrec709srgb", "scenelinearrec709"}},
        {"AP1", true, 0.713f, 0.293f, 0.165f, 0.830f, 0.128f, 0.044f, 0.32168f, 0.33767f,
         {"ACEScg", "ACES - ACEScg", "lin_ap1"},
         {"acescg", "linap1", "acesacescg", "linap1scene", "acescglinear", "linearap1"}},
        {"AP0", true, 0.7347f, 0.2653f, 0.0f, 1.0f, 0.0001f, -0.0770f, 0.32168f, 0.33767f,
         {"ACES2065-1", "ACES - ACES2065-1", "lin_ap0"},
         {"aces20651", "linap0", "aces", "acesaces20651", "linap0scene", "aces2065", "linearap0"}},
        {"Rec.2020", true, 0.708f, 0.292f, 0.170f, 0.797f, 0.131f, 0.046f, 0.3127f, 0.3290f,
         {"lin_rec2020", "Linear Rec.2020", "Utility - Linear - Rec.2020"},
         {"linrec2020", "linearrec2020", "rec2020linear", "utilitylinearrec2020", "linrec2020scene"}},
        {"P3-D65", true, 0.680f, 0.320f, 0.265f, 0.690f, 0.150f, 0.060f, 0.3127f, 0.3290f,
         {"lin_p3d65", "Linear P3-D65", "Utility - Linear - P3-D65"},
         {"linp3d65", "linearp3d65", "p3d65linear", "utilitylinearp3d65", "linp3d65scene"}},
        {"sRGB-encoded", false, 0, 0, 0, 0, 0, 0, 0, 0,
         {"srgb_display", "sRGB - Display", "sRGB - Texture", "Utility - sRGB - Texture", "srgb_tx", "sRGB"},
         {"srgb", "srgbdisplay", "srgbtexture", "utilitysrgbtexture", "srgbtx", "srgbrec709scene",
          "srgbrec709display", "srgbencodedrec709srgb"}},
        {"data", false, 0, 0, 0, 0, 0, 0, 0, 0,
         {"raw", "Raw", "Utility - Raw", "Non-Color"},
         {"raw", "data", "noncolor", "noncolour", "utilityraw", "none"}},
    };
    return k;
}

Imf::Chromaticities chromaticities(const KnownSpace& k) {
    return Imf::Chromaticities(Imath::V2f(k.rx, k.ry), Imath::V2f(k.gx, k.gy), Imath::V2f(k.bx, k.by),
                               Imath::V2f(k.wx, k.wy));
}

bool near(const Imath::V2f& a, float x, float y) {
    constexpr float tol = 0.002f;
    return std::fabs(a.x - x) <= tol && std::fabs(a.y - y) <= tol;
}

bool matches(const Imf::Chromaticities& c, const KnownSpace& k) {
    return k.hasPrimaries && near(c.red, k.rx, k.ry) && near(c.green, k.gx, k.gy) &&
           near(c.blue, k.bx, k.by) && near(c.white, k.wx, k.wy);
}

std::string describe(const Imf::Chromaticities& c) {
    char buf[200];
    std::snprintf(buf, sizeof buf, "R %.4g,%.4g G %.4g,%.4g B %.4g,%.4g W %.4g,%.4g", c.red.x, c.red.y,
                  c.green.x, c.green.y, c.blue.x, c.blue.y, c.white.x, c.white.y);
    return buf;
}

std::string chromaticitiesString(const Imf::Chromaticities& c) {
    char buf[200];
    std::snprintf(buf, sizeof buf, "%.5g %.5g %.5g %.5g %.5g %.5g %.5g %.5g", c.red.x, c.red.y, c.green.x,
                  c.green.y, c.blue.x, c.blue.y, c.white.x, c.white.y);
    return buf;
}

std::string stringAttribute(const Imf::Header& h, const char* name) {
    if (const auto* a = h.findTypedAttribute<Imf::StringAttribute>(name)) return a->value();
    return {};
}

// Directory of the binary holding this code: the obscura executable, the Python module or the
// OpenFX plugin inside its bundle (not the host application that loaded it); "" if unknown.
std::filesystem::path moduleDir() {
    Dl_info info{};
    if (!dladdr(reinterpret_cast<void*>(&moduleDir), &info) || !info.dli_fname) return {};
    std::error_code ec;
    const std::filesystem::path p = std::filesystem::canonical(info.dli_fname, ec);
    return ec ? std::filesystem::path() : p.parent_path();
}

} // namespace

ColourMetadata colourMetadata(const Imf::Header& header) {
    ColourMetadata m;
    m.colorInteropID = stringAttribute(header, "colorInteropID");
    m.oiioColorSpace = stringAttribute(header, "oiio:ColorSpace");
    if (Imf::hasChromaticities(header)) m.chromaticities = Imf::chromaticities(header);
    return m;
}

struct ColourManager::Impl {
    OCIO::ConstConfigRcPtr config;
    std::string path, working, data;

    // Optimised CPU processors, by "from\nto" (OpenColorIO caches the processors
    // themselves, not these). LOSSLESS: the default level (VERY_GOOD) uses fast
    // approximations of pow/log/exp, which would break 1e-5 round trips through the sRGB
    // curve.
    mutable std::mutex mutex;
    mutable std::vector<std::pair<std::string, OCIO::ConstCPUProcessorRcPtr>> cpu;

    Impl(const std::string& configPath, const std::string& origin) : path(configPath) {
        const std::string what = "cannot load the OpenColorIO config" + (origin.empty() ? "" : " (" + origin + ")");
        try {
            config = OCIO::Config::CreateFromFile(path.c_str());
        } catch (const std::exception& e) {
            throw FileError(path, what + ": " + firstLine(e.what()));
        }
        auto sceneLinear = config->getColorSpace(OCIO::ROLE_SCENE_LINEAR);
        if (!sceneLinear) throw FileError(path, what + ": it has no scene_linear role (the working space)");
        working = sceneLinear->getName();
        auto dataSpace = config->getColorSpace(OCIO::ROLE_DATA);
        data = dataSpace ? dataSpace->getName() : "raw";
    }

    OCIO::ConstCPUProcessorRcPtr cached(const std::string& key,
                                        const std::function<OCIO::ConstProcessorRcPtr()>& make) const {
        std::lock_guard<std::mutex> lock(mutex);
        for (auto& entry : cpu)
            if (entry.first == key) return entry.second;
        OCIO::ConstCPUProcessorRcPtr p;
        try {
            p = make()->getOptimizedCPUProcessor(OCIO::OPTIMIZATION_LOSSLESS);
        } catch (const OCIO::Exception& e) {
            throw FileError(path, "OpenColorIO: " + firstLine(e.what()));
        }
        cpu.emplace_back(key, p);
        return p;
    }

    // The config's space for a known family (first of its names the config has), "" if none.
    std::string find(const KnownSpace& k) const {
        for (const char* n : k.names)
            if (auto cs = config->getColorSpace(n)) return cs->getName();
        return {};
    }
};

std::string ColourManager::shippedConfigPath() {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::path dir = moduleDir();
    // bin/ -> share/obscura (an install); Contents/<arch>/ -> Contents/Resources (the OFX bundle).
    if (!dir.empty())
        for (const fs::path& installed : {dir / ".." / "share" / "obscura" / "ocio" / "config.ocio",
                                         dir / ".." / "Resources" / "ocio" / "config.ocio"})
            if (fs::is_regular_file(installed, ec)) return fs::weakly_canonical(installed, ec).string();
#ifdef OBSCURA_DEFAULT_OCIO_CONFIG
    if (fs::is_regular_file(OBSCURA_DEFAULT_OCIO_CONFIG, ec)) return OBSCURA_DEFAULT_OCIO_CONFIG;
#endif
    return {};
}

std::string colourConfigPath(std::string* origin) {
    std::string ignored;
    if (!origin) origin = &ignored;
    const char* env = std::getenv("OCIO");
    if (env && *env) {
        *origin = "from $OCIO";
        return env;
    }
    *origin = "shipped with obscura";
    const std::string shipped = ColourManager::shippedConfigPath();
    if (shipped.empty()) {
#ifdef OBSCURA_DEFAULT_OCIO_CONFIG
        throw FileError(OBSCURA_DEFAULT_OCIO_CONFIG, "cannot load the OpenColorIO config: $OCIO is not set and "
                                                     "the shipped config does not exist");
#else
        throw Error("cannot load OpenColorIO config: $OCIO is not set and no shipped config was found");
#endif
    }
    return shipped;
}

ColourManager::ColourManager() {
    std::string origin;
    const std::string path = colourConfigPath(&origin);
    impl_ = std::make_unique<Impl>(path, origin);
}

ColourManager::ColourManager(const std::string& configPath) : impl_(std::make_unique<Impl>(configPath, "")) {}

ColourManager::~ColourManager() = default;

const std::string& ColourManager::configPath() const { return impl_->path; }
const std::string& ColourManager::workingSpace() const { return impl_->working; }
const std::string& ColourManager::dataSpace() const { return impl_->data; }

std::string ColourManager::resolve(const std::string& name) const {
    if (name.empty()) return {};
    // The config's own names, aliases and roles first: a config may mean something else by "Linear".
    if (auto cs = impl_->config->getColorSpace(name.c_str())) return cs->getName();
    const std::string key = squash(name);
    if (key.empty()) return {};
    for (const KnownSpace& k : knownSpaces()) {
        for (const char* n : k.names)
            if (squash(n) == key) return impl_->find(k);
        for (const char* s : k.spellings)
            if (key == s) return impl_->find(k);
    }
    // Last: the config's spaces compared squashed ("lin rec709" == "lin_rec709").
    const OCIO::Config& c = *impl_->config;
    for (int i = 0; i < c.getNumColorSpaces(OCIO::SEARCH_REFERENCE_SPACE_ALL, OCIO::COLORSPACE_ALL); ++i) {
        const char* n = c.getColorSpaceNameByIndex(OCIO::SEARCH_REFERENCE_SPACE_ALL, OCIO::COLORSPACE_ALL, i);
        if (squash(n) == key) return n;
    }
    return {};
}

std::string ColourManager::require(const std::string& name, const std::string& what) const {
    std::string r = resolve(name);
    if (!r.empty()) return r;
    std::string known;
    const OCIO::Config& c = *impl_->config;
    for (int i = 0; i < c.getNumColorSpaces(); ++i) known += std::string(i ? ", " : "") + c.getColorSpaceNameByIndex(i);
    throw Error("unknown colour space '" + name + "'" + (what.empty() ? "" : " for " + what) + " in " +
                impl_->path + " (known: " + known + ")");
}

bool ColourManager::isData(const std::string& space) const {
    auto cs = impl_->config->getColorSpace(resolve(space).c_str());
    return cs && cs->isData();
}

std::optional<Imf::Chromaticities> ColourManager::chromaticitiesOf(const std::string& space) const {
    const std::string name = resolve(space);
    if (name.empty()) return std::nullopt;
    for (const KnownSpace& k : knownSpaces())
        if (k.hasPrimaries && impl_->find(k) == name) return chromaticities(k);
    return std::nullopt;
}

ColourSpaceGuess ColourManager::detectColourSpace(const Imf::Header& header, const std::string& override) const {
    return detectColourSpace(colourMetadata(header), override);
}

ColourSpaceGuess ColourManager::detectColourSpace(const ColourMetadata& meta, const std::string& override,
                                                  const std::string& overrideFlag) const {
    ColourSpaceGuess g;
    if (!override.empty()) {
        g.name = require(override, overrideFlag);
        g.source = overrideFlag;
        return g;
    }
    std::vector<std::string> ignored;
    const std::pair<const char*, const std::string*> strings[] = {{"colorInteropID", &meta.colorInteropID},
                                                                 {"oiio:ColorSpace", &meta.oiioColorSpace}};
    for (const auto& [attr, value] : strings) {
        if (value->empty()) continue;
        // "Linear" says only that the values are linear, not in which primaries (and
        // OpenImageIO reports it for every float file without colour metadata): the
        // chromaticities, when present, are the better witness.
        if (squash(*value) == "linear" && meta.chromaticities) continue;
        std::string name = resolve(*value);
        if (!name.empty()) {
            g.name = name;
            g.source = attr;
            if (!ignored.empty()) g.warning = ignored.front();
            return g;
        }
        ignored.push_back(std::string(attr) + " '" + *value + "' names no colour space of " + impl_->path);
    }
    if (meta.chromaticities) {
        for (const KnownSpace& k : knownSpaces()) {
            if (!matches(*meta.chromaticities, k)) continue;
            const std::string name = impl_->find(k);
            if (name.empty()) {
                ignored.push_back(std::string("chromaticities are ") + k.label + " but " + impl_->path +
                                  " has no linear " + k.label + " colour space");
                break;
            }
            g.name = name;
            g.source = std::string("chromaticities (") + k.label + ")";
            if (!ignored.empty()) g.warning = ignored.front();
            return g;
        }
        if (ignored.empty() || ignored.back().rfind("chromaticities", 0) != 0)
            ignored.push_back("chromaticities (" + describe(*meta.chromaticities) + ") match no known colour space");
    }
    // OpenEXR: no chromaticities attribute means Rec.709 primaries, D65.
    const std::string rec709 = impl_->find(knownSpaces().front());
    g.name = rec709.empty() ? impl_->working : rec709;
    g.source = "default";
    std::string why = ignored.empty() ? std::string("no colour-space metadata (chromaticities, oiio:ColorSpace, colorInteropID)")
                                      : ignored.front();
    for (std::size_t i = 1; i < ignored.size(); ++i) why += "; " + ignored[i];
    g.warning = why + "; assuming " + g.name + " (Rec.709 primaries, scene-linear); use --colorspace to say otherwise";
    return g;
}

void ColourManager::convert(Image& img, const std::string& from, const std::string& to) const {
    convert(img.view(), from, to);
}

namespace {
// Rows [y0, y1) of `plane` through `cpu`; positive strides as one packed image desc.
void applyRows(const OCIO::CPUProcessor& cpu, const MutablePlane& plane, int y0, int y1) {
    if (plane.xStride > 0 && plane.yStride > 0) {
        OCIO::PackedImageDesc desc(plane.at(0, y0), plane.width, y1 - y0, OCIO::CHANNEL_ORDERING_RGB,
                                   OCIO::BIT_DEPTH_F32, sizeof(float),
                                   static_cast<std::ptrdiff_t>(sizeof(float)) * plane.xStride,
                                   static_cast<std::ptrdiff_t>(sizeof(float)) * plane.yStride);
        cpu.apply(desc);
        return;
    }
    for (int y = y0; y < y1; ++y)
        for (int x = 0; x < plane.width; ++x) cpu.applyRGB(plane.at(x, y));
}

std::atomic<int> g_colourThreads{0};

void applyImage(const OCIO::CPUProcessor& cpu, const MutablePlane& plane) {
    const long long pixels = static_cast<long long>(plane.width) * plane.height;
    unsigned n = static_cast<unsigned>(cpu::resolveThreads(g_colourThreads.load()));
    n = static_cast<unsigned>(std::min<long long>(n, std::max(1LL, pixels / (256 * 1024))));
    n = std::min<unsigned>(n, static_cast<unsigned>(plane.height));
    if (n <= 1) {
        applyRows(cpu, plane, 0, plane.height);
        return;
    }
    std::vector<std::thread> threads;
    std::vector<std::string> errors(n);
    for (unsigned t = 0; t < n; ++t) {
        const int y0 = static_cast<int>(static_cast<long long>(plane.height) * t / n);
        const int y1 = static_cast<int>(static_cast<long long>(plane.height) * (t + 1) / n);
        threads.emplace_back([&, y0, y1, t] {
            try {
                applyRows(cpu, plane, y0, y1);
            } catch (const std::exception& e) {
                errors[t] = e.what();
            }
        });
    }
    for (auto& th : threads) th.join();
    for (const auto& e : errors)
        if (!e.empty()) throw Error("OpenColorIO: " + firstLine(e));
}
} // namespace

void setColourThreads(int n) { g_colourThreads = std::max(0, n); }

void ColourManager::convert(const MutablePlane& plane, const std::string& from, const std::string& to) const {
    const std::string src = require(from, "the input"), dst = require(to, "the output");
    if (src == dst || !plane.valid()) return;
    if (plane.channels < 3)
        throw Error("cannot convert " + src + " to " + dst + ": the image has " + std::to_string(plane.channels) +
                    " channel(s), RGB needs 3");
    auto cpu = impl_->cached(src + "\n" + dst, [&] { return impl_->config->getProcessor(src.c_str(), dst.c_str()); });
    if (cpu->isNoOp()) return;
    try {
        applyImage(*cpu, plane);
    } catch (const OCIO::Exception& e) {
        throw Error("OpenColorIO: " + firstLine(e.what()));
    }
}

std::string ColourManager::layerSpace(const std::string& inputSpace) const {
    const std::string input = resolve(inputSpace);
    return !input.empty() && chromaticitiesOf(input) ? input : impl_->working;
}

std::vector<StringAttribute> ColourManager::tagOutputPart(int part, const std::string& layerSpace,
                                                          const std::vector<std::string>& colourNames,
                                                          const std::vector<std::string>& dataNames,
                                                          std::string* note) const {
    std::vector<StringAttribute> attrs;
    const std::string space = require(layerSpace, "the new colour layers");
    const std::optional<Imf::Chromaticities> chroma = chromaticitiesOf(space);
    for (const std::string& ch : colourNames) {
        attrs.push_back({part, "obscura/" + ch + "/colorspace", space});
        if (chroma) attrs.push_back({part, "obscura/" + ch + "/chromaticities", chromaticitiesString(*chroma)});
    }
    for (const std::string& ch : dataNames) attrs.push_back({part, "obscura/" + ch + "/colorspace", impl_->data});
    if (note) {
        *note = colourNames.empty() ? ""
                : chroma           ? "colour layers written in " + space + ", the file's space"
                                   : "colour layers written in the working space " + space +
                                         " (the file's space has no known primaries), tagged per layer";
    }
    return attrs;
}

std::string ColourManager::defaultDisplay() const {
    const char* d = impl_->config->getDefaultDisplay();
    if (!d || !*d) throw FileError(impl_->path, "the OpenColorIO config defines no display");
    return d;
}

std::string ColourManager::defaultView(const std::string& display) const {
    const char* v = impl_->config->getDefaultView(display.c_str());
    if (!v || !*v) throw FileError(impl_->path, "the OpenColorIO config has no view for display '" + display + "'");
    return v;
}

void ColourManager::applyDisplayView(Image& img, const std::string& displayIn, const std::string& viewIn) const {
    const std::string display = displayIn.empty() ? defaultDisplay() : displayIn;
    const std::string view = viewIn.empty() ? defaultView(display) : viewIn;
    if (img.channels < 3)
        throw Error("cannot apply display " + display + " / view " + view + ": the image has " +
                    std::to_string(img.channels) + " channel(s), RGB needs 3");
    auto cpu = impl_->cached("display\n" + display + "\n" + view, [&] {
        auto t = OCIO::DisplayViewTransform::Create();
        t->setSrc(impl_->working.c_str());
        t->setDisplay(display.c_str());
        t->setView(view.c_str());
        return impl_->config->getProcessor(t);
    });
    if (cpu->isNoOp()) return;
    try {
        applyImage(*cpu, img.view());
    } catch (const OCIO::Exception& e) {
        throw Error("OpenColorIO: " + firstLine(e.what()));
    }
}

void ColourManager::writeDisplayPreview(const std::string& path, const Image& rgbWorking, const std::string& displayIn,
                                        const std::string& viewIn) const {
    if (rgbWorking.empty() || rgbWorking.channels < 3)
        throw FileError(path, "cannot write the preview: it needs an RGB image");
    const std::string display = displayIn.empty() ? defaultDisplay() : displayIn;
    const std::string view = viewIn.empty() ? defaultView(display) : viewIn;
    Image rgb(rgbWorking.width, rgbWorking.height, 3);
    for (std::size_t i = 0, n = (std::size_t)rgb.width * rgb.height; i < n; ++i)
        for (int c = 0; c < 3; ++c) rgb.pixels[i * 3 + c] = rgbWorking.pixels[i * rgbWorking.channels + c];
    applyDisplayView(rgb, display, view);

    // Tag the PNG with the view's colour space, as "sRGB" when it is the sRGB encoding
    // (the name every reader knows).
    std::string tag;
    if (const char* cs = impl_->config->getDisplayViewColorSpaceName(display.c_str(), view.c_str())) {
        const std::string name = resolve(cs);
        tag = name.empty() ? cs : name;
        if (isData(tag))
            tag.clear();
        else
            for (const KnownSpace& k : knownSpaces())
                if (std::string(k.label) == "sRGB-encoded" && impl_->find(k) == tag) tag = "sRGB";
    }
    writeEncodedPreviewPng(path, rgb, tag);
}

const ColourManager& colourManager() {
    static std::mutex mutex;
    static std::unique_ptr<ColourManager> manager;
    std::lock_guard<std::mutex> lock(mutex);
    if (!manager) manager = std::make_unique<ColourManager>();  // throws: retried on the next call
    return *manager;
}

std::string detectColourSpace(const Imf::Header& header, const std::string& override, std::string* warning) {
    ColourSpaceGuess g = colourManager().detectColourSpace(header, override);
    if (warning) *warning = g.warning;
    return g.name;
}

void toWorkingSpace(Image& rgb, const std::string& fromSpace) { colourManager().toWorkingSpace(rgb, fromSpace); }
void fromWorkingSpace(Image& rgb, const std::string& toSpace) { colourManager().fromWorkingSpace(rgb, toSpace); }
void writeDisplayPreview(const std::string& path, const Image& rgbWorking) {
    colourManager().writeDisplayPreview(path, rgbWorking);
}

} // namespace obscura
