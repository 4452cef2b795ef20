#include "contact_sheet.h"

#include "io/preview.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

namespace report {

namespace OIIO = OIIO_NAMESPACE;
using OIIO::ImageBuf;
using OIIO::ImageSpec;
using OIIO::ROI;
using OIIO::TypeDesc;
namespace IBA = OIIO::ImageBufAlgo;

namespace {

constexpr int kMargin = 6, kLabel = 22, kBarHeight = 12, kBarText = 18;
const float kSkyGrey[3] = {0.35f, 0.35f, 0.35f};

// obscura's one display encoding (io/preview.h), so a panel is what --preview shows. Infinite
// values show as black here: a beauty's infinities are no light to show.
float srgbOetf(float v) { return obscura::srgbOetf(std::isfinite(v) ? v : 0.0f); }

ImageBuf rgbBuf(int w, int h) { return ImageBuf(ImageSpec(w, h, 3, TypeDesc::FLOAT)); }

ImageBuf beautyPanel(const std::string& exrPath, int w, int h) {
    ImageBuf in(exrPath);
    if (!in.read(0, 0, true, TypeDesc::FLOAT)) throw std::runtime_error("cannot read " + exrPath + ": " + in.geterror());
    const ImageSpec& spec = in.spec();
    int channel[3];
    const char* names[3] = {"ViewLayer.Combined.R", "ViewLayer.Combined.G", "ViewLayer.Combined.B"};
    for (int c = 0; c < 3; ++c)
        if ((channel[c] = spec.channelindex(names[c])) < 0)
            throw std::runtime_error(std::string("no channel ") + names[c] + " in " + exrPath);
    ImageBuf out = rgbBuf(w, h);
    float px[3];
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            for (int c = 0; c < 3; ++c)
                px[c] = srgbOetf(in.getchannel(spec.x + x, spec.y + y, 0, channel[c]));
            out.setpixel(x, y, px, 3);
        }
    return out;
}

ImageBuf greyPanel(const obscura::Image& img) {
    ImageBuf out = rgbBuf(img.width, img.height);
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
            const float v = srgbOetf(*img.at(x, y));
            const float px[3] = {v, v, v};
            out.setpixel(x, y, px, 3);
        }
    return out;
}

ImageBuf heatPanel(const SheetPanels& p) {
    const int w = p.ao->width, h = p.ao->height;
    ImageBuf scaled(ImageSpec(w, h, 1, TypeDesc::FLOAT));
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const float e = std::abs(*p.ao->at(x, y) - *p.reference->at(x, y));
            const float v = std::isfinite(e) ? float(std::min(1.0, e / p.heatMax)) : 1.0f;
            scaled.setpixel(x, y, &v, 1);
        }
    ImageBuf heat = IBA::color_map(scaled, 0, "inferno");
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const float d = *p.depth->at(x, y);
            if (!(d > 0.0f && d < p.skyDepth)) heat.setpixel(x, y, kSkyGrey, 3);
        }
    return heat;
}

ImageBuf scaleBar(int w) {
    ImageBuf ramp(ImageSpec(w, kBarHeight, 1, TypeDesc::FLOAT));
    for (int y = 0; y < kBarHeight; ++y)
        for (int x = 0; x < w; ++x) {
            const float v = w > 1 ? float(x) / float(w - 1) : 0.0f;
            ramp.setpixel(x, y, &v, 1);
        }
    return IBA::color_map(ramp, 0, "inferno");
}

std::string fixed(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3g", v);
    return buf;
}

// Draws `text` with the first font OpenImageIO finds; false when none works.
bool label(ImageBuf& sheet, int x, int y, const std::string& text, int size,
           OIIO::ImageBufAlgo::TextAlignX align = OIIO::ImageBufAlgo::TextAlignX::Left) {
    static const char* const fonts[] = {"DejaVuSans", "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf", ""};
    static int working = -1;  // index of the font that worked, -2 when none did
    if (working == -2) return false;
    const float white[3] = {1, 1, 1};
    for (int i = working >= 0 ? working : 0; i < 3; ++i) {
        if (IBA::render_text(sheet, x, y, text, size, fonts[i], white, align)) {
            working = i;
            return true;
        }
        (void)sheet.geterror();  // clear the error before the next font
        if (working >= 0) break;
    }
    working = -2;
    return false;
}

} // namespace

bool writeContactSheet(const std::string& pngPath, const SheetPanels& p) {
    const int w = p.ao->width, h = p.ao->height;
    const int cellW = w + kMargin, cellH = kLabel + h;
    const int sheetW = kMargin + 2 * cellW, sheetH = kMargin + 2 * cellH + kMargin + kBarHeight + kBarText;
    ImageBuf sheet = rgbBuf(sheetW, sheetH);
    const float background[3] = {0.08f, 0.08f, 0.08f};
    IBA::fill(sheet, background);

    const ImageBuf panels[4] = {beautyPanel(p.exrPath, w, h), greyPanel(*p.ao), greyPanel(*p.reference), heatPanel(p)};
    const std::string titles[4] = {"beauty (sRGB)", p.aoLabel, p.referenceLabel, "|error|, scale below"};
    bool labels = true;
    for (int i = 0; i < 4; ++i) {
        const int x = kMargin + (i % 2) * cellW, y = kMargin + (i / 2) * cellH;
        IBA::paste(sheet, x, y + kLabel, 0, 0, panels[i]);
        labels = label(sheet, x + 2, y + kLabel - 6, titles[i], 14) && labels;
    }
    // Scale bar under the heat map: 0 at the left, heatMax (and above) at the right.
    const int barX = kMargin + cellW, barY = kMargin + 2 * cellH + kMargin;
    IBA::paste(sheet, barX, barY, 0, 0, scaleBar(w));
    if (labels) {
        label(sheet, barX, barY + kBarHeight + kBarText - 4, "0", 12);
        label(sheet, barX + w / 2, barY + kBarHeight + kBarText - 4, fixed(p.heatMax / 2), 12,
              IBA::TextAlignX::Center);
        label(sheet, barX + w, barY + kBarHeight + kBarText - 4, fixed(p.heatMax) + "+", 12, IBA::TextAlignX::Right);
        label(sheet, kMargin + 2, barY + kBarHeight + kBarText - 4, "sky: grey in the error map", 12);
    }
    const std::string tmp = pngPath + ".tmp.png";
    if (!sheet.write(tmp, TypeDesc::UINT8)) throw std::runtime_error("cannot write " + tmp + ": " + sheet.geterror());
    std::filesystem::rename(tmp, pngPath);
    return labels;
}

} // namespace report
