#include "deep_output.h"

#include "render.h"
#include "sampling.h"

#include <OpenImageIO/deepdata.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <filesystem>
#include <limits>
#include <stdexcept>

namespace reference {

namespace {

// Spans from the hits along one ray: a front face opens a solid (nesting counted, so
// overlapping shapes make one span), the back face that closes the outermost ends it. With
// `light`, the opening hit's colour: the first span's with the pixel's own seed, as the flat
// render's primary hit, the others with seeds of their own.
std::vector<DeepSpan> raySpans(const Tracer& tracer, const glm::dvec3& eye, const glm::dvec3& ray, int maxHits,
                               const Integrator* light, uint32_t pixelSeed) {
    std::vector<DeepSpan> spans;
    int inside = 0;
    float tnear = 0;
    for (int i = 0; i < maxHits; ++i) {
        const Hit h = tracer.intersect(eye, ray, tnear, std::numeric_limits<float>::infinity());
        if (!h.found) break;
        if (!h.backFace) {
            if (inside++ == 0) {
                spans.push_back({h.t, h.t});
                if (light) {
                    const glm::dvec3 p = eye + double(h.t) * ray;
                    const uint32_t seed = spans.size() == 1 ? pixelSeed : hashCombine(pixelSeed, uint32_t(spans.size()));
                    spans.back().colour =
                        h.albedo * light->directDiffuse(p, h.normal, offsetEpsilon(p, h.t * glm::length(ray)), seed);
                }
            }
        } else if (inside > 0 && --inside == 0) {
            spans.back().back = h.t;
        }
        // Past this hit: float t carries about 7 digits, so step a few ulps of it.
        tnear = h.t * (1.0f + 4e-6f) + 1e-7f;
    }
    return spans;
}

} // namespace

DeepFrame traceDeep(const Tracer& tracer, const PinholeCamera& camera, int threads, const Integrator* light,
                    int maxHits) {
    DeepFrame f;
    f.width = camera.width;
    f.height = camera.height;
    f.coloured = light != nullptr;
    f.pixels.resize(size_t(f.width) * f.height);
    forEachRow(f.height, threads, [&](int y) {
        for (int x = 0; x < f.width; ++x)
            f.pixels[size_t(y) * f.width + x] = raySpans(tracer, camera.eye, camera.ray(x + 0.5, y + 0.5), maxHits, light,
                                                         light ? light->pixelSeed(x, y) : 0u);
    });
    return f;
}

void writeDeep(const std::string& path, const DeepFrame& frame) {
    // Channels A, Z, ZBack, then R, G, B when coloured (A = 1: premultiplied RGB is the colour).
    const int colourChannel = 3, channels = frame.coloured ? 6 : 3;
    OIIO::ImageSpec spec(frame.width, frame.height, channels, OIIO::TypeDesc::FLOAT);
    spec.channelnames = {"A", "Z", "ZBack"};
    if (frame.coloured) spec.channelnames.insert(spec.channelnames.end(), {"R", "G", "B"});
    spec.alpha_channel = 0;
    spec.z_channel = 1;
    spec.deep = true;
    spec.attribute("compression", "zips");
    OIIO::DeepData dd;
    dd.init(spec);
    for (size_t p = 0; p < frame.pixels.size(); ++p) dd.set_samples(int64_t(p), int(frame.pixels[p].size()));
    for (size_t p = 0; p < frame.pixels.size(); ++p)
        for (size_t s = 0; s < frame.pixels[p].size(); ++s) {
            const DeepSpan& span = frame.pixels[p][s];
            constexpr float alpha = 1.0f;
            dd.set_deep_value(int64_t(p), 0, int(s), alpha);
            dd.set_deep_value(int64_t(p), 1, int(s), span.front);
            dd.set_deep_value(int64_t(p), 2, int(s), span.back);
            for (int c = 0; frame.coloured && c < 3; ++c)
                dd.set_deep_value(int64_t(p), colourChannel + c, int(s), alpha * span.colour[c]);
        }
    const std::string temp = path + ".tmp";
    auto out = OIIO::ImageOutput::create(path);
    if (!out || !out->open(temp, spec) || !out->write_deep_image(dd) || !out->close())
        throw std::runtime_error("cannot write the deep image '" + path + "': " +
                                 (out ? out->geterror() : OIIO::geterror()));
    std::filesystem::rename(temp, path);
}

} // namespace reference
