// plugin/ofx/ofx_api.h against the OpenFX specification. The expected values below are
// spelled out here, read from the official headers (ofxCore.h, ofxProperty.h, ofxParam.h,
// ofxImageEffect.h, ofxMessage.h, ofxGPURender.h, ofxColour.h and its native config
// header; the clip-name prefixes from the prose of ofxImageEffect.h and ofxColour.h), not
// taken from the header under test: a misspelt string or a wrong layout in ofx_api.h is
// invisible to a test host built on the same header, but not to a real host.
#include "ofx/ofx_api.h"

#include <gtest/gtest.h>

#include <cstddef>
#include <climits>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <type_traits>

namespace {

struct StringConstant {
    const char* name;
    const char* header;  // the value ofx_api.h gives
    const char* spec;    // the specification's value
};
struct IntConstant {
    const char* name;
    long long header, spec;
};

#define S(name, value) StringConstant{#name, name, value}
#define I(name, value) IntConstant{#name, (long long)(name), value}

const StringConstant kStrings[] = {
    S(kOfxActionLoad, "OfxActionLoad"),
    S(kOfxActionDescribe, "OfxActionDescribe"),
    S(kOfxActionUnload, "OfxActionUnload"),
    S(kOfxActionPurgeCaches, "OfxActionPurgeCaches"),
    S(kOfxActionSyncPrivateData, "OfxActionSyncPrivateData"),
    S(kOfxActionCreateInstance, "OfxActionCreateInstance"),
    S(kOfxActionDestroyInstance, "OfxActionDestroyInstance"),
    S(kOfxActionInstanceChanged, "OfxActionInstanceChanged"),
    S(kOfxActionBeginInstanceChanged, "OfxActionBeginInstanceChanged"),
    S(kOfxActionEndInstanceChanged, "OfxActionEndInstanceChanged"),
    S(kOfxActionBeginInstanceEdit, "OfxActionBeginInstanceEdit"),
    S(kOfxActionEndInstanceEdit, "OfxActionEndInstanceEdit"),
    S(kOfxPropAPIVersion, "OfxPropAPIVersion"),
    S(kOfxPropType, "OfxPropType"),
    S(kOfxPropName, "OfxPropName"),
    S(kOfxPropLabel, "OfxPropLabel"),
    S(kOfxPropShortLabel, "OfxPropShortLabel"),
    S(kOfxPropLongLabel, "OfxPropLongLabel"),
    S(kOfxPropVersion, "OfxPropVersion"),
    S(kOfxPropVersionLabel, "OfxPropVersionLabel"),
    S(kOfxPropPluginDescription, "OfxPropPluginDescription"),
    S(kOfxPropTime, "OfxPropTime"),
    S(kOfxPropIsInteractive, "OfxPropIsInteractive"),
    S(kOfxPropInstanceData, "OfxPropInstanceData"),
    S(kOfxPropChangeReason, "OfxPropChangeReason"),
    S(kOfxPropEffectInstance, "OfxPropEffectInstance"),
    S(kOfxChangeUserEdited, "OfxChangeUserEdited"),
    S(kOfxChangePluginEdited, "OfxChangePluginEdited"),
    S(kOfxChangeTime, "OfxChangeTime"),
    S(kOfxTypeImageEffectHost, "OfxTypeImageEffectHost"),
    S(kOfxTypeImageEffect, "OfxTypeImageEffect"),
    S(kOfxTypeImageEffectInstance, "OfxTypeImageEffectInstance"),
    S(kOfxTypeParameter, "OfxTypeParameter"),
    S(kOfxTypeParameterInstance, "OfxTypeParameterInstance"),
    S(kOfxTypeClip, "OfxTypeClip"),
    S(kOfxTypeImage, "OfxTypeImage"),
    S(kOfxPropertySuite, "OfxPropertySuite"),
    S(kOfxImageEffectPluginApi, "OfxImageEffectPluginAPI"),
    S(kOfxImageEffectSuite, "OfxImageEffectSuite"),
    S(kOfxImageEffectActionGetRegionOfDefinition, "OfxImageEffectActionGetRegionOfDefinition"),
    S(kOfxImageEffectActionGetRegionsOfInterest, "OfxImageEffectActionGetRegionsOfInterest"),
    S(kOfxImageEffectActionGetTimeDomain, "OfxImageEffectActionGetTimeDomain"),
    S(kOfxImageEffectActionGetFramesNeeded, "OfxImageEffectActionGetFramesNeeded"),
    S(kOfxImageEffectActionGetClipPreferences, "OfxImageEffectActionGetClipPreferences"),
    S(kOfxImageEffectActionIsIdentity, "OfxImageEffectActionIsIdentity"),
    S(kOfxImageEffectActionRender, "OfxImageEffectActionRender"),
    S(kOfxImageEffectActionBeginSequenceRender, "OfxImageEffectActionBeginSequenceRender"),
    S(kOfxImageEffectActionEndSequenceRender, "OfxImageEffectActionEndSequenceRender"),
    S(kOfxImageEffectActionDescribeInContext, "OfxImageEffectActionDescribeInContext"),
    S(kOfxImageEffectContextGenerator, "OfxImageEffectContextGenerator"),
    S(kOfxImageEffectContextFilter, "OfxImageEffectContextFilter"),
    S(kOfxImageEffectContextTransition, "OfxImageEffectContextTransition"),
    S(kOfxImageEffectContextPaint, "OfxImageEffectContextPaint"),
    S(kOfxImageEffectContextGeneral, "OfxImageEffectContextGeneral"),
    S(kOfxImageEffectContextRetimer, "OfxImageEffectContextRetimer"),
    S(kOfxImageEffectOutputClipName, "Output"),
    S(kOfxImageEffectSimpleSourceClipName, "Source"),
    S(kOfxImageComponentNone, "OfxImageComponentNone"),
    S(kOfxImageComponentRGBA, "OfxImageComponentRGBA"),
    S(kOfxImageComponentRGB, "OfxImageComponentRGB"),
    S(kOfxImageComponentAlpha, "OfxImageComponentAlpha"),
    S(kOfxBitDepthNone, "OfxBitDepthNone"),
    S(kOfxBitDepthByte, "OfxBitDepthByte"),
    S(kOfxBitDepthShort, "OfxBitDepthShort"),
    S(kOfxBitDepthHalf, "OfxBitDepthHalf"),
    S(kOfxBitDepthFloat, "OfxBitDepthFloat"),
    S(kOfxImageOpaque, "OfxImageOpaque"),
    S(kOfxImagePreMultiplied, "OfxImageAlphaPremultiplied"),
    S(kOfxImageUnPreMultiplied, "OfxImageAlphaUnPremultiplied"),
    S(kOfxImageFieldNone, "OfxFieldNone"),
    S(kOfxImageFieldBoth, "OfxFieldBoth"),
    S(kOfxImageEffectRenderUnsafe, "OfxImageEffectRenderUnsafe"),
    S(kOfxImageEffectRenderInstanceSafe, "OfxImageEffectRenderInstanceSafe"),
    S(kOfxImageEffectRenderFullySafe, "OfxImageEffectRenderFullySafe"),
    S(kOfxImageEffectHostPropIsBackground, "OfxImageEffectHostPropIsBackground"),
    S(kOfxImageEffectPropSupportsOverlays, "OfxImageEffectPropSupportsOverlays"),
    S(kOfxImageEffectPropSupportsMultiResolution, "OfxImageEffectPropSupportsMultiResolution"),
    S(kOfxImageEffectPropSupportsTiles, "OfxImageEffectPropSupportsTiles"),
    S(kOfxImageEffectPropTemporalClipAccess, "OfxImageEffectPropTemporalClipAccess"),
    S(kOfxImageEffectPropSupportedContexts, "OfxImageEffectPropSupportedContexts"),
    S(kOfxImageEffectPropSupportedPixelDepths, "OfxImageEffectPropSupportedPixelDepths"),
    S(kOfxImageEffectPropSupportedComponents, "OfxImageEffectPropSupportedComponents"),
    S(kOfxImageEffectPropSupportsMultipleClipDepths, "OfxImageEffectPropMultipleClipDepths"),
    S(kOfxImageEffectPropSupportsMultipleClipPARs, "OfxImageEffectPropSupportsMultipleClipPARs"),
    S(kOfxImageEffectPropSetableFrameRate, "OfxImageEffectPropSetableFrameRate"),
    S(kOfxImageEffectPropSetableFielding, "OfxImageEffectPropSetableFielding"),
    S(kOfxImageEffectPluginPropGrouping, "OfxImageEffectPluginPropGrouping"),
    S(kOfxImageEffectPluginPropSingleInstance, "OfxImageEffectPluginPropSingleInstance"),
    S(kOfxImageEffectPluginRenderThreadSafety, "OfxImageEffectPluginRenderThreadSafety"),
    S(kOfxImageEffectPluginPropHostFrameThreading, "OfxImageEffectPluginPropHostFrameThreading"),
    S(kOfxImageEffectPluginPropFieldRenderTwiceAlways, "OfxImageEffectPluginPropFieldRenderTwiceAlways"),
    S(kOfxImageEffectPropClipPreferencesSlaveParam, "OfxImageEffectPropClipPreferencesSlaveParam"),
    S(kOfxImageEffectPropContext, "OfxImageEffectPropContext"),
    S(kOfxImageEffectPropPluginHandle, "OfxImageEffectPropPluginHandle"),
    S(kOfxImageEffectPropProjectSize, "OfxImageEffectPropProjectSize"),
    S(kOfxImageEffectPropProjectOffset, "OfxImageEffectPropProjectOffset"),
    S(kOfxImageEffectPropProjectExtent, "OfxImageEffectPropProjectExtent"),
    S(kOfxImageEffectPropProjectPixelAspectRatio, "OfxImageEffectPropPixelAspectRatio"),
    S(kOfxImageEffectInstancePropEffectDuration, "OfxImageEffectInstancePropEffectDuration"),
    S(kOfxImageEffectInstancePropSequentialRender, "OfxImageEffectInstancePropSequentialRender"),
    S(kOfxImageEffectPropFrameRate, "OfxImageEffectPropFrameRate"),
    S(kOfxImageEffectPropOpenGLRenderSupported, "OfxImageEffectPropOpenGLRenderSupported"),
    S(kOfxImageClipPropOptional, "OfxImageClipPropOptional"),
    S(kOfxImageClipPropIsMask, "OfxImageClipPropIsMask"),
    S(kOfxImageClipPropConnected, "OfxImageClipPropConnected"),
    S(kOfxImageClipPropUnmappedComponents, "OfxImageClipPropUnmappedComponents"),
    S(kOfxImageClipPropUnmappedPixelDepth, "OfxImageClipPropUnmappedPixelDepth"),
    S(kOfxImageClipPropFieldExtraction, "OfxImageClipPropFieldExtraction"),
    S(kOfxImageClipPropContinuousSamples, "OfxImageClipPropContinuousSamples"),
    S(kOfxImageEffectPropComponents, "OfxImageEffectPropComponents"),
    S(kOfxImageEffectPropPixelDepth, "OfxImageEffectPropPixelDepth"),
    S(kOfxImageEffectPropPreMultiplication, "OfxImageEffectPropPreMultiplication"),
    S(kOfxImageEffectFrameVarying, "OfxImageEffectFrameVarying"),
    S(kOfxImagePropPixelAspectRatio, "OfxImagePropPixelAspectRatio"),
    S(kOfxImagePropData, "OfxImagePropData"),
    S(kOfxImagePropBounds, "OfxImagePropBounds"),
    S(kOfxImagePropRegionOfDefinition, "OfxImagePropRegionOfDefinition"),
    S(kOfxImagePropRowBytes, "OfxImagePropRowBytes"),
    S(kOfxImagePropField, "OfxImagePropField"),
    S(kOfxImagePropUniqueIdentifier, "OfxImagePropUniqueIdentifier"),
    S(kOfxImageEffectPropRenderScale, "OfxImageEffectPropRenderScale"),
    S(kOfxImageEffectPropRenderWindow, "OfxImageEffectPropRenderWindow"),
    S(kOfxImageEffectPropFieldToRender, "OfxImageEffectPropFieldToRender"),
    S(kOfxImageEffectPropRegionOfDefinition, "OfxImageEffectPropRegionOfDefinition"),
    S(kOfxImageEffectPropRegionOfInterest, "OfxImageEffectPropRegionOfInterest"),
    S(kOfxImageEffectPropSequentialRenderStatus, "OfxImageEffectPropSequentialRenderStatus"),
    S(kOfxImageEffectPropInteractiveRenderStatus, "OfxImageEffectPropInteractiveRenderStatus"),
    S(kOfxImageEffectPropFrameRange, "OfxImageEffectPropFrameRange"),
    S(kOfxImageEffectPropFrameStep, "OfxImageEffectPropFrameStep"),
    S(kOfxImageClipPropRoI, "OfxImageClipPropRoI_"),
    S(kOfxImageClipPropComponentsPrefix, "OfxImageClipPropComponents_"),
    S(kOfxImageClipPropDepthPrefix, "OfxImageClipPropDepth_"),
    S(kOfxImageClipPropPARPrefix, "OfxImageClipPropPAR_"),
    S(kOfxImageClipPropPreferredColourspacesPrefix, "OfxImageClipPropPreferredColourspaces_"),
    S(kOfxImageEffectPropColourManagementStyle, "OfxImageEffectPropColourManagementStyle"),
    S(kOfxImageEffectColourManagementNone, "OfxImageEffectColourManagementNone"),
    S(kOfxImageEffectColourManagementBasic, "OfxImageEffectColourManagementBasic"),
    S(kOfxImageEffectColourManagementCore, "OfxImageEffectColourManagementCore"),
    S(kOfxImageEffectColourManagementFull, "OfxImageEffectColourManagementFull"),
    S(kOfxImageEffectColourManagementOCIO, "OfxImageEffectColourManagementOCIO"),
    S(kOfxImageEffectPropColourManagementAvailableConfigs, "OfxImageEffectPropColourManagementAvailableConfigs"),
    S(kOfxImageEffectActionGetOutputColourspace, "OfxImageEffectActionGetOutputColourspace"),
    S(kOfxImageClipPropColourspace, "OfxImageClipPropColourspace"),
    S(kOfxImageClipPropPreferredColourspaces, "OfxImageClipPropPreferredColourspaces"),
    S(kOfxConfigIdentifier, "ofx-native-v1.5_aces-v1.3_ocio-v2.3"),
    S(kOfxColourspaceOfxRaw, "ofx_raw"),
    S(kOfxColourspaceClipPrefix, "OfxColourspace_"),
    S(kOfxParameterSuite, "OfxParameterSuite"),
    S(kOfxParamTypeInteger, "OfxParamTypeInteger"),
    S(kOfxParamTypeDouble, "OfxParamTypeDouble"),
    S(kOfxParamTypeBoolean, "OfxParamTypeBoolean"),
    S(kOfxParamTypeChoice, "OfxParamTypeChoice"),
    S(kOfxParamTypeString, "OfxParamTypeString"),
    S(kOfxParamTypeRGB, "OfxParamTypeRGB"),
    S(kOfxParamTypeGroup, "OfxParamTypeGroup"),
    S(kOfxParamTypePage, "OfxParamTypePage"),
    S(kOfxParamPropType, "OfxParamPropType"),
    S(kOfxParamPropScriptName, "OfxParamPropScriptName"),
    S(kOfxParamPropHint, "OfxParamPropHint"),
    S(kOfxParamPropDefault, "OfxParamPropDefault"),
    S(kOfxParamPropAnimates, "OfxParamPropAnimates"),
    S(kOfxParamPropEnabled, "OfxParamPropEnabled"),
    S(kOfxParamPropSecret, "OfxParamPropSecret"),
    S(kOfxParamPropParent, "OfxParamPropParent"),
    S(kOfxParamPropEvaluateOnChange, "OfxParamPropEvaluateOnChange"),
    S(kOfxParamPropMin, "OfxParamPropMin"),
    S(kOfxParamPropMax, "OfxParamPropMax"),
    S(kOfxParamPropDisplayMin, "OfxParamPropDisplayMin"),
    S(kOfxParamPropDisplayMax, "OfxParamPropDisplayMax"),
    S(kOfxParamPropIncrement, "OfxParamPropIncrement"),
    S(kOfxParamPropDigits, "OfxParamPropDigits"),
    S(kOfxParamPropDoubleType, "OfxParamPropDoubleType"),
    S(kOfxParamDoubleTypePlain, "OfxParamDoubleTypePlain"),
    S(kOfxParamDoubleTypeAngle, "OfxParamDoubleTypeAngle"),
    S(kOfxParamPropChoiceOption, "OfxParamPropChoiceOption"),
    S(kOfxParamPropStringMode, "OfxParamPropStringMode"),
    S(kOfxParamStringIsSingleLine, "OfxParamStringIsSingleLine"),
    S(kOfxParamStringIsFilePath, "OfxParamStringIsFilePath"),
    S(kOfxParamPropStringFilePathExists, "OfxParamPropStringFilePathExists"),
    S(kOfxParamPropGroupOpen, "OfxParamPropGroupOpen"),
    S(kOfxParamPropPageChild, "OfxParamPropPageChild"),
    S(kOfxMessageSuite, "OfxMessageSuite"),
    S(kOfxMessageFatal, "OfxMessageFatal"),
    S(kOfxMessageError, "OfxMessageError"),
    S(kOfxMessageWarning, "OfxMessageWarning"),
    S(kOfxMessageMessage, "OfxMessageMessage"),
    S(kOfxMessageLog, "OfxMessageLog"),
    S(kOfxMessageQuestion, "OfxMessageQuestion"),
};

const IntConstant kInts[] = {
    I(kOfxStatOK, 0),
    I(kOfxStatFailed, 1),
    I(kOfxStatErrFatal, 2),
    I(kOfxStatErrUnknown, 3),
    I(kOfxStatErrMissingHostFeature, 4),
    I(kOfxStatErrUnsupported, 5),
    I(kOfxStatErrExists, 6),
    I(kOfxStatErrFormat, 7),
    I(kOfxStatErrMemory, 8),
    I(kOfxStatErrBadHandle, 9),
    I(kOfxStatErrBadIndex, 10),
    I(kOfxStatErrValue, 11),
    I(kOfxStatReplyYes, 12),
    I(kOfxStatReplyNo, 13),
    I(kOfxStatReplyDefault, 14),
    I(kOfxImageEffectPluginApiVersion, 1),
    I(kOfxFlagInfiniteMax, INT_MAX),
    I(kOfxFlagInfiniteMin, INT_MIN),
};

#undef S
#undef I

TEST(OfxApi, EveryStringIsTheSpecifications) {
    for (const StringConstant& c : kStrings) EXPECT_STREQ(c.header, c.spec) << c.name;
}

TEST(OfxApi, EveryNumberIsTheSpecifications) {
    for (const IntConstant& c : kInts) EXPECT_EQ(c.header, c.spec) << c.name;
}

// Every constant the header defines is in one of the tables above, so none goes unchecked.
TEST(OfxApi, TablesCoverEveryConstantOfTheHeader) {
    std::ifstream in(OBSCURA_OFX_API_HEADER);
    ASSERT_TRUE(in) << OBSCURA_OFX_API_HEADER;
    std::stringstream text;
    text << in.rdbuf();
    const std::string src = text.str();
    std::set<std::string> checked;
    for (const StringConstant& c : kStrings) checked.insert(c.name);
    for (const IntConstant& c : kInts) checked.insert(c.name);
    const std::regex define(R"(#define\s+(k\w+))");
    int found = 0;
    for (auto it = std::sregex_iterator(src.begin(), src.end(), define); it != std::sregex_iterator(); ++it, ++found)
        EXPECT_TRUE(checked.count((*it)[1].str())) << (*it)[1].str() << " is not checked against the specification";
    EXPECT_EQ(found, (int)checked.size());
}

// Layouts: each suite is a struct of function pointers in the specification's order, with
// its signatures. Offsets are in pointer slots; the types are written out independently.
constexpr size_t P = sizeof(void*);
template <class A, class B>
constexpr bool same = std::is_same_v<A, B>;
// Member m of suite S is its n-th function pointer.
#define SLOT(S, m, n) EXPECT_EQ(offsetof(S, m), (n) * P) << #m

TEST(OfxApi, PlainStructsHaveTheSpecificationsLayout) {
    EXPECT_EQ(sizeof(OfxRectI), 4 * sizeof(int));
    EXPECT_EQ(sizeof(OfxRectD), 4 * sizeof(double));
    EXPECT_EQ(offsetof(OfxRectD, y2), 3 * sizeof(double));
    EXPECT_EQ(sizeof(OfxPointD), 2 * sizeof(double));
    EXPECT_EQ(sizeof(OfxPointI), 2 * sizeof(int));
    EXPECT_EQ(sizeof(OfxRangeD), 2 * sizeof(double));
    EXPECT_TRUE((same<OfxTime, double> && same<OfxStatus, int>));

    EXPECT_EQ(offsetof(OfxHost, host), 0u);
    EXPECT_EQ(offsetof(OfxHost, fetchSuite), P);
    EXPECT_EQ(sizeof(OfxHost), 2 * P);
    EXPECT_TRUE((same<decltype(OfxHost::fetchSuite), const void* (*)(OfxPropertySetHandle, const char*, int)>));

    // const char*, int, const char*, unsigned, unsigned, setHost, mainEntry (LP64: 48 bytes).
    EXPECT_EQ(offsetof(OfxPlugin, pluginApi), 0u);
    EXPECT_EQ(offsetof(OfxPlugin, apiVersion), P);
    EXPECT_EQ(offsetof(OfxPlugin, pluginIdentifier), 2 * P);
    EXPECT_EQ(offsetof(OfxPlugin, pluginVersionMajor), 3 * P);
    EXPECT_EQ(offsetof(OfxPlugin, pluginVersionMinor), 3 * P + sizeof(unsigned));
    EXPECT_EQ(offsetof(OfxPlugin, setHost), 4 * P);
    EXPECT_EQ(offsetof(OfxPlugin, mainEntry), 5 * P);
    EXPECT_EQ(sizeof(OfxPlugin), 6 * P);
    EXPECT_TRUE((same<decltype(OfxPlugin::setHost), void (*)(OfxHost*)>));
    EXPECT_TRUE((same<decltype(OfxPlugin::mainEntry),
                      OfxStatus (*)(const char*, const void*, OfxPropertySetHandle, OfxPropertySetHandle)>));
}

TEST(OfxApi, ImageEffectSuiteIsThirteenEntriesOf104Bytes) {
    using S = OfxImageEffectSuiteV1;
    using E = OfxImageEffectHandle;
    using PS = OfxPropertySetHandle;
    using C = OfxImageClipHandle;
    using M = OfxImageMemoryHandle;
    EXPECT_EQ(sizeof(S), 13 * P);
    SLOT(S, getPropertySet, 0); SLOT(S, getParamSet, 1); SLOT(S, clipDefine, 2); SLOT(S, clipGetHandle, 3);
    SLOT(S, clipGetPropertySet, 4); SLOT(S, clipGetImage, 5); SLOT(S, clipReleaseImage, 6);
    SLOT(S, clipGetRegionOfDefinition, 7); SLOT(S, abort, 8); SLOT(S, imageMemoryAlloc, 9);
    SLOT(S, imageMemoryFree, 10); SLOT(S, imageMemoryLock, 11); SLOT(S, imageMemoryUnlock, 12);
    EXPECT_TRUE((same<decltype(S::getPropertySet), OfxStatus (*)(E, PS*)>));
    EXPECT_TRUE((same<decltype(S::getParamSet), OfxStatus (*)(E, OfxParamSetHandle*)>));
    EXPECT_TRUE((same<decltype(S::clipDefine), OfxStatus (*)(E, const char*, PS*)>));
    EXPECT_TRUE((same<decltype(S::clipGetHandle), OfxStatus (*)(E, const char*, C*, PS*)>));
    EXPECT_TRUE((same<decltype(S::clipGetPropertySet), OfxStatus (*)(C, PS*)>));
    EXPECT_TRUE((same<decltype(S::clipGetImage), OfxStatus (*)(C, OfxTime, const OfxRectD*, PS*)>));
    EXPECT_TRUE((same<decltype(S::clipReleaseImage), OfxStatus (*)(PS)>));
    EXPECT_TRUE((same<decltype(S::clipGetRegionOfDefinition), OfxStatus (*)(C, OfxTime, OfxRectD*)>));
    EXPECT_TRUE((same<decltype(S::abort), int (*)(E)>));
    EXPECT_TRUE((same<decltype(S::imageMemoryAlloc), OfxStatus (*)(E, size_t, M*)>));
    EXPECT_TRUE((same<decltype(S::imageMemoryFree), OfxStatus (*)(M)>));
    EXPECT_TRUE((same<decltype(S::imageMemoryLock), OfxStatus (*)(M, void**)>));
    EXPECT_TRUE((same<decltype(S::imageMemoryUnlock), OfxStatus (*)(M)>));
}

TEST(OfxApi, PropertySuiteIsEighteenEntries) {
    using S = OfxPropertySuiteV1;
    using PS = OfxPropertySetHandle;
    EXPECT_EQ(sizeof(S), 18 * P);
    SLOT(S, propSetPointer, 0); SLOT(S, propSetString, 1); SLOT(S, propSetDouble, 2); SLOT(S, propSetInt, 3);
    SLOT(S, propSetPointerN, 4); SLOT(S, propSetStringN, 5); SLOT(S, propSetDoubleN, 6); SLOT(S, propSetIntN, 7);
    SLOT(S, propGetPointer, 8); SLOT(S, propGetString, 9); SLOT(S, propGetDouble, 10); SLOT(S, propGetInt, 11);
    SLOT(S, propGetPointerN, 12); SLOT(S, propGetStringN, 13); SLOT(S, propGetDoubleN, 14);
    SLOT(S, propGetIntN, 15); SLOT(S, propReset, 16); SLOT(S, propGetDimension, 17);
    EXPECT_TRUE((same<decltype(S::propSetPointer), OfxStatus (*)(PS, const char*, int, void*)>));
    EXPECT_TRUE((same<decltype(S::propSetString), OfxStatus (*)(PS, const char*, int, const char*)>));
    EXPECT_TRUE((same<decltype(S::propSetDouble), OfxStatus (*)(PS, const char*, int, double)>));
    EXPECT_TRUE((same<decltype(S::propSetInt), OfxStatus (*)(PS, const char*, int, int)>));
    EXPECT_TRUE((same<decltype(S::propSetPointerN), OfxStatus (*)(PS, const char*, int, void* const*)>));
    EXPECT_TRUE((same<decltype(S::propSetStringN), OfxStatus (*)(PS, const char*, int, const char* const*)>));
    EXPECT_TRUE((same<decltype(S::propSetDoubleN), OfxStatus (*)(PS, const char*, int, const double*)>));
    EXPECT_TRUE((same<decltype(S::propSetIntN), OfxStatus (*)(PS, const char*, int, const int*)>));
    EXPECT_TRUE((same<decltype(S::propGetPointer), OfxStatus (*)(PS, const char*, int, void**)>));
    EXPECT_TRUE((same<decltype(S::propGetString), OfxStatus (*)(PS, const char*, int, char**)>));
    EXPECT_TRUE((same<decltype(S::propGetDouble), OfxStatus (*)(PS, const char*, int, double*)>));
    EXPECT_TRUE((same<decltype(S::propGetInt), OfxStatus (*)(PS, const char*, int, int*)>));
    EXPECT_TRUE((same<decltype(S::propGetPointerN), OfxStatus (*)(PS, const char*, int, void**)>));
    EXPECT_TRUE((same<decltype(S::propGetStringN), OfxStatus (*)(PS, const char*, int, char**)>));
    EXPECT_TRUE((same<decltype(S::propGetDoubleN), OfxStatus (*)(PS, const char*, int, double*)>));
    EXPECT_TRUE((same<decltype(S::propGetIntN), OfxStatus (*)(PS, const char*, int, int*)>));
    EXPECT_TRUE((same<decltype(S::propReset), OfxStatus (*)(PS, const char*)>));
    EXPECT_TRUE((same<decltype(S::propGetDimension), OfxStatus (*)(PS, const char*, int*)>));
}

TEST(OfxApi, ParameterAndMessageSuites) {
    using S = OfxParameterSuiteV1;
    using H = OfxParamHandle;
    using PSet = OfxParamSetHandle;
    using PS = OfxPropertySetHandle;
    EXPECT_EQ(sizeof(S), 18 * P);
    SLOT(S, paramDefine, 0); SLOT(S, paramGetHandle, 1); SLOT(S, paramSetGetPropertySet, 2);
    SLOT(S, paramGetPropertySet, 3); SLOT(S, paramGetValue, 4); SLOT(S, paramGetValueAtTime, 5);
    SLOT(S, paramGetDerivative, 6); SLOT(S, paramGetIntegral, 7); SLOT(S, paramSetValue, 8);
    SLOT(S, paramSetValueAtTime, 9); SLOT(S, paramGetNumKeys, 10); SLOT(S, paramGetKeyTime, 11);
    SLOT(S, paramGetKeyIndex, 12); SLOT(S, paramDeleteKey, 13); SLOT(S, paramDeleteAllKeys, 14);
    SLOT(S, paramCopy, 15); SLOT(S, paramEditBegin, 16); SLOT(S, paramEditEnd, 17);
    EXPECT_TRUE((same<decltype(S::paramDefine), OfxStatus (*)(PSet, const char*, const char*, PS*)>));
    EXPECT_TRUE((same<decltype(S::paramGetHandle), OfxStatus (*)(PSet, const char*, H*, PS*)>));
    EXPECT_TRUE((same<decltype(S::paramSetGetPropertySet), OfxStatus (*)(PSet, PS*)>));
    EXPECT_TRUE((same<decltype(S::paramGetPropertySet), OfxStatus (*)(H, PS*)>));
    EXPECT_TRUE((same<decltype(S::paramGetValue), OfxStatus (*)(H, ...)>));
    EXPECT_TRUE((same<decltype(S::paramGetValueAtTime), OfxStatus (*)(H, OfxTime, ...)>));
    EXPECT_TRUE((same<decltype(S::paramGetDerivative), OfxStatus (*)(H, OfxTime, ...)>));
    EXPECT_TRUE((same<decltype(S::paramGetIntegral), OfxStatus (*)(H, OfxTime, OfxTime, ...)>));
    EXPECT_TRUE((same<decltype(S::paramSetValue), OfxStatus (*)(H, ...)>));
    EXPECT_TRUE((same<decltype(S::paramSetValueAtTime), OfxStatus (*)(H, OfxTime, ...)>));
    EXPECT_TRUE((same<decltype(S::paramGetNumKeys), OfxStatus (*)(H, unsigned int*)>));
    EXPECT_TRUE((same<decltype(S::paramGetKeyTime), OfxStatus (*)(H, unsigned int, OfxTime*)>));
    EXPECT_TRUE((same<decltype(S::paramGetKeyIndex), OfxStatus (*)(H, OfxTime, int, int*)>));
    EXPECT_TRUE((same<decltype(S::paramDeleteKey), OfxStatus (*)(H, OfxTime)>));
    EXPECT_TRUE((same<decltype(S::paramDeleteAllKeys), OfxStatus (*)(H)>));
    EXPECT_TRUE((same<decltype(S::paramCopy), OfxStatus (*)(H, H, OfxTime, const OfxRangeD*)>));
    EXPECT_TRUE((same<decltype(S::paramEditBegin), OfxStatus (*)(PSet, const char*)>));
    EXPECT_TRUE((same<decltype(S::paramEditEnd), OfxStatus (*)(PSet)>));

    EXPECT_EQ(sizeof(OfxMessageSuiteV1), 1 * P);
    EXPECT_TRUE((same<decltype(OfxMessageSuiteV1::message), OfxStatus (*)(void*, const char*, const char*, const char*, ...)>));
}

#undef SLOT

} // namespace
