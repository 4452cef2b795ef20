// obscura as an OpenFX image effect (General context): an adapter from OFX clips, parameters
// and render windows to the operator (core/operator.h). This file is the plugin's entry: the
// two exported functions, and the main entry that hands each action to the file of its
// concern (ofx_actions.h) and turns what it throws into the host's status.
#include "ofx_actions.h"

#include "ofx_instance.h"
#include "ofx_names.h"
#include "ofx_suites.h"

#include <cstring>
#include <exception>
#include <mutex>
#include <new>
#include <string>

#define OBSCURA_OFX_EXPORT extern "C" __attribute__((visibility("default")))

namespace obscura::ofx {

namespace {

// Tells the host the instance's message as it is now (its error, else its warning, else none),
// again if another thread changed it meanwhile, so the node ends showing the last decision. The
// host is called with no lock held: a host may show a message on its UI thread and wait for it.
void publishMessage(OfxImageEffectHandle effect, Instance& in) {
    for (;;) {
        std::string error, warning;
        unsigned long version = 0;
        {
            std::lock_guard<std::mutex> lock(in.messageMutex);
            error = in.shownError;
            warning = in.shownWarning;
            version = in.messageVersion;
        }
        if (!error.empty()) postMessage(effect, kOfxMessageError, error);
        else if (!warning.empty()) postMessage(effect, kOfxMessageWarning, warning);
        else clearPersistentMessage(effect);
        std::lock_guard<std::mutex> lock(in.messageMutex);
        if (in.messageVersion == version) return;
    }
}

// Sets what the instance shows and tells the host when it changed: a message is shown once however
// many tiles and actions meet it.
void setShown(OfxImageEffectHandle effect, Instance& in, const std::string& error, const std::string& warning) {
    {
        std::lock_guard<std::mutex> lock(in.messageMutex);
        if (in.shownError == error && in.shownWarning == warning) return;
        in.shownError = error;
        in.shownWarning = warning;
        ++in.messageVersion;
    }
    publishMessage(effect, in);
}

// An instance's error is kept until a render succeeds; a descriptor's (no instance yet) is shown
// each time.
void showError(OfxImageEffectHandle effect, const std::string& text) {
    Instance* in = findInstance(effect);
    if (!in) return postTransientMessage(effect, kOfxMessageError, text);
    std::string warning;
    {
        std::lock_guard<std::mutex> lock(in->messageMutex);
        warning = in->shownWarning;
    }
    setShown(effect, *in, text, warning);
}

// A render that finished clears the error and shows its warning, if any; one the host aborted
// leaves the node's message as it was.
OfxStatus render(OfxImageEffectHandle effect, OfxPropertySetHandle inArgs) {
    std::optional<std::string> warning;
    const OfxStatus status = onRender(effect, inArgs, warning);
    if (status != kOfxStatOK || !warning) return status;
    if (Instance* in = findInstance(effect)) setShown(effect, *in, "", *warning);
    return status;
}

// Each action by name; kOfxStatReplyDefault for those the plugin leaves to the host.
OfxStatus dispatch(const char* action, OfxImageEffectHandle effect, OfxPropertySetHandle inArgs,
                   OfxPropertySetHandle outArgs) {
    if (!std::strcmp(action, kOfxActionLoad)) return fetchSuites();
    if (!suitesLoaded()) return kOfxStatErrMissingHostFeature;
    if (!std::strcmp(action, kOfxActionUnload)) return kOfxStatOK;
    if (!std::strcmp(action, kOfxActionDescribe)) return onDescribe(effect);
    if (!std::strcmp(action, kOfxImageEffectActionDescribeInContext)) return onDescribeInContext(effect, inArgs);
    if (!std::strcmp(action, kOfxActionCreateInstance)) return onCreateInstance(effect);
    if (!std::strcmp(action, kOfxActionDestroyInstance)) return onDestroyInstance(effect);
    if (!std::strcmp(action, kOfxActionInstanceChanged)) return onInstanceChanged(effect);
    if (!std::strcmp(action, kOfxImageEffectActionGetRegionOfDefinition))
        return onGetRegionOfDefinition(effect, inArgs, outArgs);
    if (!std::strcmp(action, kOfxImageEffectActionGetRegionsOfInterest))
        return onGetRegionsOfInterest(effect, inArgs, outArgs);
    if (!std::strcmp(action, kOfxImageEffectActionGetClipPreferences)) return onGetClipPreferences(effect, outArgs);
    if (!std::strcmp(action, kOfxImageEffectActionGetOutputColourspace)) return onGetOutputColourspace(effect, outArgs);
    if (!std::strcmp(action, kOfxImageEffectActionIsIdentity)) return onIsIdentity(effect, inArgs, outArgs);
    if (!std::strcmp(action, kOfxImageEffectActionRender)) return render(effect, inArgs);
    if (!std::strcmp(action, kOfxImageEffectActionBeginSequenceRender) ||
        !std::strcmp(action, kOfxImageEffectActionEndSequenceRender))
        return kOfxStatOK;
    return kOfxStatReplyDefault;
}

// Nothing escapes to the host: a failed suite call answers its status, an error is shown
// through the message suite (except while describing, before any instance exists).
OfxStatus mainEntry(const char* action, const void* handle, OfxPropertySetHandle inArgs, OfxPropertySetHandle outArgs) {
    OfxImageEffectHandle effect = (OfxImageEffectHandle)handle;
    try {
        return dispatch(action, effect, inArgs, outArgs);
    } catch (const OfxFailure& e) {
        // An action answers only the statuses ofxImageEffect.h lists for it: a host suite's own
        // (ErrBadHandle, ErrUnknown, ...) becomes Failed, with the message Failed asks for.
        if (e.status == kOfxStatErrMemory || e.status == kOfxStatErrFatal) return e.status;
        if (effect && std::strcmp(action, kOfxActionDescribe) != 0)
            showError(effect, "obscura: the host answered status " + std::to_string(e.status) + " to a call of " +
                                  action + "; the node could not run");
        return kOfxStatFailed;
    } catch (const std::bad_alloc&) {
        return kOfxStatErrMemory;
    } catch (const std::exception& e) {
        if (effect && std::strcmp(action, kOfxActionDescribe) != 0) showError(effect, std::string("obscura: ") + e.what());
        return kOfxStatFailed;
    } catch (...) {
        return kOfxStatFailed;
    }
}

void setHost(OfxHost* host) { gHost = host; }

OfxPlugin gPlugin = {kOfxImageEffectPluginApi, kOfxImageEffectPluginApiVersion, kPluginId, kVersionMajor,
                     kVersionMinor, setHost, mainEntry};

} // namespace

} // namespace obscura::ofx

OBSCURA_OFX_EXPORT int OfxGetNumberOfPlugins(void) { return 1; }

OBSCURA_OFX_EXPORT OfxPlugin* OfxGetPlugin(int nth) { return nth == 0 ? &obscura::ofx::gPlugin : nullptr; }
