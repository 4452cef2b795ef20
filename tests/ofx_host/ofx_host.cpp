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

namespace obscura::ofxhost {

namespace {

// The render in progress on this thread: where the Output image goes, where fetches are logged.
struct RenderContext {
    OfxRectI window{0, 0, 0, 0};
    std::vector<float>* target = nullptr;  // window-sized, laid out as the Output image says
    bool topDown = false;
    int components = 4;
    std::vector<ImageFetch>* fetches = nullptr;
    const std::map<std::string, OfxRectD>* rois = nullptr;  // exact-region delivery, when given
};
thread_local RenderContext* tRender = nullptr;

Host* gHostObject = nullptr;  // the host the suites serve (one per process at a time)

template <class T>
T* checked(void* h, unsigned magic) {
    T* t = static_cast<T*>(h);
    return t && t->magic == magic ? t : nullptr;
}
PropertySet* props(OfxPropertySetHandle h) { return checked<PropertySet>(h, 0x0f5e7001u); }
Effect* effectOf(OfxImageEffectHandle h) { return checked<Effect>(h, 0x0f5e7005u); }
Clip* clipOf(OfxImageClipHandle h) { return checked<Clip>(h, 0x0f5e7004u); }
ParamSet* paramSetOf(OfxParamSetHandle h) { return checked<ParamSet>(h, 0x0f5e7003u); }
Param* paramOf(OfxParamHandle h) { return checked<Param>(h, 0x0f5e7002u); }

// An image handed to the plugin: its properties and its own copy of the pixels.
struct FetchedImage : PropertySet {
    std::vector<float> storage;
    Effect* owner = nullptr;
};

// ---------------------------------------------------------------------------
// Property suite
// ---------------------------------------------------------------------------

template <class Fn>
OfxStatus withProp(OfxPropertySetHandle h, const char* name, bool create, Property::Type type, Fn fn) {
    PropertySet* ps = props(h);
    if (!ps || !name) return kOfxStatErrBadHandle;
    std::lock_guard<std::mutex> lock(ps->mutex);
    auto it = ps->props.find(name);
    if (it == ps->props.end()) {
        if (!create || ps->closed) return kOfxStatErrUnknown;
        it = ps->props.emplace(name, Property{}).first;
        it->second.type = type;
    }
    if (it->second.type != type) return kOfxStatErrValue;
    return fn(it->second);
}

template <class V>
OfxStatus setAt(std::vector<V>& vec, int index, V v) {
    if (index < 0) return kOfxStatErrBadIndex;
    if ((size_t)index >= vec.size()) vec.resize(index + 1);
    vec[index] = v;
    return kOfxStatOK;
}
template <class V>
OfxStatus getAt(const std::vector<V>& vec, int index, V* out) {
    if (!out) return kOfxStatErrValue;
    if (index < 0 || (size_t)index >= vec.size()) return kOfxStatErrBadIndex;
    *out = vec[index];
    return kOfxStatOK;
}

OfxStatus propSetPointer(OfxPropertySetHandle h, const char* n, int i, void* v) {
    return withProp(h, n, true, Property::Pointer, [&](Property& p) { return setAt(p.p, i, v); });
}
OfxStatus propSetString(OfxPropertySetHandle h, const char* n, int i, const char* v) {
    return withProp(h, n, true, Property::String, [&](Property& p) { return setAt(p.s, i, std::string(v ? v : "")); });
}
OfxStatus propSetDouble(OfxPropertySetHandle h, const char* n, int i, double v) {
    return withProp(h, n, true, Property::Double, [&](Property& p) { return setAt(p.d, i, v); });
}
OfxStatus propSetInt(OfxPropertySetHandle h, const char* n, int i, int v) {
    return withProp(h, n, true, Property::Int, [&](Property& p) { return setAt(p.i, i, v); });
}
OfxStatus propSetPointerN(OfxPropertySetHandle h, const char* n, int c, void* const* v) {
    return withProp(h, n, true, Property::Pointer, [&](Property& p) {
        p.p.assign(v, v + c);
        return kOfxStatOK;
    });
}
OfxStatus propSetStringN(OfxPropertySetHandle h, const char* n, int c, const char* const* v) {
    return withProp(h, n, true, Property::String, [&](Property& p) {
        p.s.clear();
        for (int k = 0; k < c; ++k) p.s.push_back(v[k] ? v[k] : "");
        return kOfxStatOK;
    });
}
OfxStatus propSetDoubleN(OfxPropertySetHandle h, const char* n, int c, const double* v) {
    return withProp(h, n, true, Property::Double, [&](Property& p) {
        p.d.assign(v, v + c);
        return kOfxStatOK;
    });
}
OfxStatus propSetIntN(OfxPropertySetHandle h, const char* n, int c, const int* v) {
    return withProp(h, n, true, Property::Int, [&](Property& p) {
        p.i.assign(v, v + c);
        return kOfxStatOK;
    });
}
OfxStatus propGetPointer(OfxPropertySetHandle h, const char* n, int i, void** v) {
    return withProp(h, n, false, Property::Pointer, [&](Property& p) { return getAt(p.p, i, v); });
}
OfxStatus propGetString(OfxPropertySetHandle h, const char* n, int i, char** v) {
    return withProp(h, n, false, Property::String, [&](Property& p) {
        if (i < 0 || (size_t)i >= p.s.size()) return kOfxStatErrBadIndex;
        *v = const_cast<char*>(p.s[i].c_str());
        return kOfxStatOK;
    });
}
OfxStatus propGetDouble(OfxPropertySetHandle h, const char* n, int i, double* v) {
    return withProp(h, n, false, Property::Double, [&](Property& p) { return getAt(p.d, i, v); });
}
OfxStatus propGetInt(OfxPropertySetHandle h, const char* n, int i, int* v) {
    return withProp(h, n, false, Property::Int, [&](Property& p) { return getAt(p.i, i, v); });
}
OfxStatus propGetPointerN(OfxPropertySetHandle h, const char* n, int c, void** v) {
    return withProp(h, n, false, Property::Pointer, [&](Property& p) {
        if (c > (int)p.p.size()) return kOfxStatErrBadIndex;
        std::copy(p.p.begin(), p.p.begin() + c, v);
        return kOfxStatOK;
    });
}
OfxStatus propGetStringN(OfxPropertySetHandle h, const char* n, int c, char** v) {
    return withProp(h, n, false, Property::String, [&](Property& p) {
        if (c > (int)p.s.size()) return kOfxStatErrBadIndex;
        for (int k = 0; k < c; ++k) v[k] = const_cast<char*>(p.s[k].c_str());
        return kOfxStatOK;
    });
}
OfxStatus propGetDoubleN(OfxPropertySetHandle h, const char* n, int c, double* v) {
    return withProp(h, n, false, Property::Double, [&](Property& p) {
        if (c > (int)p.d.size()) return kOfxStatErrBadIndex;
        std::copy(p.d.begin(), p.d.begin() + c, v);
        return kOfxStatOK;
    });
}
OfxStatus propGetIntN(OfxPropertySetHandle h, const char* n, int c, int* v) {
    return withProp(h, n, false, Property::Int, [&](Property& p) {
        if (c > (int)p.i.size()) return kOfxStatErrBadIndex;
        std::copy(p.i.begin(), p.i.begin() + c, v);
        return kOfxStatOK;
    });
}
OfxStatus propReset(OfxPropertySetHandle h, const char* n) {
    PropertySet* ps = props(h);
    if (!ps) return kOfxStatErrBadHandle;
    std::lock_guard<std::mutex> lock(ps->mutex);
    return ps->props.count(n) ? kOfxStatOK : kOfxStatErrUnknown;
}
OfxStatus propGetDimension(OfxPropertySetHandle h, const char* n, int* count) {
    PropertySet* ps = props(h);
    if (!ps) return kOfxStatErrBadHandle;
    std::lock_guard<std::mutex> lock(ps->mutex);
    auto it = ps->props.find(n);
    if (it == ps->props.end()) return kOfxStatErrUnknown;
    *count = it->second.size();
    return kOfxStatOK;
}

const OfxPropertySuiteV1 kPropertySuite = {
    propSetPointer, propSetString,  propSetDouble,  propSetInt,     propSetPointerN, propSetStringN,
    propSetDoubleN, propSetIntN,    propGetPointer, propGetString,  propGetDouble,   propGetInt,
    propGetPointerN, propGetStringN, propGetDoubleN, propGetIntN,   propReset,       propGetDimension};

// ---------------------------------------------------------------------------
// Image effect suite
// ---------------------------------------------------------------------------

OfxStatus getPropertySet(OfxImageEffectHandle h, OfxPropertySetHandle* out) {
    Effect* e = effectOf(h);
    if (!e) return kOfxStatErrBadHandle;
    *out = e->props.handle();
    return kOfxStatOK;
}
OfxStatus getParamSet(OfxImageEffectHandle h, OfxParamSetHandle* out) {
    Effect* e = effectOf(h);
    if (!e) return kOfxStatErrBadHandle;
    *out = reinterpret_cast<OfxParamSetHandle>(&e->params);
    return kOfxStatOK;
}
OfxStatus clipDefine(OfxImageEffectHandle h, const char* name, OfxPropertySetHandle* out) {
    Effect* e = effectOf(h);
    if (!e || !e->descriptor) return kOfxStatErrBadHandle;
    if (e->clip(name)) return kOfxStatErrExists;
    auto c = std::make_unique<Clip>();
    c->name = name;
    c->effect = e;
    c->props.setString(kOfxPropType, {kOfxTypeClip});
    c->props.setString(kOfxPropName, {name});
    c->props.setInt(kOfxImageClipPropOptional, {0});
    c->props.setInt(kOfxImageClipPropIsMask, {0});
    c->props.setInt(kOfxImageEffectPropSupportsTiles, {1});
    c->props.setInt(kOfxImageEffectPropTemporalClipAccess, {0});
    *out = c->props.handle();
    e->clips.push_back(std::move(c));
    return kOfxStatOK;
}
OfxStatus clipGetHandle(OfxImageEffectHandle h, const char* name, OfxImageClipHandle* clip, OfxPropertySetHandle* ps) {
    Effect* e = effectOf(h);
    if (!e) return kOfxStatErrBadHandle;
    Clip* c = e->clip(name);
    if (!c) return kOfxStatErrUnknown;
    if (clip) *clip = reinterpret_cast<OfxImageClipHandle>(c);
    if (ps) *ps = c->props.handle();
    return kOfxStatOK;
}
OfxStatus clipGetPropertySet(OfxImageClipHandle h, OfxPropertySetHandle* out) {
    Clip* c = clipOf(h);
    if (!c) return kOfxStatErrBadHandle;
    *out = c->props.handle();
    return kOfxStatOK;
}

// Canonical coordinates are pixels at render scale 1 stretched by the pixel aspect ratio:
// canonical x = pixel x * PAR / scale, canonical y = pixel y / scale.
OfxRectD toCanonical(const Effect& e, const OfxRectI& r) {
    const double kx = e.par / e.renderScale, ky = 1.0 / e.renderScale;
    return {r.x1 * kx, r.y1 * ky, r.x2 * kx, r.y2 * ky};
}
OfxRectI toPixels(const Effect& e, const OfxRectD& r) {
    const double kx = e.renderScale / e.par, ky = e.renderScale;
    return {(int)std::floor(r.x1 * kx + 1e-6), (int)std::floor(r.y1 * ky + 1e-6), (int)std::ceil(r.x2 * kx - 1e-6),
            (int)std::ceil(r.y2 * ky - 1e-6)};
}
OfxRectD intersect(const OfxRectD& a, const OfxRectD& b) {
    const OfxRectD r{std::max(a.x1, b.x1), std::max(a.y1, b.y1), std::min(a.x2, b.x2), std::min(a.y2, b.y2)};
    return r.x2 > r.x1 && r.y2 > r.y1 ? r : OfxRectD{0, 0, 0, 0};
}

OfxRectD clipRod(const Clip& c) {
    if (!c.input) return {0, 0, 0, 0};
    return toCanonical(*c.effect, c.input->bounds);
}

OfxStatus clipGetRegionOfDefinition(OfxImageClipHandle h, OfxTime, OfxRectD* out) {
    Clip* c = clipOf(h);
    if (!c || c->effect->descriptor) return kOfxStatErrBadHandle;
    if (c->name == kOfxImageEffectOutputClipName) {
        // The effect's own RoD is what the host asked the plugin for; the frame for outputs.
        const std::vector<double> rod = c->props.doubles("HostOutputRoD");
        if (rod.size() != 4) return kOfxStatFailed;
        *out = {rod[0], rod[1], rod[2], rod[3]};
        return kOfxStatOK;
    }
    *out = clipRod(*c);
    return kOfxStatOK;
}

OfxStatus clipGetImage(OfxImageClipHandle h, OfxTime, const OfxRectD* region, OfxPropertySetHandle* out) {
    Clip* c = clipOf(h);
    if (!c || c->effect->descriptor || !out) return kOfxStatErrBadHandle;
    Host& host = *gHostObject;
    RenderContext* rc = tRender;
    auto img = std::make_unique<FetchedImage>();
    img->setString(kOfxPropType, {kOfxTypeImage});
    img->setString(kOfxImageEffectPropPixelDepth, {kOfxBitDepthFloat});
    img->setDouble(kOfxImagePropPixelAspectRatio, {c->effect->par});
    img->setDouble(kOfxImageEffectPropRenderScale, {c->effect->renderScale, c->effect->renderScale});
    img->setString(kOfxImagePropField, {kOfxImageFieldNone});
    img->setString(kOfxImagePropUniqueIdentifier, {c->name});
    OfxRectI b{0, 0, 0, 0};
    int comps = 4;
    if (c->name == kOfxImageEffectOutputClipName) {
        if (!rc || !rc->target) return kOfxStatFailed;  // outputs exist only during a render
        b = rc->window;
        comps = rc->components;
        const int rowFloats = (b.x2 - b.x1) * comps;
        float* base = rc->target->data();
        if (rc->topDown) {
            img->setPointer(kOfxImagePropData, base + (size_t)(b.y2 - b.y1 - 1) * rowFloats);
            img->setInt(kOfxImagePropRowBytes, {-rowFloats * (int)sizeof(float)});
        } else {
            img->setPointer(kOfxImagePropData, base);
            img->setInt(kOfxImagePropRowBytes, {rowFloats * (int)sizeof(float)});
        }
    } else {
        if (!c->input) return kOfxStatFailed;  // not connected
        const HostImage& src = *c->input;
        const OfxRectD rod = clipRod(*c);
        OfxRectD want = region ? *region : rod;
        if (rc && rc->fetches) {
            std::lock_guard<std::mutex> lock(host.logMutex_);
            rc->fetches->push_back({c->name, want, region != nullptr});
        }
        if (host.exactRegions && rc && rc->rois) {
            // What a host that computes its inputs on demand has: the RoI, nothing around it.
            auto it = rc->rois->find(c->name);
            want = intersect(want, it == rc->rois->end() ? OfxRectD{0, 0, 0, 0} : it->second);
        }
        const OfxRectI px = toPixels(*c->effect, want);
        b = {std::max(src.bounds.x1, px.x1), std::max(src.bounds.y1, px.y1), std::min(src.bounds.x2, px.x2),
             std::min(src.bounds.y2, px.y2)};
        if (b.x2 <= b.x1 || b.y2 <= b.y1) b = {0, 0, 0, 0};
        comps = src.components;
        const int w = b.x2 - b.x1, hgt = b.y2 - b.y1, rowFloats = w * comps;
        img->storage.assign((size_t)std::max(w * hgt * comps, 1), std::numeric_limits<float>::quiet_NaN());
        for (int y = b.y1; y < b.y2; ++y) {
            const int row = host.negativeRowBytes ? (b.y2 - 1 - y) : (y - b.y1);
            std::memcpy(img->storage.data() + (size_t)row * rowFloats, src.at(b.x1, y), sizeof(float) * rowFloats);
        }
        if (host.negativeRowBytes) {
            img->setPointer(kOfxImagePropData, img->storage.data() + (size_t)std::max(hgt - 1, 0) * rowFloats);
            img->setInt(kOfxImagePropRowBytes, {-rowFloats * (int)sizeof(float)});
        } else {
            img->setPointer(kOfxImagePropData, img->storage.data());
            img->setInt(kOfxImagePropRowBytes, {rowFloats * (int)sizeof(float)});
        }
        img->setDouble(kOfxImagePropRegionOfDefinition, {rod.x1, rod.y1, rod.x2, rod.y2});
    }
    img->setInt(kOfxImagePropBounds, {b.x1, b.y1, b.x2, b.y2});
    img->setString(kOfxImageEffectPropComponents, {comps == 1 ? kOfxImageComponentAlpha : kOfxImageComponentRGBA});
    img->setString(kOfxImageEffectPropPreMultiplication, {comps == 1 ? kOfxImageOpaque : kOfxImagePreMultiplied});
    ++host.liveImages_;
    ++c->effect->liveImages;
    img->owner = c->effect;
    {
        std::lock_guard<std::mutex> lock(host.logMutex_);
        host.images_.insert(img.get());
    }
    *out = img.release()->handle();
    return kOfxStatOK;
}

OfxStatus clipReleaseImage(OfxPropertySetHandle h) {
    PropertySet* p = props(h);
    if (!p) return kOfxStatErrBadHandle;
    FetchedImage* img = static_cast<FetchedImage*>(p);
    {
        // Only images handed out and not yet released can be released (no double release).
        std::lock_guard<std::mutex> lock(gHostObject->logMutex_);
        if (!gHostObject->images_.erase(img)) return kOfxStatErrBadHandle;
    }
    --img->owner->liveImages;
    delete img;
    --gHostObject->liveImages_;
    return kOfxStatOK;
}

int abortRender(OfxImageEffectHandle) { return 0; }

struct Memory {
    unsigned magic = 0x0f5e7006u;
    std::vector<char> bytes;
};
OfxStatus imageMemoryAlloc(OfxImageEffectHandle, size_t n, OfxImageMemoryHandle* out) {
    auto* m = new Memory;
    m->bytes.resize(n);
    *out = reinterpret_cast<OfxImageMemoryHandle>(m);
    return kOfxStatOK;
}
OfxStatus imageMemoryFree(OfxImageMemoryHandle h) {
    Memory* m = checked<Memory>(h, 0x0f5e7006u);
    if (!m) return kOfxStatErrBadHandle;
    delete m;
    return kOfxStatOK;
}
OfxStatus imageMemoryLock(OfxImageMemoryHandle h, void** out) {
    Memory* m = checked<Memory>(h, 0x0f5e7006u);
    if (!m) return kOfxStatErrBadHandle;
    *out = m->bytes.data();
    return kOfxStatOK;
}
OfxStatus imageMemoryNoop(OfxImageMemoryHandle h) {
    return checked<Memory>(h, 0x0f5e7006u) ? kOfxStatOK : kOfxStatErrBadHandle;
}

const OfxImageEffectSuiteV1 kImageEffectSuite = {
    getPropertySet,     getParamSet,  clipDefine,       clipGetHandle,
    clipGetPropertySet, clipGetImage, clipReleaseImage, clipGetRegionOfDefinition,
    abortRender,        imageMemoryAlloc, imageMemoryFree, imageMemoryLock,
    imageMemoryNoop};

// ---------------------------------------------------------------------------
// Parameter suite
// ---------------------------------------------------------------------------

bool isIntLike(const std::string& t) {
    return t == kOfxParamTypeInteger || t == kOfxParamTypeChoice || t == kOfxParamTypeBoolean;
}

OfxStatus paramDefine(OfxParamSetHandle h, const char* type, const char* name, OfxPropertySetHandle* out) {
    ParamSet* ps = paramSetOf(h);
    if (!ps) return kOfxStatErrBadHandle;
    if (ps->find(name)) return kOfxStatErrExists;
    const std::string t = type;
    if (!(isIntLike(t) || t == kOfxParamTypeDouble || t == kOfxParamTypeRGB || t == kOfxParamTypeString ||
          t == kOfxParamTypeGroup || t == kOfxParamTypePage))
        return kOfxStatErrUnknown;
    auto p = std::make_unique<Param>();
    p->type = t;
    p->name = name;
    p->props.setString(kOfxPropType, {kOfxTypeParameter});
    p->props.setString(kOfxPropName, {name});
    p->props.setString(kOfxParamPropType, {t});
    if (out) *out = p->props.handle();
    ps->params.push_back(std::move(p));
    return kOfxStatOK;
}
OfxStatus paramGetHandle(OfxParamSetHandle h, const char* name, OfxParamHandle* param, OfxPropertySetHandle* out) {
    ParamSet* ps = paramSetOf(h);
    if (!ps) return kOfxStatErrBadHandle;
    Param* p = ps->find(name);
    if (!p) return kOfxStatErrUnknown;
    if (param) *param = reinterpret_cast<OfxParamHandle>(p);
    if (out) *out = p->props.handle();
    return kOfxStatOK;
}
OfxStatus paramSetGetPropertySet(OfxParamSetHandle h, OfxPropertySetHandle* out) {
    ParamSet* ps = paramSetOf(h);
    if (!ps) return kOfxStatErrBadHandle;
    *out = ps->props.handle();
    return kOfxStatOK;
}
OfxStatus paramGetPropertySet(OfxParamHandle h, OfxPropertySetHandle* out) {
    Param* p = paramOf(h);
    if (!p) return kOfxStatErrBadHandle;
    *out = p->props.handle();
    return kOfxStatOK;
}
OfxStatus getValue(Param* p, va_list ap) {
    if (!p) return kOfxStatErrBadHandle;
    if (isIntLike(p->type)) {
        *va_arg(ap, int*) = p->i;
    } else if (p->type == kOfxParamTypeDouble) {
        *va_arg(ap, double*) = p->d;
    } else if (p->type == kOfxParamTypeRGB) {
        for (double v : p->rgb) *va_arg(ap, double*) = v;
    } else if (p->type == kOfxParamTypeString) {
        *va_arg(ap, char**) = const_cast<char*>(p->s.c_str());
    } else {
        return kOfxStatErrValue;
    }
    return kOfxStatOK;
}
OfxStatus paramGetValue(OfxParamHandle h, ...) {
    va_list ap;
    va_start(ap, h);
    const OfxStatus st = getValue(paramOf(h), ap);
    va_end(ap);
    return st;
}
OfxStatus unsupportedDerivative(OfxParamHandle, OfxTime, ...) { return kOfxStatErrUnsupported; }
OfxStatus unsupportedIntegral(OfxParamHandle, OfxTime, OfxTime, ...) { return kOfxStatErrUnsupported; }
OfxStatus setValue(Param* p, va_list ap) {
    if (!p) return kOfxStatErrBadHandle;
    if (isIntLike(p->type)) {
        p->i = va_arg(ap, int);
    } else if (p->type == kOfxParamTypeDouble) {
        p->d = va_arg(ap, double);
    } else if (p->type == kOfxParamTypeRGB) {
        for (double& v : p->rgb) v = va_arg(ap, double);
    } else if (p->type == kOfxParamTypeString) {
        const char* s = va_arg(ap, const char*);
        p->s = s ? s : "";
    } else {
        return kOfxStatErrValue;
    }
    return kOfxStatOK;
}
OfxStatus paramSetValue(OfxParamHandle h, ...) {
    va_list ap;
    va_start(ap, h);
    const OfxStatus st = setValue(paramOf(h), ap);
    va_end(ap);
    return st;
}
OfxStatus paramSetValueAtTime(OfxParamHandle h, OfxTime t, ...) {
    va_list ap;
    va_start(ap, t);
    const OfxStatus st = setValue(paramOf(h), ap);
    va_end(ap);
    return st;
}
OfxStatus paramGetNumKeys(OfxParamHandle h, unsigned int* n) {
    if (!paramOf(h)) return kOfxStatErrBadHandle;
    *n = 0;
    return kOfxStatOK;
}
OfxStatus paramGetKeyTime(OfxParamHandle, unsigned int, OfxTime*) { return kOfxStatErrBadIndex; }
OfxStatus paramGetKeyIndex(OfxParamHandle, OfxTime, int, int*) { return kOfxStatFailed; }
OfxStatus paramDeleteKey(OfxParamHandle, OfxTime) { return kOfxStatErrBadIndex; }
OfxStatus paramDeleteAllKeys(OfxParamHandle) { return kOfxStatOK; }
OfxStatus paramCopy(OfxParamHandle, OfxParamHandle, OfxTime, const OfxRangeD*) { return kOfxStatErrUnsupported; }
OfxStatus paramEditBegin(OfxParamSetHandle, const char*) { return kOfxStatOK; }
OfxStatus paramEditEnd(OfxParamSetHandle) { return kOfxStatOK; }

// paramGetValueAtTime: the time is named, the value pointer follows it.
OfxStatus paramGetValueAtTimeImpl(OfxParamHandle h, OfxTime t, ...) {
    va_list ap;
    va_start(ap, t);
    const OfxStatus st = getValue(paramOf(h), ap);
    va_end(ap);
    return st;
}

const OfxParameterSuiteV1 kParameterSuite = {
    paramDefine,     paramGetHandle,        paramSetGetPropertySet, paramGetPropertySet, paramGetValue,
    paramGetValueAtTimeImpl, unsupportedDerivative, unsupportedIntegral, paramSetValue, paramSetValueAtTime,
    paramGetNumKeys, paramGetKeyTime,       paramGetKeyIndex,       paramDeleteKey,      paramDeleteAllKeys,
    paramCopy,       paramEditBegin,        paramEditEnd};

// ---------------------------------------------------------------------------
// Message suite
// ---------------------------------------------------------------------------

OfxStatus message(void*, const char* type, const char* id, const char* format, ...) {
    char buf[4096];
    va_list ap;
    va_start(ap, format);
    std::vsnprintf(buf, sizeof buf, format, ap);
    va_end(ap);
    std::lock_guard<std::mutex> lock(gHostObject->logMutex_);
    gHostObject->messages_.push_back(std::string(type ? type : "?") + (id ? std::string(" ") + id : "") + ": " + buf);
    return kOfxStatOK;
}
const OfxMessageSuiteV1 kMessageSuite = {message};

const void* fetchSuite(OfxPropertySetHandle, const char* name, int version) {
    const std::string n = name ? name : "";
    {
        std::lock_guard<std::mutex> lock(gHostObject->logMutex_);
        gHostObject->suites_.push_back(n + " v" + std::to_string(version));
    }
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

void PropertySet::setString(const std::string& n, std::vector<std::string> v) {
    std::lock_guard<std::mutex> lock(mutex);
    Property& p = props[n];
    p = Property{};
    p.type = Property::String;
    p.s = std::move(v);
}
void PropertySet::setDouble(const std::string& n, std::vector<double> v) {
    std::lock_guard<std::mutex> lock(mutex);
    Property& p = props[n];
    p = Property{};
    p.type = Property::Double;
    p.d = std::move(v);
}
void PropertySet::setInt(const std::string& n, std::vector<int> v) {
    std::lock_guard<std::mutex> lock(mutex);
    Property& p = props[n];
    p = Property{};
    p.type = Property::Int;
    p.i = std::move(v);
}
void PropertySet::erase(const std::string& n) {
    std::lock_guard<std::mutex> lock(mutex);
    props.erase(n);
}
void PropertySet::setPointer(const std::string& n, void* v) {
    std::lock_guard<std::mutex> lock(mutex);
    Property& p = props[n];
    p = Property{};
    p.type = Property::Pointer;
    p.p = {v};
}
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
    e.props.setDouble(kOfxImageEffectPropProjectPixelAspectRatio, {project.pixelAspect});
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
