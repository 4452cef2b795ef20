// The test host's Instance: actions on one effect instance and tiled, threaded renders.
#include "ofx_host_suites.h"

#include <dlfcn.h>

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstring>
#include <functional>
#include <limits>
#include <thread>


namespace obscura::ofxhost {

using namespace suites;

// ---------------------------------------------------------------------------
// Instance
// ---------------------------------------------------------------------------

Instance::~Instance() {
    if (created_) host_->action(kOfxActionDestroyInstance, effect_.get(), nullptr, nullptr);
}

namespace {
// Sets a parameter, tells the plugin, and re-runs clip preferences if the plugin made the
// parameter a slave of them (kOfxImageEffectPropClipPreferencesSlaveParam).
OfxStatus setAndNotify(Host& host, Instance& inst, const std::string& name, const std::function<OfxStatus(Param&)>& set) {
    Effect& e = inst.effect();
    Param* p = e.params.find(name);
    if (!p) return kOfxStatErrUnknown;
    const OfxStatus st = set(*p);
    if (st != kOfxStatOK) return st;
    PropertySet in;
    in.setString(kOfxPropType, {kOfxTypeParameter});
    in.setString(kOfxPropName, {name});
    in.setString(kOfxPropChangeReason, {kOfxChangeUserEdited});
    in.setDouble(kOfxPropTime, {0.0});
    in.setDouble(kOfxImageEffectPropRenderScale, {e.renderScale, e.renderScale});
    const OfxStatus r = host.action(kOfxActionInstanceChanged, &e, &in, nullptr);
    if (r != kOfxStatOK && r != kOfxStatReplyDefault) return r;
    const std::vector<std::string> slaves = e.props.strings(kOfxImageEffectPropClipPreferencesSlaveParam);
    if (std::find(slaves.begin(), slaves.end(), name) != slaves.end()) {
        PropertySet prefs;
        return inst.clipPreferences(prefs);
    }
    return kOfxStatOK;
}
} // namespace

OfxStatus Instance::setInt(const std::string& name, int v) {
    return setAndNotify(*host_, *this, name, [&](Param& p) {
        if (!isIntLike(p.type)) return kOfxStatErrValue;
        p.i = v;
        return kOfxStatOK;
    });
}
OfxStatus Instance::setDouble(const std::string& name, double v) {
    return setAndNotify(*host_, *this, name, [&](Param& p) {
        if (p.type != kOfxParamTypeDouble) return kOfxStatErrValue;
        p.d = v;
        return kOfxStatOK;
    });
}
OfxStatus Instance::setString(const std::string& name, const std::string& v) {
    return setAndNotify(*host_, *this, name, [&](Param& p) {
        if (p.type != kOfxParamTypeString) return kOfxStatErrValue;
        p.s = v;
        return kOfxStatOK;
    });
}

OfxStatus Instance::setRGB(const std::string& name, double r, double g, double b) {
    return setAndNotify(*host_, *this, name, [&](Param& p) {
        if (p.type != kOfxParamTypeRGB) return kOfxStatErrValue;
        p.rgb[0] = r, p.rgb[1] = g, p.rgb[2] = b;
        return kOfxStatOK;
    });
}

OfxStatus Instance::clipPreferences(PropertySet& out) {
    // The out-arguments are what HostSupport defines (per clip: components, depth, PAR; the
    // effect's premultiplication, continuous samples, frame varying), plus the preferred
    // colourspaces a 1.5 colour-managed host adds; a set on anything else fails.
    const std::string style = effect_->props.string(kOfxImageEffectPropColourManagementStyle);
    const bool colourManaged = !style.empty() && style != kOfxImageEffectColourManagementNone;
    for (const auto& c : effect_->clips) {
        out.setString(std::string(kOfxImageClipPropComponentsPrefix) + c->name, {c->props.string(kOfxImageEffectPropComponents)});
        out.setString(std::string(kOfxImageClipPropDepthPrefix) + c->name, {kOfxBitDepthFloat});
        out.setDouble(std::string(kOfxImageClipPropPARPrefix) + c->name, {effect_->par});
        if (colourManaged) out.setString(std::string(kOfxImageClipPropPreferredColourspacesPrefix) + c->name, {});
    }
    out.setString(kOfxImageEffectPropPreMultiplication, {kOfxImagePreMultiplied});
    out.setInt(kOfxImageClipPropContinuousSamples, {0});
    out.setInt(kOfxImageEffectFrameVarying, {0});
    out.closed = true;
    ++clipPreferencesRuns;
    const OfxStatus st = host_->action(kOfxImageEffectActionGetClipPreferences, effect_.get(), nullptr, &out);
    if (st != kOfxStatOK && st != kOfxStatReplyDefault) return st;
    Clip* output = effect_->clip(kOfxImageEffectOutputClipName);
    output->props.setString(kOfxImageEffectPropPreMultiplication, {out.string(kOfxImageEffectPropPreMultiplication)});
    // The general context lets the plugin remap the Output's components.
    const std::string comps = out.string(std::string(kOfxImageClipPropComponentsPrefix) + kOfxImageEffectOutputClipName);
    if (comps == kOfxImageComponentAlpha || comps == kOfxImageComponentRGBA) {
        outputComponents = comps == kOfxImageComponentAlpha ? 1 : 4;
        output->props.setString(kOfxImageEffectPropComponents, {comps});
    }
    // A colour-managed host asks for the output colourspace after the clip preferences.
    if (colourManaged) {
        std::string space;
        const OfxStatus cs = outputColourspace({"ofx_scene_linear"}, space);
        if (cs != kOfxStatOK && cs != kOfxStatReplyDefault) return cs;
    }
    return st;
}

OfxStatus Instance::outputColourspace(const std::vector<std::string>& preferred, std::string& space) {
    PropertySet in, out;
    in.setString(kOfxImageClipPropPreferredColourspaces, preferred);
    const OfxStatus st = host_->action(kOfxImageEffectActionGetOutputColourspace, effect_.get(), &in, &out);
    Clip* output = effect_->clip(kOfxImageEffectOutputClipName);
    if (st == kOfxStatOK) {
        space = out.string(kOfxImageClipPropColourspace);
        output->props.setString(kOfxImageClipPropColourspace, {space});
    } else {
        space.clear();
        output->props.erase(kOfxImageClipPropColourspace);
    }
    return st;
}

OfxStatus Instance::regionOfDefinition(OfxRectD& rod) {
    PropertySet in, out;
    in.setDouble(kOfxPropTime, {0.0});
    in.setDouble(kOfxImageEffectPropRenderScale, {effect_->renderScale, effect_->renderScale});
    // Default (what the host would use on ReplyDefault): the union of the connected inputs.
    OfxRectD def{0, 0, 0, 0};
    bool any = false;
    for (const auto& c : effect_->clips) {
        if (!c->input) continue;
        const OfxRectD r = clipRod(*c);
        def = any ? OfxRectD{std::min(def.x1, r.x1), std::min(def.y1, r.y1), std::max(def.x2, r.x2), std::max(def.y2, r.y2)} : r;
        any = true;
    }
    out.setDouble(kOfxImageEffectPropRegionOfDefinition, {def.x1, def.y1, def.x2, def.y2});
    const OfxStatus st = host_->action(kOfxImageEffectActionGetRegionOfDefinition, effect_.get(), &in, &out);
    const auto v = out.doubles(kOfxImageEffectPropRegionOfDefinition);
    rod = v.size() == 4 ? OfxRectD{v[0], v[1], v[2], v[3]} : def;
    if (Clip* o = effect_->clip(kOfxImageEffectOutputClipName)) o->props.setDouble("HostOutputRoD", {rod.x1, rod.y1, rod.x2, rod.y2});
    return st;
}

OfxStatus Instance::regionsOfInterest(const OfxRectD& region, std::map<std::string, OfxRectD>& rois) {
    PropertySet in, out;
    in.setDouble(kOfxPropTime, {0.0});
    in.setDouble(kOfxImageEffectPropRenderScale, {effect_->renderScale, effect_->renderScale});
    in.setDouble(kOfxImageEffectPropRegionOfInterest, {region.x1, region.y1, region.x2, region.y2});
    for (const auto& c : effect_->clips)
        if (c->name != kOfxImageEffectOutputClipName)
            out.setDouble(std::string(kOfxImageClipPropRoI) + c->name, {region.x1, region.y1, region.x2, region.y2});
    const OfxStatus st = host_->action(kOfxImageEffectActionGetRegionsOfInterest, effect_.get(), &in, &out);
    rois.clear();
    for (const auto& c : effect_->clips) {
        if (c->name == kOfxImageEffectOutputClipName) continue;
        const auto v = out.doubles(std::string(kOfxImageClipPropRoI) + c->name);
        if (v.size() == 4) rois[c->name] = {v[0], v[1], v[2], v[3]};
    }
    return st;
}

OfxStatus Instance::isIdentity(const OfxRectI& w, std::string& clipName) {
    PropertySet in, out;
    in.setDouble(kOfxPropTime, {0.0});
    in.setString(kOfxImageEffectPropFieldToRender, {kOfxImageFieldNone});
    in.setInt(kOfxImageEffectPropRenderWindow, {w.x1, w.y1, w.x2, w.y2});
    in.setDouble(kOfxImageEffectPropRenderScale, {effect_->renderScale, effect_->renderScale});
    out.setString(kOfxPropName, {""});
    out.setDouble(kOfxPropTime, {0.0});
    const OfxStatus st = host_->action(kOfxImageEffectActionIsIdentity, effect_.get(), &in, &out);
    clipName = out.string(kOfxPropName);
    return st;
}

OfxStatus Instance::render(const OfxRectI& w, HostImage& frame, std::vector<ImageFetch>* fetches,
                           const std::map<std::string, OfxRectD>* rois) {
    RenderContext rc;
    rc.rois = rois;
    rc.window = w;
    rc.components = outputComponents;
    rc.topDown = host_->negativeRowBytes;
    rc.fetches = fetches;
    const int ww = w.x2 - w.x1, wh = w.y2 - w.y1;
    std::vector<float> target((size_t)ww * wh * outputComponents, std::numeric_limits<float>::quiet_NaN());
    rc.target = &target;
    PropertySet in;
    in.setDouble(kOfxPropTime, {0.0});
    in.setString(kOfxImageEffectPropFieldToRender, {kOfxImageFieldNone});
    in.setInt(kOfxImageEffectPropRenderWindow, {w.x1, w.y1, w.x2, w.y2});
    in.setDouble(kOfxImageEffectPropRenderScale, {effect_->renderScale, effect_->renderScale});
    in.setInt(kOfxImageEffectPropSequentialRenderStatus, {0});
    in.setInt(kOfxImageEffectPropInteractiveRenderStatus, {0});
    tRender = &rc;
    const OfxStatus st = host_->action(kOfxImageEffectActionRender, effect_.get(), &in, nullptr);
    tRender = nullptr;
    const int rowFloats = ww * outputComponents;
    for (int y = w.y1; y < w.y2; ++y) {
        const int row = rc.topDown ? (w.y2 - 1 - y) : (y - w.y1);
        if (y < frame.bounds.y1 || y >= frame.bounds.y2) continue;
        for (int x = w.x1; x < w.x2; ++x) {
            if (x < frame.bounds.x1 || x >= frame.bounds.x2) continue;
            std::memcpy(frame.at(x, y), target.data() + (size_t)row * rowFloats + (size_t)(x - w.x1) * outputComponents,
                        sizeof(float) * outputComponents);
        }
    }
    return st;
}

namespace {
bool inside(const OfxRectD& a, const OfxRectD& b) {  // a within b
    return a.x1 >= b.x1 && a.y1 >= b.y1 && a.x2 <= b.x2 && a.y2 <= b.y2;
}
std::string str(const OfxRectD& r) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "(%g,%g)-(%g,%g)", r.x1, r.y1, r.x2, r.y2);
    return buf;
}
} // namespace

HostImage Instance::renderFrame(int tileW, int tileH, int threads, std::vector<std::string>& problems) {
    OfxRectD rodD{0, 0, 0, 0};
    if (regionOfDefinition(rodD) != kOfxStatOK) problems.push_back("the RoD action failed");
    const OfxRectI rod = toPixels(*effect_, rodD);
    HostImage frame(rod, outputComponents, std::numeric_limits<float>::quiet_NaN());
    if (tileW <= 0) tileW = rod.x2 - rod.x1;
    if (tileH <= 0) tileH = rod.y2 - rod.y1;
    std::vector<OfxRectI> tiles;
    for (int y = rod.y1; y < rod.y2; y += tileH)
        for (int x = rod.x1; x < rod.x2; x += tileW)
            tiles.push_back({x, y, std::min(x + tileW, rod.x2), std::min(y + tileH, rod.y2)});

    std::mutex problemMutex;
    std::atomic<size_t> next{0};
    auto worker = [&] {
        for (size_t i = next++; i < tiles.size(); i = next++) {
            const OfxRectI& t = tiles[i];
            std::vector<std::string> local;
            std::map<std::string, OfxRectD> rois;
            const OfxRectD tD = toCanonical(*effect_, t);
            if (regionsOfInterest(tD, rois) != kOfxStatOK) local.push_back("the RoI action failed");
            std::string identityClip;
            const OfxStatus id = isIdentity(t, identityClip);
            if (id == kOfxStatOK) {
                // The host copies the identity clip's pixels itself.
                Clip* c = effect_->clip(identityClip);
                if (!c || !c->input) {
                    local.push_back("identity names an unconnected clip '" + identityClip + "'");
                } else {
                    for (int y = t.y1; y < t.y2; ++y)
                        for (int x = t.x1; x < t.x2; ++x)
                            for (int k = 0; k < outputComponents; ++k)
                                frame.at(x, y)[k] = c->input->at(x, y)[std::min(k, c->input->components - 1)];
                }
            } else {
                std::vector<ImageFetch> fetches;
                const OfxStatus st = render(t, frame, &fetches, &rois);
                if (st != kOfxStatOK) local.push_back("render of a tile failed: status " + std::to_string(st));
                for (const ImageFetch& f : fetches) {
                    auto it = rois.find(f.clip);
                    if (it == rois.end()) {
                        local.push_back("fetched " + f.clip + " without a region of interest");
                    } else if (!inside(f.region, it->second)) {
                        local.push_back("fetched " + f.clip + " over " + str(f.region) + ", outside its RoI " +
                                        str(it->second) + " for tile " + str(tD));
                    }
                    if (!f.regionGiven) local.push_back("fetched " + f.clip + " without a region");
                }
            }
            if (!local.empty()) {
                std::lock_guard<std::mutex> lock(problemMutex);
                problems.insert(problems.end(), local.begin(), local.end());
            }
        }
    };
    std::vector<std::thread> pool;
    for (int k = 1; k < std::max(threads, 1); ++k) pool.emplace_back(worker);
    worker();
    for (auto& th : pool) th.join();
    for (float v : frame.pixels)
        if (std::isnan(v)) {
            problems.push_back("some output pixels were never written");
            break;
        }
    if (effect_->liveImages != 0) problems.push_back("images not released: " + std::to_string(effect_->liveImages.load()));
    return frame;
}

} // namespace obscura::ofxhost
