// In-memory planes: the currency of the operator. Views never own; Image owns.
#pragma once
#include <cstddef>
#include <type_traits>
#include <vector>

namespace obscura {

// Pixel rectangle, half-open: [x0, x1) × [y0, y1). Coordinates are in the
// display window's frame (display min = 0,0), y down like EXR rows.
struct Box2i {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    int width() const { return x1 - x0; }
    int height() const { return y1 - y0; }
    bool empty() const { return x1 <= x0 || y1 <= y0; }
    long long area() const { return empty() ? 0 : (long long)width() * height(); }
    bool contains(int x, int y) const { return x >= x0 && x < x1 && y >= y0 && y < y1; }
    bool operator==(const Box2i& o) const { return x0 == o.x0 && y0 == o.y0 && x1 == o.x1 && y1 == o.y1; }
    bool operator!=(const Box2i& o) const { return !(*this == o); }
};

inline Box2i intersect(const Box2i& a, const Box2i& b) {
    Box2i r{a.x0 > b.x0 ? a.x0 : b.x0, a.y0 > b.y0 ? a.y0 : b.y0,
            a.x1 < b.x1 ? a.x1 : b.x1, a.y1 < b.y1 ? a.y1 : b.y1};
    if (r.empty()) r = Box2i{};
    return r;
}

// A strided view of `channels` floats per pixel. Strides are in floats, so a
// numpy array, an OFX clip or an interleaved buffer can be viewed without copying.
template <class T>
struct PlaneView {
    T* data = nullptr;
    int width = 0, height = 0, channels = 0;
    std::ptrdiff_t xStride = 0, yStride = 0;

    bool valid() const { return data != nullptr && width > 0 && height > 0; }
    // A mutable view reads as a const one.
    template <class U = T, class = std::enable_if_t<!std::is_const_v<U>>>
    operator PlaneView<const U>() const { return {data, width, height, channels, xStride, yStride}; }
    T* at(int x, int y) const { return data + y * yStride + x * xStride; }
};
using ConstPlane = PlaneView<const float>;
using MutablePlane = PlaneView<float>;

// Owning, tightly packed, interleaved float image.
struct Image {
    int width = 0, height = 0, channels = 0;
    std::vector<float> pixels;

    Image() = default;
    Image(int w, int h, int c, float fill = 0.0f)
        : width(w), height(h), channels(c), pixels((std::size_t)w * h * c, fill) {}

    bool empty() const { return pixels.empty(); }
    float* at(int x, int y) { return pixels.data() + ((std::size_t)y * width + x) * channels; }
    const float* at(int x, int y) const { return pixels.data() + ((std::size_t)y * width + x) * channels; }
    MutablePlane view() { return {pixels.data(), width, height, channels, channels, (std::ptrdiff_t)width * channels}; }
    ConstPlane view() const { return {pixels.data(), width, height, channels, channels, (std::ptrdiff_t)width * channels}; }
};

} // namespace obscura
