// libobscura_oiio.so: everything obscura calls in OpenImageIO (io/oiio_module.h says why it
// is a library of its own).
#include "io/oiio_module.h"

#include "base/error.h"

#include <OpenImageIO/imageio.h>

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

const OiioModule kModule{kOiioModuleAbi, &readRgb};

} // namespace
} // namespace obscura

extern "C" __attribute__((visibility("default"))) const obscura::OiioModule* obscuraOiioModule() {
    return &obscura::kModule;
}
