// The actions the entry point (ofx_actions.cpp) hands a host's call to, each defined in the
// file of its concern.
#pragma once
#include "ofx_api.h"

#include <optional>
#include <string>

namespace obscura::ofx {

// ofx_describe.cpp: the plugin, then its clips and parameters in the General context.
OfxStatus onDescribe(OfxImageEffectHandle effect);
OfxStatus onDescribeInContext(OfxImageEffectHandle effect, OfxPropertySetHandle inArgs);

// ofx_instance.cpp: an instance's handles, and the controls its choices grey out.
OfxStatus onCreateInstance(OfxImageEffectHandle effect);
OfxStatus onDestroyInstance(OfxImageEffectHandle effect);
OfxStatus onInstanceChanged(OfxImageEffectHandle effect);

// ofx_coords.cpp: where the output exists, and what each clip is read over.
OfxStatus onGetRegionOfDefinition(OfxImageEffectHandle effect, OfxPropertySetHandle inArgs,
                                  OfxPropertySetHandle outArgs);
OfxStatus onGetRegionsOfInterest(OfxImageEffectHandle effect, OfxPropertySetHandle inArgs,
                                 OfxPropertySetHandle outArgs);

// ofx_clip_prefs.cpp: depths, premultiplication, colourspaces, and the identity.
OfxStatus onGetClipPreferences(OfxImageEffectHandle effect, OfxPropertySetHandle outArgs);
OfxStatus onGetOutputColourspace(OfxImageEffectHandle effect, OfxPropertySetHandle outArgs);
OfxStatus onIsIdentity(OfxImageEffectHandle effect, OfxPropertySetHandle inArgs, OfxPropertySetHandle outArgs);

// ofx_render.cpp: one render window; `warning`: what the node should show after it ("" for
// nothing, e.g. that the Source clip held NaN values; unset where the host aborted the render).
OfxStatus onRender(OfxImageEffectHandle effect, OfxPropertySetHandle inArgs, std::optional<std::string>& warning);

} // namespace obscura::ofx
