// The test host's OFX image effect suite: clips, images and image memory.
#include "ofx_host_suites.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <mutex>
#include <thread>

namespace obscura::ofxhost::suites {

// ---------------------------------------------------------------------------
// Image effect suite
// ---------------------------------------------------------------------------

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

namespace {

OfxStatus getPropertySet(OfxImageEffectHandle h, OfxPropertySetHandle* out) { return propertiesOf(effectOf(h), out); }
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
    return keep(e->clips, std::move(c), out);
}
OfxStatus clipGetHandle(OfxImageEffectHandle h, const char* name, OfxImageClipHandle* clip, OfxPropertySetHandle* ps) {
    Effect* e = effectOf(h);
    return e ? handOut(e->clip(name), clip, ps) : kOfxStatErrBadHandle;
}
OfxStatus clipGetPropertySet(OfxImageClipHandle h, OfxPropertySetHandle* out) { return propertiesOf(clipOf(h), out); }

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
    if (const int failing = c->props.integer("HostRoDStatus")) return failing;  // a test's failing host
    *out = clipRod(*c);
    // A generator's input (a test sets HostInfiniteRoD): infinite, as ofxCore.h flags it.
    if (c->props.integer("HostInfiniteRoD") == 1)
        *out = {(double)kOfxFlagInfiniteMin, (double)kOfxFlagInfiniteMin, (double)kOfxFlagInfiniteMax,
                (double)kOfxFlagInfiniteMax};
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
        if (b.x2 <= b.x1 || b.y2 <= b.y1) {
            if (host.failEmptyFetch) return kOfxStatFailed;
            b = {0, 0, 0, 0};
        }
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

int abortRender(OfxImageEffectHandle) {
    Host& host = *gHostObject;
    {
        std::lock_guard<std::mutex> lock(host.logMutex_);
        host.abortThreads_.insert(std::this_thread::get_id());
    }
    const int call = ++host.abortCalls_;
    return host.abortFromCall > 0 && call >= host.abortFromCall ? 1 : 0;
}

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

} // namespace

const OfxImageEffectSuiteV1 kImageEffectSuite = {
    getPropertySet,     getParamSet,  clipDefine,       clipGetHandle,
    clipGetPropertySet, clipGetImage, clipReleaseImage, clipGetRegionOfDefinition,
    abortRender,        imageMemoryAlloc, imageMemoryFree, imageMemoryLock,
    imageMemoryNoop};

} // namespace obscura::ofxhost::suites
