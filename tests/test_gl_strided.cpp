// The GL backend reads and writes planes of any layout: a plane whose rows are one run of memory
// goes to and from the GPU without a copy, others are gathered row by row (or texel by texel when
// a texel has spare floats, as numpy and OFX views may), and every layout gives the packed
// plane's result bit for bit. The spare floats of an input are NaN, so a read of them would show;
// those of an output must come back untouched.
#include "core/operator.h"
#include "gpu/gl_backend.h"
#include "support/gl_devices.h"
#include "support/scenes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

using namespace obscura;
using namespace obscura::test;

namespace {

constexpr int W = 160, H = 120;
constexpr long long kManyTiles = 110 * 110;  // the frame in several tiles with aprons
constexpr float kOutSpare = -7.0f;

// A copy of `img` laid out with `xStride` floats a texel and `rowPad` spare floats after each row.
struct Strided {
    std::vector<float> mem;
    MutablePlane view;
    Strided(const Image& img, int xStride, int rowPad, float spare) {
        const std::ptrdiff_t yStride = (std::ptrdiff_t)img.width * xStride + rowPad;
        mem.assign((size_t)yStride * img.height, spare);
        view = {mem.data(), img.width, img.height, img.channels, xStride, yStride};
        for (int y = 0; y < img.height; ++y)
            for (int x = 0; x < img.width; ++x) std::copy_n(img.at(x, y), img.channels, view.at(x, y));
    }
    // An output of w x h x channels, every float kOutSpare before the run.
    Strided(int w, int h, int channels, int xStride, int rowPad)
        : Strided(Image(w, h, channels, kOutSpare), xStride, rowPad, kOutSpare) {}

    Image packed() const {
        Image out(view.width, view.height, view.channels);
        for (int y = 0; y < view.height; ++y)
            for (int x = 0; x < view.width; ++x) std::copy_n(view.at(x, y), view.channels, out.at(x, y));
        return out;
    }
    // How many floats outside the view's texels no longer hold kOutSpare.
    int sparesWritten() const {
        std::vector<char> inView(mem.size(), 0);
        for (int y = 0; y < view.height; ++y)
            for (int x = 0; x < view.width; ++x)
                std::fill_n(inView.begin() + (view.at(x, y) - mem.data()), view.channels, 1);
        int written = 0;
        for (size_t i = 0; i < mem.size(); ++i) written += !inView[i] && mem[i] != kOutSpare;
        return written;
    }
};

// The same bits (NaN and signed zeros included) in two images of one size.
::testing::AssertionResult sameBits(const Image& a, const Image& b) {
    if (a.width != b.width || a.height != b.height || a.channels != b.channels)
        return ::testing::AssertionFailure() << "sizes differ";
    for (size_t i = 0; i < a.pixels.size(); ++i)
        if (std::memcmp(&a.pixels[i], &b.pixels[i], sizeof(float)) != 0)
            return ::testing::AssertionFailure() << "float " << i << ": " << a.pixels[i] << " vs " << b.pixels[i];
    return ::testing::AssertionSuccess();
}

// The layouts tried for an input of `channels` floats a texel: rows with spare floats after them,
// and texels with a spare float each (gathered one texel at a time).
struct Layout {
    int xExtra, rowPad;
};
constexpr Layout kLayouts[] = {{0, 5}, {1, 3}};

const float kNaN = std::numeric_limits<float>::quiet_NaN();

SceneBuffers studio() { return renderScene(studioScene(), studioCamera(W, H), W, H); }

} // namespace

// HBAO with blur, in one tile and in several: strided depth, normals and AO give the packed result.
TEST(GlStridedViews, HbaoAnyLayoutGivesThePackedResult) {
    const SceneBuffers scene = studio();
    const KernelParams p = makeKernelParams(scene.inputs(), hbaoSettings(Weighting::Cosine, Falloff::Linear, 0.8f));
    for (const std::string& device : glDevicesUnderTest()) {
        gpu::GlBackend& gl = gpu::glBackendFor(device);
        for (long long maxTexels : {0LL, kManyTiles}) {
            Image packed(W, H, 1);
            gl.runHbao(p, scene.depth.view(), scene.normal.view(), packed.view(), 2, nullptr, maxTexels);
            for (const Layout& l : kLayouts) {
                const Strided depth(scene.depth, 1 + l.xExtra, l.rowPad, kNaN);
                const Strided normal(scene.normal, 3 + l.xExtra, l.rowPad, kNaN);
                Strided ao(W, H, 1, 1 + l.xExtra, l.rowPad);
                gpu::GlTimings t;
                gl.runHbao(p, depth.view, normal.view, ao.view, 2, &t, maxTexels);
                EXPECT_EQ(t.tiles > 1, maxTexels > 0);
                EXPECT_TRUE(sameBits(packed, ao.packed())) << device << " tiles " << t.tiles << " extra " << l.xExtra;
                EXPECT_EQ(ao.sparesWritten(), 0) << device;
            }
        }
    }
}

// Deep input and HBAO's GI: strided deep pairs, radiance and normal words and outputs give the
// packed result.
TEST(GlStridedViews, DeepGiAnyLayoutGivesThePackedResult) {
    const SceneBuffers scene = studio();
    const Image deep = deepLayersFromDepth(scene.depth, {{0.0f, 0.0f}, {0.05f, 0.3f}, {0.5f, 0.5f}});
    OperatorInputs in = scene.inputs();
    in.deepLayers = deep.view();
    Settings s = hbaoSettings(Weighting::Cosine, Falloff::None, 1.0f);
    s.thickness = 0.5f;
    s.bounce = true;
    const KernelParams p = makeKernelParams(in, s);
    ASSERT_EQ(p.deepLayers, 3);
    Image words(W, H, 3);  // a packed RGB word per layer: greys 0.25, 0.5, 0.75 by layer
    for (size_t i = 0; i < words.pixels.size(); ++i) {
        const uint32_t m = 64u * (uint32_t)(i % 3 + 1), bits = 16u << 27 | m | m << 9 | m << 18;
        std::memcpy(&words.pixels[i], &bits, sizeof bits);
    }
    Image facing(W, H, 1);  // the normals' words: any bits, read alike whatever the layout
    for (size_t i = 0; i < facing.pixels.size(); ++i) {
        const uint32_t bits = (uint32_t)(i * 2654435761u) & 0x3fffffffu;
        std::memcpy(&facing.pixels[i], &bits, sizeof bits);
    }
    for (const std::string& device : glDevicesUnderTest()) {
        gpu::GlBackend& gl = gpu::glBackendFor(device);
        for (long long maxTexels : {0LL, kManyTiles}) {
            Image ao(W, H, 1), gi(W, H, 3);
            gl.runHbaoGi(p, in.depth, in.normal, in.deepLayers, words.view(), facing.view(), ao.view(), gi.view(), 1,
                         nullptr, maxTexels);
            for (const Layout& l : kLayouts) {
                const Strided sDeep(deep, 6 + l.xExtra, l.rowPad, kNaN), sWords(words, 3 + l.xExtra, l.rowPad, kNaN);
                const Strided sFacing(facing, 1 + l.xExtra, l.rowPad, kNaN);
                Strided sAo(W, H, 1, 1 + l.xExtra, l.rowPad), sGi(W, H, 3, 3 + l.xExtra, l.rowPad);
                gl.runHbaoGi(p, in.depth, in.normal, sDeep.view, sWords.view, sFacing.view, sAo.view, sGi.view, 1, nullptr,
                             maxTexels);
                EXPECT_TRUE(sameBits(ao, sAo.packed())) << device << " " << maxTexels << " extra " << l.xExtra;
                EXPECT_TRUE(sameBits(gi, sGi.packed())) << device << " " << maxTexels << " extra " << l.xExtra;
                EXPECT_EQ(sAo.sparesWritten() + sGi.sparesWritten(), 0) << device;
            }
        }
    }
}

// The depth's own normals into the RGB of an RGBA plane (a texel's fourth float left alone).
TEST(GlStridedViews, DepthNormalsIntoAnRgbaPlane) {
    const SceneBuffers scene = studio();
    const KernelParams p = makeKernelParams(scene.inputs(), Settings());
    for (const std::string& device : glDevicesUnderTest()) {
        gpu::GlBackend& gl = gpu::glBackendFor(device);
        Image packed(W, H, 3);
        gl.runDepthNormals(p, scene.depth.view(), packed.view());
        const Strided depth(scene.depth, 1, 9, kNaN);
        Strided rgba(W, H, 3, 4, 0);
        gl.runDepthNormals(p, depth.view, rgba.view);
        EXPECT_TRUE(sameBits(packed, rgba.packed())) << device;
        EXPECT_EQ(rgba.sparesWritten(), 0) << device;
    }
}

// Through the operator, as the Python and OFX hosts call it with their views: SSDO with its
// bounce (radiance, albedo) and disc AO with blur, each from strided planes.
TEST(GlStridedViews, OperatorFromStridedViews) {
    const SceneBuffers scene = studio();
    Image radiance(W, H, 3), albedo(W, H, 3);
    for (int i = 0; i < W * H; ++i)
        for (int c = 0; c < 3; ++c) {
            radiance.pixels[3 * i + c] = 0.2f + 0.3f * c + 0.5f * scene.normal.pixels[3 * i + 1];
            albedo.pixels[3 * i + c] = 0.8f - 0.2f * c;
        }
    const Strided depth(scene.depth, 1, 7, kNaN), normal(scene.normal, 4, 2, kNaN);
    const Strided sRadiance(radiance, 4, 1, kNaN), sAlbedo(albedo, 3, 6, kNaN);
    OperatorInputs packed = scene.inputs(), strided = scene.inputs();
    packed.radiance = radiance.view();
    packed.albedo = albedo.view();
    strided.depth = depth.view;
    strided.normal = normal.view;
    strided.radiance = sRadiance.view;
    strided.albedo = sAlbedo.view;
    for (const std::string& device : glDevicesUnderTest())
        for (const char* method : {"ssdo", "discs"}) {
            Settings s;
            s.method = method;
            s.device = device;
            s.radius = 0.8f;
            s.blur = 1;
            s.bounce = std::string(method) == "ssdo";
            const OperatorOutputs a = runOperator(packed, s), b = runOperator(strided, s);
            ASSERT_EQ(b.stats.device.rfind(device, 0), 0u) << b.stats.device;
            EXPECT_TRUE(sameBits(a.ao, b.ao)) << device << " " << method;
            EXPECT_TRUE(sameBits(a.directional, b.directional)) << device << " " << method;
            EXPECT_TRUE(sameBits(a.indirect, b.indirect)) << device << " " << method;
        }
}
