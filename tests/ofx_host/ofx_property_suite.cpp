// The test host's OFX property suite.
#include "ofx_host_suites.h"

#include <mutex>

namespace obscura::ofxhost::suites {

// ---------------------------------------------------------------------------
// Property suite
// ---------------------------------------------------------------------------

namespace {

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

} // namespace

const OfxPropertySuiteV1 kPropertySuite = {
    propSetPointer, propSetString,  propSetDouble,  propSetInt,     propSetPointerN, propSetStringN,
    propSetDoubleN, propSetIntN,    propGetPointer, propGetString,  propGetDouble,   propGetInt,
    propGetPointerN, propGetStringN, propGetDoubleN, propGetIntN,   propReset,       propGetDimension};


} // namespace obscura::ofxhost::suites
