// Renderer presets: which EXR layers hold depth, normals, ... and the conventions
// (depth kind, normal space) each renderer uses. All of it lives in one table in layers.cpp.
#pragma once
#include "core/settings.h"
#include "io/exr_file.h"

#include <map>
#include <string>
#include <vector>

namespace obscura {

enum class Role { Depth, Normal, Position, Beauty, Albedo, DirectDiffuse };

const char* roleName(Role);                         // "depth", "normal", ..., "direct-diffuse"
bool parseRole(const std::string&, Role&);
const std::vector<Role>& allRoles();

// Channel names of a deep file's sample depths, per renderer preset (--flat; docs/deep.md).
// The defaults are OpenEXR's standard names, which every renderer in layers.cpp's table writes.
struct DeepChannelNames {
    std::string z = "Z", zBack = "ZBack";  // zBack may be absent: point samples
};

struct LayerBinding {
    Role role = Role::Depth;
    int part = 0;
    std::string layer;                  // layer prefix ("" for top-level channels)
    std::vector<std::string> channels;  // full channel names: 1 for depth, X,Y,Z order for
                                        // vectors, R,G,B(,A) for colour
};

struct LayerPlan {
    std::string preset;                 // "blender", "arnold", "renderman", "vray", "karma", "generic"
    std::vector<LayerBinding> bindings; // only the roles found
    DepthKind depthKind = DepthKind::Planar;
    NormalSpace normalSpace = NormalSpace::World;
    float skyDepth = 1e9f;
    bool normalsLeftHanded = false;     // camera space looks down +z (RenderMan): caller flips z
    DeepChannelNames deep;              // the renderer's deep sample depths

    const LayerBinding* find(Role) const;
};

// Preset names accepted by planLayers, "auto" first.
const std::vector<std::string>& presetNames();

// preset "auto" picks the preset whose names (and header hints) match best.
// overrides: role -> a layer ("ViewLayer.Normal") or a channel ("Z"); an override naming
// nothing throws an Error listing the layers found.
LayerPlan planLayers(const ExrInfo& info, const std::string& preset,
                     const std::map<Role, std::string>& overrides = {});

// Throws Error naming the first missing role, the preset and the layers found.
void requireRoles(const LayerPlan&, const ExrInfo&, const std::vector<Role>&);

// Where a channel suffix sorts in a layer's display order: R, G, B, A, X, Y, Z, W in either case
// (Nuke's red, green, blue, alpha as R, G, B, A), then the rest, in their own order.
int channelOrder(const std::string& suffix);

// One layer of a file as --inspect lists it: channel suffixes in display order (R,G,B,A, X,Y,Z,
// then the rest), and the pixel type ("half", "float", "uint", or "mixed").
struct LayerSummary {
    int part = 0;
    std::string partName;                 // "" when the part has no name
    std::string name;                     // "ViewLayer.AO"; "" for top-level channels
    std::vector<std::string> channels;    // suffixes: "R", "G", "B"
    std::string type;
};
std::vector<LayerSummary> summariseLayers(const ExrInfo&);
// "layer (channels) type"; in a multipart file it starts with "part: ".
std::string layerLine(const LayerSummary&, bool multipart);
// Every layer's line, for --inspect and error messages.
std::vector<std::string> listLayers(const ExrInfo&);

// The binding's channels as references for readExrChannels.
std::vector<ChannelRef> channelRefs(const LayerBinding&);

} // namespace obscura
