#include "ofx_host.h"

#include <dlfcn.h>

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstring>
#include <functional>
#include <limits>
#include <thread>

#include "ofx_host_suites.h"

namespace obscura::ofxhost {

namespace suites {
thread_local RenderContext* tRender = nullptr;
Host* gHostObject = nullptr;
} // namespace suites

namespace {
using namespace suites;

// ---------------------------------------------------------------------------
// Message suite
// ---------------------------------------------------------------------------

// "<type>[ <id>]: <text>" of a printf-style message.
std::string messageLine(const char* type, const char* id, const char* format, va_list ap) {
    char buf[4096];
    std::vsnprintf(buf, sizeof buf, format, ap);
    return std::string(type ? type : "?") + (id && *id ? std::string(" ") + id : "") + ": " + buf;
}

OfxStatus message(void*, const char* type, const char* id, const char* format, ...) {
    va_list ap;
    va_start(ap, format);
    const std::string line = messageLine(type, id, format, ap);
    va_end(ap);
    std::lock_guard<std::mutex> lock(gHostObject->logMutex_);
    gHostObject->messages_.push_back(line);
    return kOfxStatOK;
}
const OfxMessageSuiteV1 kMessageSuite = {message};

// Version 2: a persistent message is logged as "persistent <type>: <text>" and kept until cleared.
OfxStatus setPersistentMessage(void*, const char* type, const char* id, const char* format, ...) {
    va_list ap;
    va_start(ap, format);
    const std::string line = messageLine(type, id, format, ap);
    va_end(ap);
    std::lock_guard<std::mutex> lock(gHostObject->logMutex_);
    gHostObject->persistent_ = line;
    gHostObject->messages_.push_back("persistent " + line);
    return kOfxStatOK;
}
OfxStatus clearPersistentMessage(void*) {
    std::lock_guard<std::mutex> lock(gHostObject->logMutex_);
    gHostObject->persistent_.clear();
    return kOfxStatOK;
}
const OfxMessageSuiteV2 kMessageSuiteV2 = {message, setPersistentMessage, clearPersistentMessage};

const void* fetchSuite(OfxPropertySetHandle, const char* name, int version) {
    const std::string n = name ? name : "";
    {
        std::lock_guard<std::mutex> lock(gHostObject->logMutex_);
        gHostObject->suites_.push_back(n + " v" + std::to_string(version));
    }
    if (n == kOfxMessageSuite && version == 2) return gHostObject->messageSuiteV2 ? &kMessageSuiteV2 : nullptr;
    if (version != 1) return nullptr;
    if (n == kOfxPropertySuite) return &kPropertySuite;
    if (n == kOfxImageEffectSuite) return &kImageEffectSuite;
    if (n == kOfxParameterSuite) return &kParameterSuite;
    if (n == kOfxMessageSuite) return &kMessageSuite;
    return nullptr;
}

// OFX 1.5 colour-management styles in increasing order (none, or anything unknown, is 0).
int styleRank(const std::string& style) {
    const char* order[] = {kOfxImageEffectColourManagementBasic, kOfxImageEffectColourManagementCore,
                           kOfxImageEffectColourManagementFull, kOfxImageEffectColourManagementOCIO};
    for (int i = 0; i < 4; ++i)
        if (style == order[i]) return i + 1;
    return 0;
}

std::string ofxArch() {
#if defined(__x86_64__)
    return "Linux-x86-64";
#elif defined(__aarch64__)
    return "Linux-arm-64";
#else
    return "Linux-x86";
#endif
}

} // namespace

// ---------------------------------------------------------------------------
// Plain data
// ---------------------------------------------------------------------------

int Property::size() const {
    switch (type) {
    case String: return (int)s.size();
    case Double: return (int)d.size();
    case Int: return (int)i.size();
    default: return (int)p.size();
    }
}

namespace {
// Replaces property n with a value of one type.
template <class V>
void assign(PropertySet& set, const std::string& n, Property::Type type, std::vector<V> Property::*field,
            std::vector<V> v) {
    std::lock_guard<std::mutex> lock(set.mutex);
    Property& p = set.props[n];
    p = Property{};
    p.type = type;
    p.*field = std::move(v);
}
} // namespace

void PropertySet::setString(const std::string& n, std::vector<std::string> v) { assign(*this, n, Property::String, &Property::s, std::move(v)); }
void PropertySet::setDouble(const std::string& n, std::vector<double> v) { assign(*this, n, Property::Double, &Property::d, std::move(v)); }
void PropertySet::setInt(const std::string& n, std::vector<int> v) { assign(*this, n, Property::Int, &Property::i, std::move(v)); }
void PropertySet::erase(const std::string& n) {
    std::lock_guard<std::mutex> lock(mutex);
    props.erase(n);
}
void PropertySet::setPointer(const std::string& n, void* v) { assign(*this, n, Property::Pointer, &Property::p, {v}); }
bool PropertySet::has(const std::string& n) const {
    std::lock_guard<std::mutex> lock(mutex);
    return props.count(n) != 0;
}
std::vector<std::string> PropertySet::strings(const std::string& n) const {
    std::lock_guard<std::mutex> lock(mutex);
    auto it = props.find(n);
    return it == props.end() || it->second.type != Property::String ? std::vector<std::string>{} : it->second.s;
}
std::vector<double> PropertySet::doubles(const std::string& n) const {
    std::lock_guard<std::mutex> lock(mutex);
    auto it = props.find(n);
    return it == props.end() || it->second.type != Property::Double ? std::vector<double>{} : it->second.d;
}
std::vector<int> PropertySet::ints(const std::string& n) const {
    std::lock_guard<std::mutex> lock(mutex);
    auto it = props.find(n);
    return it == props.end() || it->second.type != Property::Int ? std::vector<int>{} : it->second.i;
}
std::string PropertySet::string(const std::string& n, int index) const {
    const auto v = strings(n);
    return index < (int)v.size() ? v[index] : std::string();
}
int PropertySet::integer(const std::string& n, int index, int fallback) const {
    const auto v = ints(n);
    return index < (int)v.size() ? v[index] : fallback;
}

HostImage::HostImage(OfxRectI b, int comps, float fill)
    : bounds(b), components(comps), pixels((size_t)(b.x2 - b.x1) * (b.y2 - b.y1) * comps, fill) {}

Param* ParamSet::find(const std::string& name) const {
    for (const auto& p : params)
        if (p->name == name) return p.get();
    return nullptr;
}

Clip* Effect::clip(const std::string& name) const {
    for (const auto& c : clips)
        if (c->name == name) return c.get();
    return nullptr;
}

// ---------------------------------------------------------------------------
// Host
// ---------------------------------------------------------------------------

Host::Host(const std::string& bundlePath) {
    gHostObject = this;
    hostProps_.setString(kOfxPropType, {kOfxTypeImageEffectHost});
    hostProps_.setString(kOfxPropName, {"io.github.obscura.testhost"});
    hostProps_.setString(kOfxPropLabel, {"obscura test host"});
    hostProps_.setInt(kOfxPropAPIVersion, {1, 4});
    hostProps_.setInt(kOfxImageEffectHostPropIsBackground, {1});
    hostProps_.setInt(kOfxImageEffectPropSupportsOverlays, {0});
    hostProps_.setInt(kOfxImageEffectPropSupportsMultiResolution, {1});
    hostProps_.setInt(kOfxImageEffectPropSupportsTiles, {1});
    hostProps_.setInt(kOfxImageEffectPropTemporalClipAccess, {0});
    hostProps_.setString(kOfxImageEffectPropSupportedComponents, {kOfxImageComponentRGBA, kOfxImageComponentAlpha});
    hostProps_.setString(kOfxImageEffectPropSupportedContexts, {kOfxImageEffectContextGeneral, kOfxImageEffectContextFilter});
    hostProps_.setString(kOfxImageEffectPropSupportedPixelDepths, {kOfxBitDepthFloat});
    hostProps_.setInt(kOfxImageEffectPropSupportsMultipleClipDepths, {0});
    hostProps_.setInt(kOfxImageEffectPropSupportsMultipleClipPARs, {0});
    hostProps_.setInt(kOfxImageEffectPropSetableFrameRate, {0});
    hostProps_.setInt(kOfxImageEffectPropSetableFielding, {0});
    ofxHost_.host = hostProps_.handle();
    ofxHost_.fetchSuite = fetchSuite;

    binaryPath_ = bundlePath + "/Contents/" + ofxArch() + "/obscura.ofx";
    library_ = dlopen(binaryPath_.c_str(), RTLD_LAZY | RTLD_LOCAL);
    if (!library_) {
        const char* e = dlerror();
        error_ = std::string("dlopen ") + binaryPath_ + ": " + (e ? e : "?");
        return;
    }
    auto count = reinterpret_cast<OfxGetNumberOfPluginsFn>(dlsym(library_, "OfxGetNumberOfPlugins"));
    auto get = reinterpret_cast<OfxGetPluginFn>(dlsym(library_, "OfxGetPlugin"));
    if (!count || !get) {
        error_ = "the binary does not export OfxGetNumberOfPlugins and OfxGetPlugin";
        return;
    }
    numPlugins_ = count();
    plugin_ = numPlugins_ > 0 ? get(0) : nullptr;
    if (!plugin_) {
        error_ = "OfxGetPlugin(0) returned nothing";
        return;
    }
    if (std::strcmp(plugin_->pluginApi, kOfxImageEffectPluginApi) != 0 || plugin_->apiVersion != 1) {
        error_ = std::string("unexpected plugin API ") + plugin_->pluginApi;
        plugin_ = nullptr;
        return;
    }
    plugin_->setHost(&ofxHost_);
}

Host::~Host() {
    if (plugin_ && loaded_) plugin_->mainEntry(kOfxActionUnload, nullptr, nullptr, nullptr);
    descriptor_.reset();
    if (library_) dlclose(library_);
    if (gHostObject == this) gHostObject = nullptr;
}

OfxStatus Host::action(const char* name, Effect* effect, PropertySet* in, PropertySet* out) {
    if (!plugin_) return kOfxStatErrFatal;
    return plugin_->mainEntry(name, effect ? effect->handle() : nullptr, in ? in->handle() : nullptr,
                              out ? out->handle() : nullptr);
}

OfxStatus Host::load() {
    const OfxStatus st = action(kOfxActionLoad, nullptr, nullptr, nullptr);
    loaded_ = st == kOfxStatOK || st == kOfxStatReplyDefault;
    return st;
}

OfxStatus Host::describe() {
    descriptor_ = std::make_unique<Effect>();
    descriptor_->props.setString(kOfxPropType, {kOfxTypeImageEffect});
    OfxStatus st = action(kOfxActionDescribe, descriptor_.get(), nullptr, nullptr);
    if (st != kOfxStatOK && st != kOfxStatReplyDefault) return st;
    return describeInContext(kOfxImageEffectContextGeneral);
}

OfxStatus Host::describeInContext(const std::string& context) {
    if (!descriptor_) return kOfxStatErrBadHandle;
    PropertySet in;
    in.setString(kOfxImageEffectPropContext, {context});
    return action(kOfxImageEffectActionDescribeInContext, descriptor_.get(), &in, nullptr);
}

void Host::setColourManagementStyle(const std::string& style) {
    if (style.empty()) {
        hostProps_.erase(kOfxImageEffectPropColourManagementStyle);
        hostProps_.erase(kOfxImageEffectPropColourManagementAvailableConfigs);
    } else {
        hostProps_.setString(kOfxImageEffectPropColourManagementStyle, {style});
        hostProps_.setString(kOfxImageEffectPropColourManagementAvailableConfigs, {kOfxConfigIdentifier});
    }
}

std::vector<std::string> Host::fetchedSuites() const {
    std::lock_guard<std::mutex> lock(logMutex_);
    return suites_;
}
std::vector<std::string> Host::messages() const {
    std::lock_guard<std::mutex> lock(logMutex_);
    return messages_;
}

std::string Host::persistentMessage() const {
    std::lock_guard<std::mutex> lock(logMutex_);
    return persistent_;
}

std::unique_ptr<Instance> Host::createInstance(const ProjectSetup& project,
                                               const std::map<std::string, const HostImage*>& inputs,
                                               OfxStatus* status) {
    std::unique_ptr<Instance> inst(new Instance);
    inst->host_ = this;
    inst->outputComponents = project.outputComponents;
    inst->effect_ = std::make_unique<Effect>();
    Effect& e = *inst->effect_;
    e.descriptor = false;
    e.par = project.pixelAspect;
    e.renderScale = project.renderScale;
    e.props = descriptor_->props;
    // The style both sides support (the lower of the two); none from a 1.4 host or plugin.
    const std::string hostStyle = hostProps_.string(kOfxImageEffectPropColourManagementStyle);
    const std::string pluginStyle = descriptor_->props.string(kOfxImageEffectPropColourManagementStyle);
    if (hostStyle.empty()) {
        e.props.erase(kOfxImageEffectPropColourManagementStyle);
    } else {
        const bool pluginLower = styleRank(pluginStyle) < styleRank(hostStyle);
        const std::string style = !pluginLower ? hostStyle : styleRank(pluginStyle) > 0 ? pluginStyle
                                                                                       : kOfxImageEffectColourManagementNone;
        e.props.setString(kOfxImageEffectPropColourManagementStyle, {style});
    }
    e.props.setString(kOfxPropType, {kOfxTypeImageEffectInstance});
    e.props.setString(kOfxImageEffectPropContext, {kOfxImageEffectContextGeneral});
    e.props.setPointer(kOfxPropInstanceData, nullptr);
    e.props.setDouble(kOfxImageEffectPropProjectSize, {project.width * project.pixelAspect, (double)project.height});
    e.props.setDouble(kOfxImageEffectPropProjectOffset, {0.0, 0.0});
    e.props.setDouble(kOfxImageEffectPropProjectExtent, {project.width * project.pixelAspect, (double)project.height});
    e.props.setDouble(kOfxImageEffectPropProjectPixelAspectRatio,
                      {project.projectPar > 0 ? project.projectPar : project.pixelAspect});
    e.props.setDouble(kOfxImageEffectInstancePropEffectDuration, {1.0});
    e.props.setInt(kOfxImageEffectInstancePropSequentialRender, {0});
    e.props.setDouble(kOfxImageEffectPropFrameRate, {24.0});
    e.props.setInt(kOfxPropIsInteractive, {0});
    // Parameters start at their defaults.
    for (const auto& d : descriptor_->params.params) {
        auto p = std::make_unique<Param>();
        p->type = d->type;
        p->name = d->name;
        p->props = d->props;
        p->props.setString(kOfxPropType, {kOfxTypeParameterInstance});
        if (isIntLike(p->type)) p->i = d->props.integer(kOfxParamPropDefault);
        if (p->type == kOfxParamTypeDouble) {
            const auto v = d->props.doubles(kOfxParamPropDefault);
            p->d = v.empty() ? 0.0 : v[0];
        }
        if (p->type == kOfxParamTypeRGB) {
            const auto v = d->props.doubles(kOfxParamPropDefault);
            for (int k = 0; k < 3; ++k) p->rgb[k] = k < (int)v.size() ? v[k] : 0.0;
        }
        if (p->type == kOfxParamTypeString) p->s = d->props.string(kOfxParamPropDefault);
        e.params.params.push_back(std::move(p));
    }
    for (const auto& dc : descriptor_->clips) {
        auto c = std::make_unique<Clip>();
        c->name = dc->name;
        c->effect = &e;
        c->props = dc->props;
        auto it = inputs.find(c->name);
        c->input = it == inputs.end() ? nullptr : it->second;
        const bool isOutput = c->name == kOfxImageEffectOutputClipName;
        const bool conn = isOutput || c->input != nullptr;
        c->props.setInt(kOfxImageClipPropConnected, {conn ? 1 : 0});
        const int comps = isOutput ? inst->outputComponents : c->input ? c->input->components : 4;
        const char* compName = comps == 1 ? kOfxImageComponentAlpha : kOfxImageComponentRGBA;
        c->props.setString(kOfxImageEffectPropComponents, {conn ? compName : kOfxImageComponentNone});
        c->props.setString(kOfxImageClipPropUnmappedComponents, {conn ? compName : kOfxImageComponentNone});
        c->props.setString(kOfxImageEffectPropPixelDepth, {conn ? kOfxBitDepthFloat : kOfxBitDepthNone});
        c->props.setString(kOfxImageClipPropUnmappedPixelDepth, {conn ? kOfxBitDepthFloat : kOfxBitDepthNone});
        c->props.setDouble(kOfxImagePropPixelAspectRatio, {project.pixelAspect});
        c->props.setString(kOfxImageEffectPropPreMultiplication,
                           {comps == 1 || c->name != kOfxImageEffectSimpleSourceClipName ? kOfxImageOpaque
                                                                                         : kOfxImagePreMultiplied});
        c->props.setInt(kOfxImageClipPropContinuousSamples, {0});
        e.clips.push_back(std::move(c));
    }
    const OfxStatus st = action(kOfxActionCreateInstance, &e, nullptr, nullptr);
    if (status) *status = st;
    inst->created_ = st == kOfxStatOK || st == kOfxStatReplyDefault;
    return inst;
}

} // namespace obscura::ofxhost
