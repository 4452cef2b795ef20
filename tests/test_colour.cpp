// Colour management: the shipped OpenColorIO config, colour-space detection from EXR
// headers, conversions to and from the working space, output tagging and display previews.
#include "io/colour.h"

#include "base/error.h"
#include "io/exr_file.h"

#include <OpenColorIO/OpenColorIO.h>
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStandardAttributes.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

namespace OCIO = OCIO_NAMESPACE;
using namespace obscura;

namespace {

std::string tmpPath(const std::string& name) { return std::string(OBSCURA_TEST_TMP) + "/colour_" + name; }

// Every test uses the shipped config explicitly, whatever $OCIO the environment has.
const ColourManager& shipped() {
    static ColourManager cm(ColourManager::shippedConfigPath());
    return cm;
}

Image randomImage(int w, int h, int channels, unsigned seed, float lo = 0.0f, float hi = 100.0f) {
    Image img(w, h, channels);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(lo, hi);
    for (float& v : img.pixels) v = u(rng);
    return img;
}

// Per pixel, |a - b| <= tol * max(1, largest |b| of the pixel's RGB): 1e-5 absolute for
// pixels up to 1, relative to the pixel above. A float32 image holding values near 100 is
// only exact to its spacing there (7.6e-6), and a 3x3 matrix mixes the channels, so a
// small component next to large ones cannot be better than ~1e-7 of the pixel's size.
::testing::AssertionResult closeImages(const Image& a, const Image& b, double tol, int channels = 3) {
    double worst = 0, worstAbs = 0;
    std::size_t at = 0;
    for (std::size_t p = 0; p < a.pixels.size(); p += a.channels) {
        double scale = 1.0;
        for (int c = 0; c < channels; ++c) scale = std::max(scale, std::fabs((double)b.pixels[p + c]));
        for (int c = 0; c < channels; ++c) {
            const double d = std::fabs((double)a.pixels[p + c] - b.pixels[p + c]);
            worstAbs = std::max(worstAbs, d);
            if (d / scale > worst) worst = d / scale, at = p + c;
        }
    }
    if (worst <= tol)
        return ::testing::AssertionSuccess() << "worst scaled error " << worst << ", absolute " << worstAbs;
    return ::testing::AssertionFailure() << "worst scaled error " << worst << " (absolute " << worstAbs
                                         << ") at sample " << at << ": " << a.pixels[at] << " vs " << b.pixels[at];
}

// The 3x3 matrix a (linear) conversion applies: columns are the images of the unit vectors.
std::array<std::array<double, 3>, 3> matrixOf(const ColourManager& cm, const std::string& from, const std::string& to) {
    Image img(3, 1, 3, 0.0f);
    for (int i = 0; i < 3; ++i) img.at(i, 0)[i] = 1.0f;
    cm.convert(img, from, to);
    std::array<std::array<double, 3>, 3> m{};
    for (int col = 0; col < 3; ++col)
        for (int row = 0; row < 3; ++row) m[row][col] = img.at(col, 0)[row];
    return m;
}

Imf::Chromaticities prim(float rx, float ry, float gx, float gy, float bx, float by, float wx, float wy) {
    return Imf::Chromaticities(Imath::V2f(rx, ry), Imath::V2f(gx, gy), Imath::V2f(bx, by), Imath::V2f(wx, wy));
}
const Imf::Chromaticities kRec709 = prim(0.64f, 0.33f, 0.30f, 0.60f, 0.15f, 0.06f, 0.3127f, 0.3290f);
const Imf::Chromaticities kAP1 = prim(0.713f, 0.293f, 0.165f, 0.830f, 0.128f, 0.044f, 0.32168f, 0.33767f);
const Imf::Chromaticities kAP0 = prim(0.7347f, 0.2653f, 0.0f, 1.0f, 0.0001f, -0.0770f, 0.32168f, 0.33767f);
const Imf::Chromaticities kRec2020 = prim(0.708f, 0.292f, 0.170f, 0.797f, 0.131f, 0.046f, 0.3127f, 0.3290f);
const Imf::Chromaticities kP3D65 = prim(0.680f, 0.320f, 0.265f, 0.690f, 0.150f, 0.060f, 0.3127f, 0.3290f);
const Imf::Chromaticities kAdobeRgb = prim(0.64f, 0.33f, 0.21f, 0.71f, 0.15f, 0.06f, 0.3127f, 0.3290f);

Imf::Header headerWith(const Imf::Chromaticities* c, const char* oiio = nullptr, const char* interop = nullptr) {
    Imf::Header h(4, 4);
    if (c) Imf::addChromaticities(h, *c);
    if (oiio) h.insert("oiio:ColorSpace", Imf::StringAttribute(oiio));
    if (interop) h.insert("colorInteropID", Imf::StringAttribute(interop));
    return h;
}

// Published values (Bradford-adapted, as in the ACES and colour-science references).
constexpr double kRec709ToAP1[3][3] = {{0.6130974024, 0.3395231462, 0.0473794514},
                                       {0.0701937225, 0.9163538791, 0.0134523985},
                                       {0.0206155929, 0.1095697729, 0.8698146342}};
constexpr double kAP1ToRec709[3][3] = {{1.7050509927, -0.6217921207, -0.0832588720},
                                       {-0.1302564175, 1.1408047366, -0.0105483191},
                                       {-0.0240033568, -0.1289689761, 1.1529723329}};
// ACES TB-2014-004: AP0 -> AP1 (same white, no adaptation).
constexpr double kAP0ToAP1[3][3] = {{1.4514393161, -0.2365107469, -0.2149285693},
                                    {-0.0765537734, 1.1762296998, -0.0996759264},
                                    {0.0083161484, -0.0060324498, 0.9977163014}};

struct ScopedEnv {
    std::string name;
    bool had = false;
    std::string old;
    ScopedEnv(const std::string& n, const char* value) : name(n) {
        if (const char* v = std::getenv(n.c_str())) had = true, old = v;
        if (value)
            setenv(n.c_str(), value, 1);
        else
            unsetenv(n.c_str());
    }
    ~ScopedEnv() {
        if (had)
            setenv(name.c_str(), old.c_str(), 1);
        else
            unsetenv(name.c_str());
    }
};

} // namespace

TEST(Colour, ShippedConfigLoadsAndValidates) {
    const std::string path = ColourManager::shippedConfigPath();
    ASSERT_FALSE(path.empty());
    auto config = OCIO::Config::CreateFromFile(path.c_str());
    EXPECT_NO_THROW(config->validate());
    const ColourManager& cm = shipped();
    EXPECT_EQ(cm.workingSpace(), "lin_rec709");
    EXPECT_EQ(cm.dataSpace(), "raw");
    EXPECT_TRUE(cm.isData("raw"));
    EXPECT_FALSE(cm.isData("ACEScg"));
    EXPECT_EQ(cm.defaultDisplay(), "sRGB");
    EXPECT_EQ(cm.defaultView("sRGB"), "Standard");
    for (const char* name : {"lin_rec709", "ACEScg", "ACES2065-1", "lin_rec2020", "lin_p3d65", "srgb_display", "raw"})
        EXPECT_EQ(cm.resolve(name), name);
}

TEST(Colour, CommonSpellingsResolve) {
    const ColourManager& cm = shipped();
    const std::pair<const char*, const char*> cases[] = {
        {"Linear", "lin_rec709"},          {"scene_linear", "lin_rec709"},   {"lin_srgb", "lin_rec709"},
        {"Linear Rec.709 (sRGB)", "lin_rec709"}, {"lin_rec709_scene", "lin_rec709"},
        {"acescg", "ACEScg"},              {"lin_ap1", "ACEScg"},            {"ACES - ACEScg", "ACEScg"},
        {"lin_ap1_scene", "ACEScg"},       {"ACES2065-1", "ACES2065-1"},     {"lin_ap0", "ACES2065-1"},
        {"ACES", "ACES2065-1"},            {"Linear Rec.2020", "lin_rec2020"}, {"lin_p3d65_scene", "lin_p3d65"},
        {"sRGB", "srgb_display"},          {"Non-Color", "raw"},             {"data", "raw"},
    };
    for (const auto& [spelling, name] : cases) EXPECT_EQ(cm.resolve(spelling), name) << spelling;
    EXPECT_EQ(cm.resolve("no such space"), "");
    EXPECT_THROW(cm.require("no such space", "--colorspace"), Error);
}

TEST(Colour, RoundTripsThroughEverySpaceAreExact) {
    const ColourManager& cm = shipped();
    const Image original = randomImage(64, 32, 3, 1);
    for (const char* space : {"ACEScg", "ACES2065-1", "lin_rec2020", "lin_p3d65", "CIE-XYZ-D65", "srgb_display", "raw"}) {
        Image img = original;
        cm.fromWorkingSpace(img, space);  // lin_rec709 -> space
        if (std::string(space) != "raw") {
            EXPECT_FALSE(closeImages(img, original, 1e-3)) << space << " did nothing";
        }
        cm.toWorkingSpace(img, space);    // -> lin_rec709
        EXPECT_TRUE(closeImages(img, original, 1e-5)) << "lin_rec709 -> " << space << " -> lin_rec709";

        // And the other way round, starting in that space.
        Image there = original;
        cm.toWorkingSpace(there, space);
        cm.fromWorkingSpace(there, space);
        EXPECT_TRUE(closeImages(there, original, 1e-5)) << space << " -> lin_rec709 -> " << space;
    }
    // Between two non-working spaces too.
    Image img = original;
    cm.convert(img, "ACEScg", "ACES2065-1");
    cm.convert(img, "ACES2065-1", "ACEScg");
    EXPECT_TRUE(closeImages(img, original, 1e-5));
}

TEST(Colour, MatricesAgreeWithPublishedValues) {
    const ColourManager& cm = shipped();
    const auto toAP1 = matrixOf(cm, "lin_rec709", "ACEScg");
    const auto fromAP1 = matrixOf(cm, "ACEScg", "lin_rec709");
    const auto ap0ToAP1 = matrixOf(cm, "ACES2065-1", "ACEScg");
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(toAP1[r][c], kRec709ToAP1[r][c], 1e-4) << r << "," << c;
            EXPECT_NEAR(fromAP1[r][c], kAP1ToRec709[r][c], 1e-4) << r << "," << c;
            EXPECT_NEAR(ap0ToAP1[r][c], kAP0ToAP1[r][c], 1e-4) << r << "," << c;
        }
    // White stays white (Bradford adaptation D65 <-> D60).
    Image white(1, 1, 3, 1.0f);
    cm.convert(white, "lin_rec709", "ACEScg");
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(white.pixels[c], 1.0, 1e-5);
}

TEST(Colour, ChromaticitiesPickTheMatchingSpace) {
    const ColourManager& cm = shipped();
    const std::pair<const Imf::Chromaticities*, const char*> cases[] = {
        {&kRec709, "lin_rec709"}, {&kAP1, "ACEScg"}, {&kAP0, "ACES2065-1"}, {&kRec2020, "lin_rec2020"}, {&kP3D65, "lin_p3d65"}};
    for (const auto& [c, name] : cases) {
        ColourSpaceGuess g = cm.detectColourSpace(headerWith(c));
        EXPECT_EQ(g.name, name);
        EXPECT_EQ(g.source.rfind("chromaticities (", 0), 0u) << g.source;
        EXPECT_TRUE(g.warning.empty()) << g.warning;
    }
    EXPECT_EQ(cm.detectColourSpace(headerWith(&kAP1)).source, "chromaticities (AP1)");
    // Rounded as some writers store them (within 0.002).
    Imf::Chromaticities rounded = kAP1;
    rounded.white = Imath::V2f(0.3217f, 0.3377f);
    EXPECT_EQ(cm.detectColourSpace(headerWith(&rounded)).name, "ACEScg");
}

TEST(Colour, UnknownOrMissingMetadataFallsBackWithAWarning) {
    const ColourManager& cm = shipped();
    ColourSpaceGuess unknown = cm.detectColourSpace(headerWith(&kAdobeRgb));
    EXPECT_EQ(unknown.name, "lin_rec709");
    EXPECT_EQ(unknown.source, "default");
    EXPECT_NE(unknown.warning.find("match no known colour space"), std::string::npos) << unknown.warning;
    EXPECT_NE(unknown.warning.find("assuming lin_rec709"), std::string::npos) << unknown.warning;
    EXPECT_EQ(unknown.warning.find('\n'), std::string::npos);

    ColourSpaceGuess none = cm.detectColourSpace(headerWith(nullptr));
    EXPECT_EQ(none.name, "lin_rec709");
    EXPECT_EQ(none.source, "default");
    EXPECT_NE(none.warning.find("no colour-space metadata"), std::string::npos) << none.warning;
}

TEST(Colour, StringAttributesWinOverChromaticities) {
    const ColourManager& cm = shipped();
    ColourSpaceGuess g = cm.detectColourSpace(headerWith(&kRec709, "ACEScg"));
    EXPECT_EQ(g.name, "ACEScg");
    EXPECT_EQ(g.source, "oiio:ColorSpace");
    EXPECT_TRUE(g.warning.empty());

    // colorInteropID before oiio:ColorSpace.
    g = cm.detectColourSpace(headerWith(&kRec709, "ACEScg", "lin_ap0_scene"));
    EXPECT_EQ(g.name, "ACES2065-1");
    EXPECT_EQ(g.source, "colorInteropID");

    // An unknown name is reported and the chromaticities decide.
    g = cm.detectColourSpace(headerWith(&kAP1, "MyStudioSpace"));
    EXPECT_EQ(g.name, "ACEScg");
    EXPECT_NE(g.warning.find("'MyStudioSpace'"), std::string::npos) << g.warning;

    // A bare "Linear" names no primaries: chromaticities decide when present.
    g = cm.detectColourSpace(headerWith(&kAP1, "Linear"));
    EXPECT_EQ(g.name, "ACEScg");
    EXPECT_TRUE(g.warning.empty()) << g.warning;
    g = cm.detectColourSpace(headerWith(nullptr, "Linear"));
    EXPECT_EQ(g.name, "lin_rec709");
    EXPECT_EQ(g.source, "oiio:ColorSpace");

    // The override beats everything, and must name a space.
    g = cm.detectColourSpace(headerWith(&kAP1, "ACEScg"), "lin_rec2020");
    EXPECT_EQ(g.name, "lin_rec2020");
    EXPECT_EQ(g.source, "--colorspace");
    EXPECT_THROW(cm.detectColourSpace(headerWith(&kAP1), "bogus"), Error);
}

TEST(Colour, TheSameSceneInRec709AndACEScgGivesTheSameWorkingValues) {
    const ColourManager& cm = shipped();
    // A scene's radiance in lin_rec709, and the same radiance as an ACEScg renderer would
    // write it, computed independently with the published matrix in double precision.
    const Image rec709 = randomImage(40, 30, 4, 7, 0.0f, 100.0f);
    Image acescg = rec709;
    for (std::size_t i = 0; i < acescg.pixels.size(); i += 4) {
        const double* m[3] = {kRec709ToAP1[0], kRec709ToAP1[1], kRec709ToAP1[2]};
        for (int r = 0; r < 3; ++r)
            acescg.pixels[i + r] = (float)(m[r][0] * rec709.pixels[i] + m[r][1] * rec709.pixels[i + 1] +
                                           m[r][2] * rec709.pixels[i + 2]);
    }
    // Each beauty as the frame job sees it: detected from its header, then converted.
    Image a = rec709, b = acescg;
    cm.toWorkingSpace(a, cm.detectColourSpace(headerWith(&kRec709)).name);
    cm.toWorkingSpace(b, cm.detectColourSpace(headerWith(&kAP1)).name);
    EXPECT_TRUE(closeImages(a, b, 1e-5));
    EXPECT_TRUE(closeImages(b, rec709, 1e-5));
    // Alpha (channel 3) is not touched.
    for (std::size_t i = 3; i < b.pixels.size(); i += 4) ASSERT_EQ(b.pixels[i], acescg.pixels[i]);
}

TEST(Colour, StridedPlanesConvertInPlace) {
    const ColourManager& cm = shipped();
    // Every other pixel of every other row, with a 5-float pixel.
    Image big = randomImage(20, 10, 5, 3);
    const Image before = big;
    MutablePlane view{big.pixels.data(), 10, 5, 5, 10, 2 * 20 * 5};
    cm.convert(view, "ACEScg", "lin_rec709");
    Image expect(1, 1, 3);
    for (int y = 0; y < 10; ++y)
        for (int x = 0; x < 20; ++x) {
            const bool inView = x % 2 == 0 && y % 2 == 0;
            const float* p = big.at(x, y);
            const float* q = before.at(x, y);
            if (!inView) {
                for (int c = 0; c < 5; ++c) ASSERT_EQ(p[c], q[c]) << x << "," << y;
                continue;
            }
            for (int r = 0; r < 3; ++r) {
                const double want = kAP1ToRec709[r][0] * q[0] + kAP1ToRec709[r][1] * q[1] + kAP1ToRec709[r][2] * q[2];
                ASSERT_NEAR(p[r], want, 1e-5 * std::max(1.0, std::fabs(want)));
            }
            ASSERT_EQ(p[3], q[3]);
            ASSERT_EQ(p[4], q[4]);
        }
    // A large image goes through the threaded path and agrees with the small one.
    Image large = randomImage(1024, 600, 3, 11), rows = large;
    cm.convert(large, "lin_rec709", "lin_p3d65");
    for (int y = 0; y < rows.height; y += 97) {
        Image row(rows.width, 1, 3);
        std::copy(rows.at(0, y), rows.at(0, y) + rows.width * 3, row.pixels.begin());
        cm.convert(row, "lin_rec709", "lin_p3d65");
        for (int x = 0; x < rows.width; ++x)
            for (int c = 0; c < 3; ++c) ASSERT_EQ(row.at(x, 0)[c], large.at(x, y)[c]);
    }
    Image grey(2, 2, 1, 0.5f);
    EXPECT_THROW(cm.convert(grey, "ACEScg", "lin_rec709"), Error);
}

TEST(Colour, NewColourLayersAreInTheFilesSpaceWhenItsPrimariesAreKnown) {
    const ColourManager& cm = shipped();
    EXPECT_EQ(cm.layerSpace("lin_rec709"), "lin_rec709");
    EXPECT_EQ(cm.layerSpace("ACEScg"), "ACEScg");
    EXPECT_EQ(cm.layerSpace("lin_ap1"), "ACEScg");  // a spelling resolves to the config's name
    // sRGB-encoded or data: no primaries obscura knows for a linear layer, the working space.
    EXPECT_EQ(cm.layerSpace("srgb_display"), cm.workingSpace());
    EXPECT_EQ(cm.layerSpace("raw"), cm.workingSpace());
}

TEST(Colour, TaggingNamesEachLayersSpaceAndPrimaries) {
    const ColourManager& cm = shipped();
    const std::vector<std::string> colour = {"obscura.DO.B", "obscura.DO.G", "obscura.DO.R"};
    const std::vector<std::string> data = {"obscura.AO.Y"};
    std::string note;
    auto attrs = cm.tagOutputPart(2, "ACEScg", colour, data, &note);
    ASSERT_EQ(attrs.size(), 7u);
    for (const auto& a : attrs) EXPECT_EQ(a.part, 2);
    EXPECT_EQ(attrs[0].name, "obscura/obscura.DO.B/colorspace");
    EXPECT_EQ(attrs[0].value, "ACEScg");
    EXPECT_EQ(attrs[1].name, "obscura/obscura.DO.B/chromaticities");
    const Imf::Chromaticities ap1 = *cm.chromaticitiesOf("ACEScg");
    char want[160];
    std::snprintf(want, sizeof want, "%g %g %g %g %g %g %g %g", ap1.red.x, ap1.red.y, ap1.green.x, ap1.green.y,
                  ap1.blue.x, ap1.blue.y, ap1.white.x, ap1.white.y);
    EXPECT_EQ(attrs[1].value, want);
    EXPECT_EQ(attrs[6].name, "obscura/obscura.AO.Y/colorspace");
    EXPECT_EQ(attrs[6].value, "raw");
    EXPECT_NE(note.find("ACEScg"), std::string::npos) << note;

    // Data only: no colour tags, no note.
    attrs = cm.tagOutputPart(0, "lin_rec709", {}, data, &note);
    ASSERT_EQ(attrs.size(), 1u);
    EXPECT_TRUE(note.empty()) << note;
    EXPECT_THROW(cm.tagOutputPart(0, "no such space", colour, data), Error);
}

TEST(Colour, TaggedLayersSurviveTheExrWriter) {
    const ColourManager& cm = shipped();
    const std::string in = tmpPath("ap1_in.exr"), out = tmpPath("ap1_out.exr");
    {
        const int w = 8, h = 4;
        Imf::Header header(w, h);
        Imf::addChromaticities(header, kAP1);
        for (const char* c : {"R", "G", "B"}) header.channels().insert(c, Imf::Channel(Imf::FLOAT));
        std::vector<float> px(w * h * 3, 0.25f);
        Imf::FrameBuffer fb;
        for (int c = 0; c < 3; ++c)
            fb.insert(std::string(1, "RGB"[c]),
                      Imf::Slice(Imf::FLOAT, (char*)(px.data() + c), 3 * sizeof(float), 3 * w * sizeof(float)));
        Imf::OutputFile file(in.c_str(), header);
        file.setFrameBuffer(fb);
        file.writePixels(h);
    }
    {
        // The environment-map path: the same file through OpenImageIO.
        auto oiio = OIIO::ImageInput::open(in);
        ASSERT_TRUE(oiio);
        const ColourSpaceGuess g = cm.detectColourSpace(colourMetadata(oiio->spec()));
        EXPECT_EQ(g.name, "ACEScg") << g.source << " " << g.warning;
        oiio->close();
    }
    ExrInfo info = readExrInfo(in);
    ExrPixels raw;
    std::vector<Image> planes = readExrChannels(in, info, {{0, "R"}, {0, "G"}, {0, "B"}}, true, &raw);
    const std::string inputSpace = cm.detectColourSpace(raw.info.parts[0].header).name;
    ASSERT_EQ(inputSpace, "ACEScg");

    std::vector<NewChannel> add;
    for (const char* c : {"obscura.GI.R", "obscura.GI.G", "obscura.GI.B"}) add.push_back({0, c, Image(8, 4, 1, 0.5f), Imf::HALF});
    add.push_back({0, "obscura.AO.Y", Image(8, 4, 1, 1.0f), Imf::HALF});
    auto attrs = cm.tagOutputPart(0, cm.layerSpace(inputSpace), {"obscura.GI.R", "obscura.GI.G", "obscura.GI.B"},
                                  {"obscura.AO.Y"});
    writeExrWithNewChannels(out, raw, add, false, attrs);

    ExrInfo back = readExrInfo(out);
    const Imf::Header& h = back.parts[0].header;
    EXPECT_EQ(cm.detectColourSpace(h).name, "ACEScg");  // the beauty still reads as ACEScg
    auto attr = [&](const std::string& n) {
        const auto* a = h.findTypedAttribute<Imf::StringAttribute>(n);
        return a ? a->value() : std::string("<missing>");
    };
    EXPECT_EQ(Imf::chromaticities(h).red, kAP1.red);    // the file's chromaticities are untouched
    EXPECT_EQ(attr("obscura/obscura.GI.R/colorspace"), "ACEScg");
    EXPECT_EQ(attr("obscura/obscura.GI.G/chromaticities"), "0.713 0.293 0.165 0.83 0.128 0.044 0.32168 0.33767");
    EXPECT_EQ(attr("obscura/obscura.AO.Y/colorspace"), "raw");
}

TEST(Colour, PreviewGoesThroughTheDisplayView) {
    const ColourManager& cm = shipped();
    const std::string path = tmpPath("preview.png");
    Image img(4, 2, 4, 0.0f);
    const float values[4] = {0.18f, 1.0f, 0.0f, 4.0f};
    for (int x = 0; x < 4; ++x)
        for (int y = 0; y < 2; ++y)
            for (int c = 0; c < 3; ++c) img.at(x, y)[c] = values[x];
    cm.writeDisplayPreview(path, img);

    auto in = OIIO::ImageInput::open(path);
    ASSERT_TRUE(in) << OIIO::geterror();
    const OIIO::ImageSpec& spec = in->spec();
    EXPECT_EQ(spec.nchannels, 3);
    EXPECT_EQ(spec.get_string_attribute("oiio:ColorSpace"), "sRGB");
    std::vector<unsigned char> px(spec.width * spec.height * spec.nchannels);
    ASSERT_TRUE(in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::UINT8, px.data()));
    in->close();
    // An 8-bit environment map such as this PNG reads as sRGB-encoded and is linearised.
    EXPECT_EQ(cm.detectColourSpace(colourMetadata(spec)).name, "srgb_display");
    for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(px[0 * 3 + c], 118, 1);   // mid grey: sRGB(0.18) = 0.4614 -> 117.6
        EXPECT_EQ(px[1 * 3 + c], 255);
        EXPECT_EQ(px[2 * 3 + c], 0);
        EXPECT_EQ(px[3 * 3 + c], 255);       // clamped, no tone mapping in "Standard"
    }
    // Nothing left behind besides the PNG.
    for (const auto& e : std::filesystem::directory_iterator(OBSCURA_TEST_TMP))
        EXPECT_EQ(e.path().filename().string().find(".colour_preview.png.tmp"), std::string::npos);

    EXPECT_THROW(cm.writeDisplayPreview(tmpPath("no/such/dir/p.png"), img), Error);
    EXPECT_THROW(cm.writeDisplayPreview(path, img, "sRGB", "NoSuchView"), Error);
}

TEST(Colour, FreeFunctionsUseTheShippedConfigWithoutOcio) {
    ScopedEnv env("OCIO", nullptr);
    Imf::Header h = headerWith(&kAP1);
    std::string warning;
    EXPECT_EQ(detectColourSpace(h, "", &warning), "ACEScg");
    EXPECT_TRUE(warning.empty());
    Image img = randomImage(8, 8, 3, 5), copy = img;
    toWorkingSpace(img, "ACEScg");
    fromWorkingSpace(img, "ACEScg");
    EXPECT_TRUE(closeImages(img, copy, 1e-5));
    EXPECT_EQ(colourManager().configPath(), ColourManager::shippedConfigPath());
}

TEST(Colour, OcioEnvironmentVariableIsUsedAndABadOneIsOneClearLine) {
    {
        ScopedEnv env("OCIO", ColourManager::shippedConfigPath().c_str());
        ColourManager cm;
        EXPECT_EQ(cm.configPath(), ColourManager::shippedConfigPath());
    }
    {
        const std::string bad = "/nonexistent/dir/config.ocio";
        ScopedEnv env("OCIO", bad.c_str());
        try {
            ColourManager cm;
            FAIL() << "a missing $OCIO config loaded";
        } catch (const Error& e) {
            const std::string msg = e.what();
            EXPECT_NE(msg.find(bad), std::string::npos) << msg;
            EXPECT_NE(msg.find("$OCIO"), std::string::npos) << msg;
            RecordProperty("missing_config_error", msg);
            EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
        }
    }
    {
        const std::string garbage = tmpPath("garbage.ocio");
        std::ofstream(garbage) << "ocio_profile_version: 2\ncolorspaces: [ {name: x\n";
        ScopedEnv env("OCIO", garbage.c_str());
        try {
            ColourManager cm;
            FAIL() << "a broken config loaded";
        } catch (const Error& e) {
            const std::string msg = e.what();
            EXPECT_NE(msg.find(garbage), std::string::npos) << msg;
            RecordProperty("broken_config_error", msg);
            EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
        }
    }
    {
        // A config without scene_linear has no working space.
        const std::string noRole = tmpPath("norole.ocio");
        std::ofstream(noRole) << "ocio_profile_version: 2\nroles:\n  default: a\n"
                                 "file_rules:\n  - !<Rule> {name: Default, colorspace: a}\n"
                                 "displays:\n  d:\n    - !<View> {name: v, colorspace: a}\n"
                                 "colorspaces:\n  - !<ColorSpace>\n    name: a\n";
        EXPECT_THROW(ColourManager{noRole}, Error);
    }
}
