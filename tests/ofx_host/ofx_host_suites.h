// The test host's internals shared by its suite implementations (one file per OFX suite) and
// by Host and Instance: handle checks, the render in progress, the host object.
#pragma once

#include "ofx_host.h"

namespace obscura::ofxhost::suites {


// The render in progress on this thread: where the Output image goes, where fetches are logged.
struct RenderContext {
    OfxRectI window{0, 0, 0, 0};
    std::vector<float>* target = nullptr;  // window-sized, laid out as the Output image says
    bool topDown = false;
    int components = 4;
    std::vector<ImageFetch>* fetches = nullptr;
    const std::map<std::string, OfxRectD>* rois = nullptr;  // exact-region delivery, when given
};
extern thread_local RenderContext* tRender;

extern Host* gHostObject;  // the host the suites serve (one per process at a time)

template <class T>
T* checked(void* h, unsigned magic) {
    T* t = static_cast<T*>(h);
    return t && t->magic == magic ? t : nullptr;
}
inline PropertySet* props(OfxPropertySetHandle h) { return checked<PropertySet>(h, 0x0f5e7001u); }
inline Effect* effectOf(OfxImageEffectHandle h) { return checked<Effect>(h, 0x0f5e7005u); }
inline Clip* clipOf(OfxImageClipHandle h) { return checked<Clip>(h, 0x0f5e7004u); }
inline ParamSet* paramSetOf(OfxParamSetHandle h) { return checked<ParamSet>(h, 0x0f5e7003u); }
inline Param* paramOf(OfxParamHandle h) { return checked<Param>(h, 0x0f5e7002u); }

// An image handed to the plugin: its properties and its own copy of the pixels.
struct FetchedImage : PropertySet {
    std::vector<float> storage;
    Effect* owner = nullptr;
};


// Parameters whose values are ints (integer, choice, boolean).
inline bool isIntLike(const std::string& t) {
    return t == kOfxParamTypeInteger || t == kOfxParamTypeChoice || t == kOfxParamTypeBoolean;
}

// A clip's or parameter's handle and property set, as the GetHandle functions return them.
template <class Handle, class Item>
OfxStatus handOut(Item* item, Handle* handle, OfxPropertySetHandle* props) {
    if (!item) return kOfxStatErrUnknown;
    if (handle) *handle = reinterpret_cast<Handle>(item);
    if (props) *props = item->props.handle();
    return kOfxStatOK;
}

// Keeps a newly defined clip or parameter and hands out its property set.
template <class Item>
OfxStatus keep(std::vector<std::unique_ptr<Item>>& items, std::unique_ptr<Item> item, OfxPropertySetHandle* out) {
    if (out) *out = item->props.handle();
    items.push_back(std::move(item));
    return kOfxStatOK;
}

// The property set of an item a handle names, as the GetPropertySet functions return it.
template <class Item>
OfxStatus propertiesOf(Item* item, OfxPropertySetHandle* out) {
    if (!item) return kOfxStatErrBadHandle;
    *out = item->props.handle();
    return kOfxStatOK;
}

// Geometry the effect suite and Instance::renderFrame share.
OfxRectD toCanonical(const Effect& e, const OfxRectI& r);
OfxRectI toPixels(const Effect& e, const OfxRectD& r);
OfxRectD clipRod(const Clip& c);

extern const OfxPropertySuiteV1 kPropertySuite;
extern const OfxImageEffectSuiteV1 kImageEffectSuite;
extern const OfxParameterSuiteV1 kParameterSuite;

} // namespace obscura::ofxhost::suites
