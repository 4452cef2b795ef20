// Renderer presets: which layer holds each role (depth, normals, position, colour passes) in
// the files Blender, Arnold, RenderMan, V-Ray, Karma and others write, and the overrides.
#include "io/exr_file.h"
#include "io/layers.h"
#include "support/exr_fixtures.h"
#include "support/expect_error.h"
#include "support/scratch.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

using namespace obscura;
using namespace obscura::fixtures;
using obscura::test::expectError;

namespace {

const std::string kRoom = std::string(OBSCURA_TEST_DATA_DIR) + "/room.exr";

std::vector<std::string> channelsOf(const std::string& layer, const std::string& suffixes) {
    std::vector<std::string> out;
    for (char c : suffixes) out.push_back(layer + (layer.empty() ? "" : ".") + c);
    return out;
}

std::string tmp(const std::string& name) {
    const std::filesystem::path dir = obscura::test::scratchRoot("presets");
    std::filesystem::create_directories(dir);
    return (dir / name).string();
}

// The plan for an 8 x 6 file holding `channels` (and header attributes `attrs`).
LayerPlan planFor(const std::string& name, const std::vector<std::string>& channels,
                  const std::string& preset = "auto", const std::map<Role, std::string>& overrides = {},
                  const std::map<std::string, std::string>& attrs = {}) {
    const std::string path = tmp(name + ".exr");
    writeSimple(path, channels, 8, 6, attrs);
    return planLayers(readExrInfo(path), preset, overrides);
}

std::vector<std::string> cat(std::initializer_list<std::vector<std::string>> lists) {
    std::vector<std::string> out;
    for (const auto& l : lists) out.insert(out.end(), l.begin(), l.end());
    return out;
}

} // namespace

TEST(Presets, RoleNamesRoundTrip) {
    for (Role r : allRoles()) {
        Role back;
        ASSERT_TRUE(parseRole(roleName(r), back));
        EXPECT_EQ(back, r);
    }
    Role r;
    EXPECT_FALSE(parseRole("Depth", r));
    EXPECT_STREQ(roleName(Role::DirectDiffuse), "direct-diffuse");
}

TEST(Presets, BlenderWithCustomViewLayerAndNewPassNames) {
    std::string v = "RenderLayer";
    LayerPlan p = planFor("blender", cat({{v + ".Depth.Z"}, channelsOf(v + ".Normal", "XYZ"),
                                          channelsOf(v + ".Position", "XYZ"), channelsOf(v + ".Combined", "RGBA"),
                                          channelsOf(v + ".Diffuse Color", "RGB"),
                                          channelsOf(v + ".Diffuse Direct", "RGB")}));
    EXPECT_EQ(p.preset, "blender");
    EXPECT_EQ(p.depthKind, DepthKind::Planar);
    EXPECT_EQ(p.normalSpace, NormalSpace::World);
    EXPECT_FALSE(p.normalsLeftHanded);
    EXPECT_LE(p.skyDepth, 1e10f);
    ASSERT_EQ(p.bindings.size(), 6u);
    EXPECT_EQ(p.find(Role::Depth)->channels, std::vector<std::string>{v + ".Depth.Z"});
    EXPECT_EQ(p.find(Role::Normal)->channels, channelsOf(v + ".Normal", "XYZ"));
    EXPECT_EQ(p.find(Role::Position)->layer, v + ".Position");
    EXPECT_EQ(p.find(Role::Beauty)->channels, channelsOf(v + ".Combined", "RGBA"));
    EXPECT_EQ(p.find(Role::Albedo)->channels, channelsOf(v + ".Diffuse Color", "RGB"));
    EXPECT_EQ(p.find(Role::DirectDiffuse)->channels, channelsOf(v + ".Diffuse Direct", "RGB"));
}

TEST(Presets, BlenderPrefersOneViewLayer) {
    LayerPlan p = planFor("blender2", cat({{"A.Depth.Z", "B.Depth.Z"}, channelsOf("A.Normal", "XYZ"),
                                           channelsOf("B.Normal", "XYZ"), channelsOf("B.DiffCol", "RGB")}));
    EXPECT_EQ(p.preset, "blender");
    EXPECT_EQ(p.find(Role::Depth)->layer, "A.Depth");
    EXPECT_EQ(p.find(Role::Normal)->layer, "A.Normal");      // same view layer as depth
    EXPECT_EQ(p.find(Role::Albedo)->layer, "B.DiffCol");     // only one there: old name
}

TEST(Presets, Arnold) {
    LayerPlan p = planFor("arnold", cat({{"R", "G", "B", "A", "Z"}, channelsOf("N", "RGB"), channelsOf("P", "RGB"),
                                         channelsOf("diffuse_albedo", "RGB"), channelsOf("diffuse_direct", "RGB")}));
    EXPECT_EQ(p.preset, "arnold");
    EXPECT_EQ(p.normalSpace, NormalSpace::World);
    EXPECT_EQ(p.find(Role::Depth)->channels, std::vector<std::string>{"Z"});
    EXPECT_EQ(p.find(Role::Normal)->channels, channelsOf("N", "RGB"));
    EXPECT_EQ(p.find(Role::Position)->channels, channelsOf("P", "RGB"));
    EXPECT_EQ(p.find(Role::Beauty)->channels, (std::vector<std::string>{"R", "G", "B", "A"}));
    EXPECT_EQ(p.find(Role::Albedo)->layer, "diffuse_albedo");
    EXPECT_EQ(p.find(Role::DirectDiffuse)->layer, "diffuse_direct");
}

TEST(Presets, ArnoldByHeaderHint) {
    auto channels = cat({{"Z"}, channelsOf("N", "XYZ"), channelsOf("P", "XYZ")});
    EXPECT_EQ(planFor("nohint", channels).preset, "generic");  // no specific evidence
    EXPECT_EQ(planFor("hint", channels, "auto", {}, {{"arnold/version", "7.1"}}).preset, "arnold");
}

TEST(Presets, RenderMan) {
    LayerPlan p = planFor("renderman", cat({channelsOf("Ci", "rgb"), {"a", "z"}, channelsOf("Nn", "xyz"),
                                            channelsOf("P", "xyz"), channelsOf("__Pworld", "xyz")}));
    EXPECT_EQ(p.preset, "renderman");
    EXPECT_EQ(p.normalSpace, NormalSpace::Camera);
    EXPECT_TRUE(p.normalsLeftHanded);
    EXPECT_EQ(p.find(Role::Depth)->channels, std::vector<std::string>{"z"});
    EXPECT_EQ(p.find(Role::Normal)->channels, channelsOf("Nn", "xyz"));
    EXPECT_EQ(p.find(Role::Position)->layer, "__Pworld");  // P is camera space
    EXPECT_EQ(p.find(Role::Beauty)->channels, channelsOf("Ci", "rgb"));
}

TEST(Presets, VRayUsesRawZNotZDepth) {
    LayerPlan p = planFor("vray", cat({{"R", "G", "B", "A", "Z"}, channelsOf("VRayZDepth", "RGB"),
                                       channelsOf("VRayNormals", "XYZ"), channelsOf("VRayDiffuseFilter", "RGB"),
                                       channelsOf("VRayLighting", "RGB")}));
    EXPECT_EQ(p.preset, "vray");
    EXPECT_EQ(p.normalSpace, NormalSpace::Camera);
    EXPECT_EQ(p.find(Role::Depth)->channels, std::vector<std::string>{"Z"});
    EXPECT_EQ(p.find(Role::Normal)->channels, channelsOf("VRayNormals", "XYZ"));
    EXPECT_EQ(p.find(Role::Albedo)->layer, "VRayDiffuseFilter");
    EXPECT_EQ(p.find(Role::DirectDiffuse)->layer, "VRayLighting");
}

TEST(Presets, Karma) {
    LayerPlan p = planFor("karma", cat({channelsOf("C", "rgba"), {"depth"}, channelsOf("N", "xyz"),
                                        channelsOf("P", "xyz"), channelsOf("directdiffuse", "rgb")}));
    EXPECT_EQ(p.preset, "karma");
    EXPECT_EQ(p.find(Role::Depth)->channels, std::vector<std::string>{"depth"});
    EXPECT_EQ(p.find(Role::Normal)->channels, channelsOf("N", "xyz"));
    EXPECT_EQ(p.find(Role::Beauty)->channels, channelsOf("C", "rgba"));
    EXPECT_EQ(p.find(Role::DirectDiffuse)->layer, "directdiffuse");
}

TEST(Presets, Generic) {
    LayerPlan p = planFor("generic", cat({{"R", "G", "B", "A"}, channelsOf("Depth", "Z"), channelsOf("normal", "XYZ"),
                                          channelsOf("P", "XYZ")}));
    EXPECT_EQ(p.preset, "generic");
    EXPECT_EQ(p.find(Role::Depth)->channels, std::vector<std::string>{"Depth.Z"});
    EXPECT_EQ(p.find(Role::Normal)->layer, "normal");
    EXPECT_EQ(p.find(Role::Position)->layer, "P");
    EXPECT_EQ(p.find(Role::Beauty)->channels.size(), 4u);
    EXPECT_EQ(p.find(Role::Albedo), nullptr);
}

// Nuke writes the channels of every layer but rgba as red, green, blue (N.red), and V-Ray its
// render elements too: they are R, G, B, listed in that order.
TEST(Presets, NukesRedGreenBlueSpelling) {
    const std::vector<std::string> rgb = {"N.blue", "N.green", "N.red", "P.blue", "P.green", "P.red"};
    LayerPlan p = planFor("nuke", cat({{"R", "G", "B", "A", "depth.Z"}, rgb}));
    ASSERT_NE(p.find(Role::Normal), nullptr);
    EXPECT_EQ(p.find(Role::Normal)->channels, (std::vector<std::string>{"N.red", "N.green", "N.blue"}));
    ASSERT_NE(p.find(Role::Position), nullptr);
    EXPECT_EQ(p.find(Role::Position)->channels, (std::vector<std::string>{"P.red", "P.green", "P.blue"}));
    LayerPlan q = planFor("nuke_albedo", cat({{"depth.Z", "diffuse.red", "diffuse.green", "diffuse.blue", "diffuse.alpha"}}),
                          "auto", {{Role::Albedo, "diffuse"}});
    EXPECT_EQ(q.find(Role::Albedo)->channels,
              (std::vector<std::string>{"diffuse.red", "diffuse.green", "diffuse.blue", "diffuse.alpha"}));
    const std::string path = tmp("nuke_list.exr");
    writeSimple(path, rgb);
    EXPECT_EQ(listLayers(readExrInfo(path))[0], "N (red,green,blue) float");
}

TEST(Presets, ExplicitPresetThatDoesNotFitErrors) {
    std::string path = tmp("wrongpreset.exr");
    writeSimple(path, cat({{"ViewLayer.Depth.Z"}, channelsOf("ViewLayer.Normal", "XYZ")}));
    ExrInfo info = readExrInfo(path);
    LayerPlan p = planLayers(info, "arnold", {});
    EXPECT_EQ(p.preset, "arnold");
    EXPECT_EQ(p.find(Role::Depth), nullptr);
    expectError([&] { requireRoles(p, info, {Role::Depth, Role::Normal}); },
                {"'" + path + "': no depth layer", "(preset arnold)", "ViewLayer.Depth", "ViewLayer.Normal",
                 "use --layer depth=NAME"});
    EXPECT_NO_THROW(requireRoles(planLayers(info, "blender", {}), info, {Role::Depth, Role::Normal}));
    expectError([&] { planLayers(info, "maya", {}); }, {"unknown preset 'maya'", "blender"});
}

TEST(Presets, Overrides) {
    std::string path = tmp("overrides.exr");
    writeSimple(path, cat({{"Z"}, channelsOf("alt", "Y"), channelsOf("N", "XYZ"), channelsOf("shading", "RGB"),
                           channelsOf("P", "XYZ")}));
    ExrInfo info = readExrInfo(path);
    LayerPlan p = planLayers(info, "auto", {{Role::Depth, "alt"}, {Role::Normal, "shading"}});
    EXPECT_EQ(p.find(Role::Depth)->channels, std::vector<std::string>{"alt.Y"});
    EXPECT_EQ(p.find(Role::Normal)->channels, channelsOf("shading", "RGB"));
    EXPECT_EQ(p.find(Role::Position)->layer, "P");  // untouched
    LayerPlan q = planLayers(info, "generic", {{Role::Depth, "alt.Y"}, {Role::Albedo, "shading"}});
    EXPECT_EQ(q.find(Role::Depth)->channels, std::vector<std::string>{"alt.Y"});
    EXPECT_EQ(q.find(Role::Albedo)->layer, "shading");
    expectError([&] { planLayers(info, "auto", {{Role::Normal, "nothing"}}); },
                {"--layer normal=nothing", "no layer or channel 'nothing'", "layers found:", "shading", "alt"});
    expectError([&] { planLayers(info, "auto", {{Role::Normal, "N.X"}}); }, {"single channel"});
    expectError([&] { planLayers(info, "auto", {{Role::Normal, "alt"}}); }, {"lacks the channels"});
}

TEST(Presets, ListLayers) {
    std::string path = tmp("list.exr");
    writeSimple(path, cat({{"R", "G", "B"}, channelsOf("N", "XYZ")}));
    auto lines = listLayers(readExrInfo(path));
    ASSERT_EQ(lines.size(), 2u);
    EXPECT_EQ(lines[0], "(top level) (R,G,B) float");
    EXPECT_EQ(lines[1], "N (X,Y,Z) float");
}

TEST(Presets, RealBlenderRenderIsDetected) {
    ExrInfo info = readExrInfo(kRoom);
    EXPECT_FALSE(info.multipart);
    ASSERT_EQ(info.parts.size(), 1u);
    EXPECT_EQ(info.parts[0].dataWindow, (Box2i{0, 0, 320, 320}));
    LayerPlan p = planLayers(info, "auto", {});
    EXPECT_EQ(p.preset, "blender");
    EXPECT_EQ(p.depthKind, DepthKind::Planar);
    EXPECT_EQ(p.normalSpace, NormalSpace::World);
    for (Role r : allRoles()) EXPECT_NE(p.find(r), nullptr) << roleName(r);
    EXPECT_NO_THROW(requireRoles(p, info, allRoles()));
    EXPECT_EQ(p.find(Role::Depth)->channels, std::vector<std::string>{"ViewLayer.Depth.Z"});
    EXPECT_EQ(p.find(Role::Normal)->channels, channelsOf("ViewLayer.Normal", "XYZ"));
    EXPECT_EQ(p.find(Role::Position)->channels, channelsOf("ViewLayer.Position", "XYZ"));
    EXPECT_EQ(p.find(Role::Beauty)->channels, channelsOf("ViewLayer.Combined", "RGBA"));
    EXPECT_EQ(p.find(Role::Albedo)->layer, "ViewLayer.DiffCol");
    EXPECT_EQ(p.find(Role::DirectDiffuse)->layer, "ViewLayer.DiffDir");

    // Depth holds both sky (1e10) and geometry; geometry normals are unit length.
    std::vector<ChannelRef> refs = channelRefs(*p.find(Role::Depth));
    for (const ChannelRef& r : channelRefs(*p.find(Role::Normal))) refs.push_back(r);
    auto planes = readExrChannels(kRoom, info, refs, false, nullptr);
    long sky = 0, geo = 0, unit = 0;
    for (size_t i = 0; i < planes[0].pixels.size(); ++i) {
        float d = planes[0].pixels[i];
        if (d >= p.skyDepth) { ++sky; continue; }
        ++geo;
        float n = std::sqrt(planes[1].pixels[i] * planes[1].pixels[i] + planes[2].pixels[i] * planes[2].pixels[i] +
                            planes[3].pixels[i] * planes[3].pixels[i]);
        unit += std::fabs(n - 1.0f) < 2e-2f;
    }
    EXPECT_GT(geo, 320 * 320 / 2);
    EXPECT_GT(unit, geo * 9 / 10);  // antialiased edges average normals
}

