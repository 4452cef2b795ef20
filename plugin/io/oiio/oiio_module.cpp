// libobscura_oiio.so: everything obscura calls in OpenImageIO (io/oiio_module.h says why it
// is a library of its own).
#include "io/oiio_module.h"

#include "base/error.h"

#include <OpenImageIO/deepdata.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cstring>

namespace obscura {

// Visible: tests call it (io/colour.h declares it).
__attribute__((visibility("default"))) ColourMetadata colourMetadata(const OIIO::ImageSpec& spec) {
    ColourMetadata m;
    m.colorInteropID = spec.get_string_attribute("colorInteropID");
    m.oiioColorSpace = spec.get_string_attribute("oiio:ColorSpace");
    float c[8];
    if (spec.getattribute("chromaticities", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 8), c))
        m.chromaticities = Imf::Chromaticities(Imath::V2f(c[0], c[1]), Imath::V2f(c[2], c[3]),
                                               Imath::V2f(c[4], c[5]), Imath::V2f(c[6], c[7]));
    return m;
}

namespace {

std::string oiioError(const std::string& message) { return firstLineOf(message, "unknown OpenImageIO error"); }

std::string probe(const std::string& path, int& width, int& height, int& channels, bool& deep) {
    auto in = OIIO::ImageInput::open(path);
    if (!in) return oiioError(OIIO::geterror());
    const OIIO::ImageSpec& spec = in->spec();
    width = spec.width;
    height = spec.height;
    channels = spec.nchannels;
    deep = spec.deep;
    return {};
}

std::string readRgb(const std::string& path, const std::function<void(int, int, int)>& accept, Image& rgb,
                    ColourMetadata& meta) {
    auto in = OIIO::ImageInput::open(path);
    if (!in) return oiioError(OIIO::geterror());
    const OIIO::ImageSpec& spec = in->spec();
    accept(spec.width, spec.height, spec.nchannels);
    if (spec.nchannels < 3) return "fewer than 3 channels";
    rgb = Image(spec.width, spec.height, 3);
    if (!in->read_image(0, 0, 0, 3, OIIO::TypeDesc::FLOAT, rgb.pixels.data())) return oiioError(in->geterror());
    meta = colourMetadata(spec);
    return {};
}

std::string writePng(const std::string& path, int width, int height, int channels, const std::uint8_t* bytes,
                     const std::string& colourSpaceTag) {
    auto out = OIIO::ImageOutput::create("png");
    if (!out) return oiioError(OIIO::geterror());
    OIIO::ImageSpec spec(width, height, channels, OIIO::TypeDesc::UINT8);
    if (!colourSpaceTag.empty()) spec.attribute("oiio:ColorSpace", colourSpaceTag);  // data previews stay untagged
    spec.attribute("Software", "obscura");
    bool ok = out->open(path, spec) && out->write_image(OIIO::TypeDesc::UINT8, bytes);
    ok = out->close() && ok;
    return ok ? std::string() : oiioError(out->geterror());
}

// Channels [chBegin, chEnd) of a deep image into dd, and its windows and counts into `out`;
// returns the total of samples, or -1 (the error in *error) when it cannot be read.
long long readNativeDeep(OIIO::ImageInput& in, int chBegin, int chEnd, OIIO::DeepData& dd, DeepWindows& out,
                         std::string* error) {
    const OIIO::ImageSpec spec = in.spec();
    const bool read = spec.tile_width > 0
                          ? in.read_native_deep_tiles(0, 0, spec.x, spec.x + spec.width, spec.y, spec.y + spec.height,
                                                      spec.z, spec.z + spec.depth, chBegin, chEnd, dd)
                          : in.read_native_deep_scanlines(0, 0, spec.y, spec.y + spec.height, spec.z, chBegin, chEnd, dd);
    if (!read) {
        *error = oiioError(in.geterror());
        return -1;
    }
    out.fullWidth = spec.full_width;
    out.fullHeight = spec.full_height;
    out.x = spec.x - spec.full_x;
    out.y = spec.y - spec.full_y;
    out.width = spec.width;
    out.height = spec.height;
    const OIIO::cspan<unsigned int> counts = dd.all_samples();
    out.counts.assign(counts.begin(), counts.end());
    long long total = 0;
    for (unsigned int n : counts) total += n;
    return total;
}

std::string readDeep(const std::string& path, const std::string& z, const std::string& zBack, DeepSamples& out) {
    auto in = OIIO::ImageInput::open(path);
    if (!in) return oiioError(OIIO::geterror());
    const OIIO::ImageSpec& spec = in->spec();
    if (!spec.deep) return "not a deep image (a flat file gives the passes with --flat)";
    const int zc = spec.channelindex(z), zBackC = spec.channelindex(zBack);
    if (zc < 0) return "deep image without a " + z + " channel";
    // Only the channels from Z to ZBack (adjacent in OpenEXR's sorted list), not colour or ids.
    const int chBegin = zBackC >= 0 ? std::min(zc, zBackC) : zc, chEnd = std::max(zc, zBackC) + 1;
    OIIO::DeepData dd;
    std::string error;
    const long long total = readNativeDeep(*in, chBegin, chEnd, dd, out, &error);
    if (total < 0) return error;
    out.hasZBack = zBackC >= 0;
    out.z.reserve(total);
    if (out.hasZBack) out.zBack.reserve(total);
    for (int64_t p = 0, pixels = (int64_t)out.width * out.height; p < pixels; ++p)
        for (int s = 0; s < dd.samples(p); ++s) {
            out.z.push_back(dd.deep_value(p, zc - chBegin, s));
            if (out.hasZBack) out.zBack.push_back(dd.deep_value(p, zBackC - chBegin, s));
        }
    return {};
}

std::string readDeepChannels(const std::string& path, DeepChannels& out) {
    auto in = OIIO::ImageInput::open(path);
    if (!in) return oiioError(OIIO::geterror());
    const OIIO::ImageSpec& spec = in->spec();
    if (!spec.deep) return "not a deep image";
    const int nc = spec.nchannels;
    OIIO::DeepData dd;
    std::string error;
    const long long total = readNativeDeep(*in, 0, nc, dd, out, &error);
    if (total < 0) return error;
    out.names.assign(spec.channelnames.begin(), spec.channelnames.end());
    out.values.resize((size_t)total * nc);
    float* v = out.values.data();
    bool allFloat = true;  // then each pixel's samples are nc floats each, one after another
    for (int c = 0; c < nc; ++c) allFloat = allFloat && dd.channeltype(c) == OIIO::TypeDesc::FLOAT;
    for (int64_t p = 0, pixels = (int64_t)out.width * out.height; p < pixels; ++p) {
        const int n = dd.samples(p);
        if (allFloat && n > 0) {
            std::memcpy(v, dd.data_ptr(p, 0, 0), sizeof(float) * nc * n);
            v += (size_t)nc * n;
            continue;
        }
        for (int s = 0; s < n; ++s)
            for (int c = 0; c < nc; ++c) *v++ = dd.deep_value(p, c, s);
    }
    return {};
}

const OiioModule kModule{kOiioModuleAbi, &probe, &readRgb, &writePng, &readDeep, &readDeepChannels};

} // namespace
} // namespace obscura

extern "C" __attribute__((visibility("default"))) const obscura::OiioModule* obscuraOiioModule() {
    return &obscura::kModule;
}
