// Deep elements without a flat file (docs/deep.md): one or more deep EXRs rendered apart, their
// samples merged per pixel by depth and flattened front to back (OpenEXR's deep compositing
// rules), with the surfaces HBAO reads as deep layers: of the merge, and per element with that
// element's own visible surface first.
#pragma once
#include "base/image.h"
#include "io/deep_file.h"
#include "io/exr_file.h"
#include "io/layers.h"
#include "io/deep_samples.h"

#include <string>
#include <vector>

namespace obscura {

struct DeepElement {
    std::string path;
    ExrPart part;            // its first part's header, channels listed
    DeepChannels samples;
    int z = -1, zBack = -1;  // channel indices in samples.names (zBack -1: point samples)
};

// The channels a header lists (a deep part's too: readExrInfo leaves them out), by name.
std::vector<ExrChannel> headerChannels(const Imf::Header& header);

// Reads every channel of a deep file. Throws FileError for a flat file, one without the depth
// channel `names.z`, or a window over maxPixels (checked before reading).
DeepElement readDeepElement(const std::string& path, const DeepChannelNames& names, long long maxPixels);

struct DeepMerge {
    Box2i display, data;
    std::vector<ExrChannel> channels;  // flattened: every channel but the depths, by name, over all elements
    std::vector<Image> flat;           // one plane per channel over `data`
    Image front;                       // the nearest sample's Z per pixel; +inf where there is none
    Image layers;                      // the merge's surfaces (DeepLayerBuilder::planes)
    Image colour;                      // with colour, when R, G and B are merged: their colours (colourPlanes)
    int layerCount = 0;
    std::vector<Image> elementFront, elementLayers;  // per element, when asked: its own surface first
    long long samples = 0, droppedSamples = 0, emptyPixels = 0, truncatedPixels = 0;
};

// Merges the elements' samples, on `threads` threads (0: every core); maxLayers 0 flattens them
// and builds no surfaces (`layers` empty, layerCount 0); with `colour`, the merge's surfaces'
// colours too, each from its own samples (so each element's). Throws FileError naming
// the element whose display or data window is not the first element's.
DeepMerge mergeDeepElements(const std::vector<DeepElement>& elements, int maxLayers, bool perElement, int threads = 0,
                            bool colour = false);

// readDeepElement of each path, `threads` files at a time (0: every core); the first failure in
// the paths' order is thrown.
std::vector<DeepElement> readDeepElements(const std::vector<std::string>& paths, const DeepChannelNames& names,
                                          long long maxPixels, int threads = 0);

// Front-to-back "over" of one pixel's samples, each `stride` floats: Z, ZBack, then the flattened
// channels, premultiplied, alpha at `alpha` among them (-1: every sample opaque). Sorted by
// (Z, ZBack). Overlapping volume samples are split where other samples begin or end and samples
// over the same range combined, as "Interpreting OpenEXR Deep Pixels" defines; `scratch` is
// reused between calls. Writes `stride - 2` floats to out.
void flattenSamples(const float* samples, size_t n, int stride, int alpha, std::vector<float>& scratch, float* out);

} // namespace obscura
