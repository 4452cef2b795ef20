#include "core/environment.h"

#include <algorithm>

namespace obscura {

namespace {

// One 2x2 box-filter step; odd sizes keep their last row/column.
Image halve(const Image& src) {
    Image dst(std::max(1, src.width / 2), std::max(1, src.height / 2), src.channels);
    for (int y = 0; y < dst.height; ++y)
        for (int x = 0; x < dst.width; ++x)
            for (int c = 0; c < src.channels; ++c) {
                float sum = 0;
                int n = 0;
                for (int dy = 0; dy < 2; ++dy)
                    for (int dx = 0; dx < 2; ++dx) {
                        const int sx = std::min(2 * x + dx, src.width - 1), sy = std::min(2 * y + dy, src.height - 1);
                        sum += src.at(sx, sy)[c];
                        ++n;
                    }
                dst.at(x, y)[c] = sum / n;
            }
    return dst;
}

} // namespace

Image prefilterLatLong(const Image& latLong, int samples) {
    // A lat-long texel covers on average 4 pi / (W H) sr; a sample stands for 2 pi / n sr,
    // so the matching level has about 2 n texels.
    const long long target = 2LL * std::max(samples, 1);
    Image level = latLong;
    while ((long long)level.width * level.height / 4 >= target && level.width > 1 && level.height > 1)
        level = halve(level);
    return level;
}

} // namespace obscura
