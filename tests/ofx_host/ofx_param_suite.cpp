// The test host's OFX parameter suite.
#include "ofx_host_suites.h"

#include <cstdarg>
#include <mutex>

namespace obscura::ofxhost::suites {

// ---------------------------------------------------------------------------
// Parameter suite
// ---------------------------------------------------------------------------

namespace {

// The variadic entry points hand their value arguments on as a va_list.
#define FORWARD_VALUE_ARGS(last, fn)              \
    va_list ap;                                   \
    va_start(ap, last);                           \
    const OfxStatus st = fn(paramOf(h), ap);      \
    va_end(ap);                                   \
    return st

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
    return keep(ps->params, std::move(p), out);
}
OfxStatus paramGetHandle(OfxParamSetHandle h, const char* name, OfxParamHandle* param, OfxPropertySetHandle* out) {
    ParamSet* ps = paramSetOf(h);
    return ps ? handOut(ps->find(name), param, out) : kOfxStatErrBadHandle;
}
OfxStatus paramSetGetPropertySet(OfxParamSetHandle h, OfxPropertySetHandle* out) { return propertiesOf(paramSetOf(h), out); }
OfxStatus paramGetPropertySet(OfxParamHandle h, OfxPropertySetHandle* out) { return propertiesOf(paramOf(h), out); }
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
OfxStatus paramGetValue(OfxParamHandle h, ...) { FORWARD_VALUE_ARGS(h, getValue); }
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
OfxStatus paramSetValue(OfxParamHandle h, ...) { FORWARD_VALUE_ARGS(h, setValue); }
OfxStatus paramSetValueAtTime(OfxParamHandle h, OfxTime t, ...) { FORWARD_VALUE_ARGS(t, setValue); }
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
OfxStatus paramGetValueAtTimeImpl(OfxParamHandle h, OfxTime t, ...) { FORWARD_VALUE_ARGS(t, getValue); }

#undef FORWARD_VALUE_ARGS

} // namespace

const OfxParameterSuiteV1 kParameterSuite = {
    paramDefine,     paramGetHandle,        paramSetGetPropertySet, paramGetPropertySet, paramGetValue,
    paramGetValueAtTimeImpl, unsupportedDerivative, unsupportedIntegral, paramSetValue, paramSetValueAtTime,
    paramGetNumKeys, paramGetKeyTime,       paramGetKeyIndex,       paramDeleteKey,      paramDeleteAllKeys,
    paramCopy,       paramEditBegin,        paramEditEnd};

} // namespace obscura::ofxhost::suites
