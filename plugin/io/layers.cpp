#include "io/layers.h"

#include "base/error.h"

#include <OpenEXR/ImfStringAttribute.h>

#include <algorithm>
#include <cctype>

namespace obscura {
namespace {

// ---------------------------------------------------------------------------
// THE table of renderer conventions. Names are layer prefixes ("" = top-level
// R,G,B,A) or bare channel names (depth). Candidates are tried in order.
// ---------------------------------------------------------------------------
struct RoleNames {
    Role role;
    std::vector<std::string> names;
};
struct Preset {
    const char* name;
    DepthKind depth;
    NormalSpace normals;
    bool leftHanded;        // camera space looks down +z
    bool viewLayerPrefix;   // layers are "<anything>.<name>" (Blender's view layer)
    const char* hint;       // header attribute name (or software value) token
    std::vector<RoleNames> roles;
    // Deep output's sample depths: every renderer here writes OpenEXR's standard names (the
    // default); a renderer that differs gives its names at the end of its row.
    DeepChannelNames deep = {};
};

const std::vector<Preset>& presetTable() {
    using R = Role;
    static const std::vector<Preset> table = {
        // Generic first: it wins ties, so a specific preset needs specific evidence.
        {"generic", DepthKind::Planar, NormalSpace::World, false, false, "",
         {{R::Depth, {"Z", "depth", "Depth"}}, {R::Normal, {"N", "normal"}}, {R::Position, {"P"}},
          {R::Beauty, {""}}, {R::Albedo, {"albedo"}}, {R::DirectDiffuse, {}}}},
        // Blender: planar depth (radial only for panoramic cameras), world normals, sky 1e10.
        {"blender", DepthKind::Planar, NormalSpace::World, false, true, "blender",
         {{R::Depth, {"Depth"}}, {R::Normal, {"Normal"}}, {R::Position, {"Position"}},
          {R::Beauty, {"Combined"}}, {R::Albedo, {"DiffCol", "Diffuse Color"}},
          {R::DirectDiffuse, {"DiffDir", "Diffuse Direct"}}}},
        {"arnold", DepthKind::Planar, NormalSpace::World, false, false, "arnold",
         {{R::Depth, {"Z"}}, {R::Normal, {"N"}}, {R::Position, {"P"}}, {R::Beauty, {"", "RGBA"}},
          {R::Albedo, {"albedo", "diffuse_albedo"}}, {R::DirectDiffuse, {"diffuse_direct"}}}},
        // RenderMan: Nn in camera ("current") space, left-handed, +z forward. P is camera
        // space, so only the world-space __Pworld is bound as position.
        {"renderman", DepthKind::Planar, NormalSpace::Camera, true, false, "renderman",
         {{R::Depth, {"z"}}, {R::Normal, {"Nn"}}, {R::Position, {"__Pworld"}}, {R::Beauty, {"Ci"}},
          {R::Albedo, {"albedo"}}, {R::DirectDiffuse, {"directDiffuse"}}}},
        // V-Ray: raw Z only; VRayZDepth is remapped for display and never used.
        {"vray", DepthKind::Planar, NormalSpace::Camera, false, false, "vray",
         {{R::Depth, {"Z"}}, {R::Normal, {"VRayNormals"}}, {R::Position, {"VRaySamplerInfo"}},
          {R::Beauty, {""}}, {R::Albedo, {"VRayDiffuseFilter"}}, {R::DirectDiffuse, {"VRayLighting"}}}},
        {"karma", DepthKind::Planar, NormalSpace::World, false, false, "karma",
         {{R::Depth, {"depth"}}, {R::Normal, {"N"}}, {R::Position, {"P"}}, {R::Beauty, {"C"}},
          {R::Albedo, {"albedo"}}, {R::DirectDiffuse, {"directdiffuse"}}}},
    };
    return table;
}

// Channel suffixes, in preference order. Nuke writes the channels of layers other than rgba as
// red, green, blue (N.red), and so do V-Ray's render elements.
const std::vector<std::string> kScalarSuffixes = {"Z", "z", "V", "R", "r", "Y", "y"};
const std::vector<std::vector<std::string>> kVectorSuffixes = {
    {"X", "Y", "Z"}, {"x", "y", "z"}, {"R", "G", "B"}, {"r", "g", "b"}, {"red", "green", "blue"}};
const std::vector<std::vector<std::string>> kColourSuffixes = {{"R", "G", "B"}, {"r", "g", "b"}, {"red", "green", "blue"}};
const std::vector<std::string> kAlphaSuffixes = {"A", "a", "alpha"};

const char* kRoleNames[] = {"depth", "normal", "position", "beauty", "albedo", "direct-diffuse"};

// Channels grouped by (part, layer prefix).
struct LayerEntry {
    int part = 0;
    std::string partName, layer;
    std::vector<std::string> suffixes, fullNames;
    std::vector<Imf::PixelType> types;

    int findSuffix(const std::string& s) const {
        for (size_t i = 0; i < suffixes.size(); ++i)
            if (suffixes[i] == s) return (int)i;
        return -1;
    }
};

std::vector<LayerEntry> collectLayers(const ExrInfo& info) {
    std::vector<LayerEntry> out;
    for (int p = 0; p < (int)info.parts.size(); ++p) {
        for (const ExrChannel& ch : info.parts[p].channels) {
            size_t dot = ch.name.rfind('.');
            std::string layer = dot == std::string::npos ? "" : ch.name.substr(0, dot);
            std::string suffix = dot == std::string::npos ? ch.name : ch.name.substr(dot + 1);
            auto it = std::find_if(out.begin(), out.end(),
                                   [&](const LayerEntry& e) { return e.part == p && e.layer == layer; });
            if (it == out.end()) {
                out.push_back({p, info.parts[p].name, layer, {}, {}, {}});
                it = out.end() - 1;
            }
            it->suffixes.push_back(suffix);
            it->fullNames.push_back(ch.name);
            it->types.push_back(ch.type);
        }
    }
    return out;
}

bool endsWith(const std::string& s, const std::string& tail) {
    return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

// Does `e` carry the layer `name`? Sets *prefix to the view-layer prefix matched.
bool layerMatches(const LayerEntry& e, const std::string& name, bool viewLayerPrefix, std::string* prefix) {
    prefix->clear();
    // Top-level R,G,B(,A): only part 0's, so a part named "N" holding R,G,B is not the beauty.
    if (name.empty()) return e.layer.empty() && e.part == 0;
    if (e.layer == name) return true;
    if (e.layer.empty() && e.partName == name) return true;  // a part named after the layer
    if (viewLayerPrefix && endsWith(e.layer, "." + name)) {
        *prefix = e.layer.substr(0, e.layer.size() - name.size() - 1);
        return true;
    }
    return false;
}

// Binds `role` to the channels of layer `e`; false if the layer lacks the right channels.
bool bindLayer(Role role, const LayerEntry& e, LayerBinding* b) {
    b->role = role;
    b->part = e.part;
    b->layer = e.layer;
    b->channels.clear();
    if (role == Role::Depth) {
        for (const std::string& s : kScalarSuffixes)
            if (int i = e.findSuffix(s); i >= 0) { b->channels = {e.fullNames[i]}; return true; }
        if (e.fullNames.size() == 1 && !e.layer.empty()) { b->channels = e.fullNames; return true; }
        return false;
    }
    bool vector = role == Role::Normal || role == Role::Position;
    for (const auto& triple : vector ? kVectorSuffixes : kColourSuffixes) {
        std::vector<std::string> names;
        for (const std::string& s : triple)
            if (int i = e.findSuffix(s); i >= 0) names.push_back(e.fullNames[i]);
        if (names.size() != 3) continue;
        if (!vector)
            for (const std::string& a : kAlphaSuffixes)
                if (int i = e.findSuffix(a); i >= 0) { names.push_back(e.fullNames[i]); break; }
        b->channels = names;
        return true;
    }
    return false;
}

// A bare channel called `name` (e.g. "Z", "depth"), bound as a scalar.
bool bindChannel(Role role, const std::vector<LayerEntry>& layers, const std::string& name, LayerBinding* b) {
    if (role != Role::Depth) return false;
    for (const LayerEntry& e : layers)
        for (size_t i = 0; i < e.fullNames.size(); ++i)
            if (e.fullNames[i] == name) {
                *b = LayerBinding{role, e.part, e.layer, {name}};
                return true;
            }
    return false;
}

// Tries the preset's candidates for `role`, preferring the view-layer prefix already chosen.
bool bindRole(const Preset& pr, Role role, const std::vector<std::string>& names,
              const std::vector<LayerEntry>& layers, std::string* viewLayer, LayerBinding* out) {
    for (const std::string& name : names) {
        if (!name.empty() && bindChannel(role, layers, name, out)) return true;
        bool found = false;
        std::string prefix, chosen;
        for (const LayerEntry& e : layers) {
            LayerBinding b;
            if (!layerMatches(e, name, pr.viewLayerPrefix, &prefix) || !bindLayer(role, e, &b)) continue;
            bool preferred = prefix == *viewLayer;
            if (!found || preferred) { *out = b; chosen = prefix; }
            found = true;
            if (preferred) break;
        }
        if (found) {
            if (viewLayer->empty()) *viewLayer = chosen;
            return true;
        }
    }
    return false;
}

int roleWeight(Role r) {
    switch (r) {
    case Role::Depth: case Role::Normal: return 8;
    case Role::Position: return 2;
    default: return 1;
    }
}

std::string lower(std::string s) {
    for (char& c : s) c = (char)std::tolower((unsigned char)c);
    return s;
}

// Renderer evidence in the header: an attribute name, or a software/writer value.
bool headerHints(const ExrInfo& info, const std::string& hint) {
    if (hint.empty()) return false;
    for (const ExrPart& p : info.parts)
        for (auto it = p.header.begin(); it != p.header.end(); ++it) {
            std::string n = lower(it.name());
            if (n.find(hint) != std::string::npos) return true;
            auto* s = dynamic_cast<const Imf::StringAttribute*>(&it.attribute());
            if (s && (n == "software" || n == "writer" || n == "renderer") &&
                lower(s->value()).find(hint) != std::string::npos)
                return true;
        }
    return false;
}

LayerPlan planPreset(const Preset& pr, const std::vector<LayerEntry>& layers) {
    LayerPlan plan;
    plan.preset = pr.name;
    plan.depthKind = pr.depth;
    plan.normalSpace = pr.normals;
    plan.normalsLeftHanded = pr.leftHanded;
    plan.deep = pr.deep;
    plan.skyDepth = 1e9f;  // Blender's 1e10 sky, "large Z" and inf all sit above this
    std::string viewLayer;
    for (const RoleNames& rn : pr.roles) {
        LayerBinding b;
        if (bindRole(pr, rn.role, rn.names, layers, &viewLayer, &b)) plan.bindings.push_back(b);
    }
    return plan;
}

// Display order: R,G,B,A then X,Y,Z, then the rest as stored (alphabetical).
std::vector<std::string> displayOrder(std::vector<std::string> v) {
    std::stable_sort(v.begin(), v.end(),
                     [](const std::string& a, const std::string& b) { return channelOrder(a) < channelOrder(b); });
    return v;
}

} // namespace

int channelOrder(const std::string& suffix) {
    static const std::string order = "RGBAXYZW";
    static const char* const words[] = {"red", "green", "blue", "alpha"};
    for (int i = 0; i < 4; ++i)
        if (suffix == words[i]) return i;
    const size_t i = suffix.size() == 1 ? order.find((char)std::toupper((unsigned char)suffix[0])) : std::string::npos;
    return i == std::string::npos ? 100 : (int)i;
}

namespace {

std::string layerLabel(const LayerEntry& e, bool multipart) {
    std::string s = multipart ? (e.partName.empty() ? std::to_string(e.part) : e.partName) + ": " : "";
    return s + (e.layer.empty() ? "(top level)" : e.layer);
}

std::string layersFound(const ExrInfo& info) {
    std::string s;
    for (const LayerEntry& e : collectLayers(info)) {
        if (!s.empty()) s += ", ";
        s += layerLabel(e, info.multipart);
        if (e.layer.empty()) {  // top-level channels are their own names
            s += " [";
            std::vector<std::string> suffixes = displayOrder(e.suffixes);
            for (size_t i = 0; i < suffixes.size(); ++i) s += (i ? " " : "") + suffixes[i];
            s += "]";
        }
    }
    return s.empty() ? "none" : s;
}

LayerBinding resolveOverride(const ExrInfo& info, const std::vector<LayerEntry>& layers, Role role,
                             const std::string& name) {
    const std::string what = std::string("--layer ") + roleName(role) + "=" + name;
    LayerBinding b;
    for (const LayerEntry& e : layers) {
        std::string prefix;
        if (!layerMatches(e, name, false, &prefix)) continue;
        if (bindLayer(role, e, &b)) return b;
        throw FileError(info.path, what + ": layer '" + name + "' lacks the channels a " + roleName(role) +
                                       " needs (" + (role == Role::Depth ? "Z/V/R/Y" : "X,Y,Z, R,G,B in either case, or red,green,blue") + ")");
    }
    if (bindChannel(role, layers, name, &b)) return b;
    for (const LayerEntry& e : layers)
        if (std::find(e.fullNames.begin(), e.fullNames.end(), name) != e.fullNames.end())
            throw FileError(info.path, what + ": '" + name + "' is a single channel; " +
                        roleName(role) + " needs a layer (e.g. '" + e.layer + "')");
    throw FileError(info.path, what + ": no layer or channel '" + name +
                "'; layers found: " + layersFound(info));
}

} // namespace

const char* roleName(Role r) { return kRoleNames[(int)r]; }

bool parseRole(const std::string& s, Role& r) {
    for (int i = 0; i < 6; ++i)
        if (s == kRoleNames[i]) { r = (Role)i; return true; }
    return false;
}

const std::vector<Role>& allRoles() {
    static const std::vector<Role> roles = {Role::Depth, Role::Normal, Role::Position,
                                            Role::Beauty, Role::Albedo, Role::DirectDiffuse};
    return roles;
}

const LayerBinding* LayerPlan::find(Role r) const {
    for (const LayerBinding& b : bindings)
        if (b.role == r) return &b;
    return nullptr;
}

const std::vector<std::string>& presetNames() {
    static const std::vector<std::string> names = [] {
        std::vector<std::string> n = {"auto"};
        for (const Preset& p : presetTable()) n.push_back(p.name);
        return n;
    }();
    return names;
}

LayerPlan planLayers(const ExrInfo& info, const std::string& preset,
                     const std::map<Role, std::string>& overrides) {
    std::vector<LayerEntry> layers = collectLayers(info);
    LayerPlan plan;
    if (preset == "auto") {
        int best = -1;
        for (const Preset& pr : presetTable()) {
            LayerPlan p = planPreset(pr, layers);
            int score = headerHints(info, pr.hint) ? 3 : 0;
            for (const LayerBinding& b : p.bindings) score += roleWeight(b.role);
            if (score > best) { best = score; plan = p; }  // strict: earlier (generic) wins ties
        }
    } else {
        auto& table = presetTable();
        auto it = std::find_if(table.begin(), table.end(), [&](const Preset& p) { return preset == p.name; });
        if (it == table.end()) {
            std::string all;
            for (const std::string& n : presetNames()) all += (all.empty() ? "" : ", ") + n;
            throw Error("unknown preset '" + preset + "' (choose one of: " + all + ")");
        }
        plan = planPreset(*it, layers);
    }
    for (const auto& [role, name] : overrides) {
        LayerBinding b = resolveOverride(info, layers, role, name);
        auto it = std::find_if(plan.bindings.begin(), plan.bindings.end(),
                               [&](const LayerBinding& x) { return x.role == role; });
        if (it != plan.bindings.end()) *it = b;
        else plan.bindings.push_back(b);
    }
    return plan;
}

void requireRoles(const LayerPlan& plan, const ExrInfo& info, const std::vector<Role>& roles) {
    for (Role r : roles)
        if (!plan.find(r))
            throw FileError(info.path, std::string("no ") + roleName(r) + " layer (preset " +
                        plan.preset + "); layers found: " + layersFound(info) + "; use --layer " +
                        roleName(r) + "=NAME");
}

std::vector<LayerSummary> summariseLayers(const ExrInfo& info) {
    std::vector<LayerSummary> out;
    for (const LayerEntry& e : collectLayers(info)) {
        const bool same = std::all_of(e.types.begin(), e.types.end(), [&](Imf::PixelType t) { return t == e.types[0]; });
        const char* type = e.types[0] == Imf::HALF ? "half" : e.types[0] == Imf::FLOAT ? "float" : "uint";
        out.push_back({e.part, e.partName, e.layer, displayOrder(e.suffixes), same ? type : "mixed"});
    }
    return out;
}

std::string layerLine(const LayerSummary& l, bool multipart) {
    LayerEntry e;
    e.part = l.part, e.partName = l.partName, e.layer = l.name;
    std::string s = layerLabel(e, multipart) + " (";
    for (size_t i = 0; i < l.channels.size(); ++i) s += (i ? "," : "") + l.channels[i];
    return s + ") " + l.type;
}

std::vector<std::string> listLayers(const ExrInfo& info) {
    std::vector<std::string> lines;
    for (const LayerSummary& l : summariseLayers(info)) lines.push_back(layerLine(l, info.multipart));
    return lines;
}

std::vector<ChannelRef> channelRefs(const LayerBinding& b) {
    std::vector<ChannelRef> refs;
    for (const std::string& c : b.channels) refs.push_back({b.part, c});
    return refs;
}

} // namespace obscura
