// Low-discrepancy sampling: 2D Sobol points, Owen-scrambled per pixel and per
// use with hash-based nested uniform scrambling (Burley 2020, "Practical
// Hash-based Owen Scrambling"), mapped to the hemisphere around a normal.
#pragma once
#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace reference {

inline uint32_t hash32(uint32_t x) {  // lowbias32 (Wellons)
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
}
inline uint32_t hashCombine(uint32_t seed, uint32_t v) { return hash32(seed ^ (v + 0x9e3779b9u + (seed << 6) + (seed >> 2))); }

inline uint32_t reverseBits(uint32_t x) {
    x = (x << 16) | (x >> 16);
    x = ((x & 0x00ff00ffu) << 8) | ((x & 0xff00ff00u) >> 8);
    x = ((x & 0x0f0f0f0fu) << 4) | ((x & 0xf0f0f0f0u) >> 4);
    x = ((x & 0x33333333u) << 2) | ((x & 0xccccccccu) >> 2);
    x = ((x & 0x55555555u) << 1) | ((x & 0xaaaaaaaau) >> 1);
    return x;
}

// Owen scrambling of a 32-bit fixed-point value: every bit flipped by a hash of the bits above it.
inline uint32_t owenScramble(uint32_t x, uint32_t seed) {
    x = reverseBits(x);
    x += seed;  // Laine-Karras permutation on the reversed bits
    x ^= x * 0x6c50b47cu;
    x ^= x * 0xb82f1e52u;
    x ^= x * 0xc7afe638u;
    x ^= x * 0x8d22f6e6u;
    return reverseBits(x);
}

// The first two Sobol dimensions (van der Corput, and the x + 1 polynomial).
inline uint32_t sobol0(uint32_t i) { return reverseBits(i); }
// Dimension 1 is linear over GF(2) in the index bits: XOR of one table entry per index byte.
struct Sobol1Tables {
    uint32_t byte[4][256];
    Sobol1Tables() {
        uint32_t direction[32];
        direction[0] = 1u << 31;
        for (int k = 1; k < 32; ++k) direction[k] = direction[k - 1] ^ (direction[k - 1] >> 1);
        for (int b = 0; b < 4; ++b)
            for (uint32_t v = 0; v < 256; ++v) {
                uint32_t r = 0;
                for (int k = 0; k < 8; ++k)
                    if (v & (1u << k)) r ^= direction[8 * b + k];
                byte[b][v] = r;
            }
    }
};
inline uint32_t sobol1(uint32_t i) {
    static const Sobol1Tables t;
    return t.byte[0][i & 255] ^ t.byte[1][(i >> 8) & 255] ^ t.byte[2][(i >> 16) & 255] ^ t.byte[3][i >> 24];
}

// A scrambled 2D Sobol set in [0,1)^2. Each (pixel, use) gets its own seed, so
// sets are decorrelated between pixels and between uses in one pixel.
class SobolSet {
public:
    explicit SobolSet(uint32_t seed)
        : shuffle_(hashCombine(seed, 0x5eedu)), scrambleX_(hashCombine(seed, 1)), scrambleY_(hashCombine(seed, 2)) {}
    glm::dvec2 operator()(uint32_t i) const {
        const uint32_t index = owenScramble(i, shuffle_);  // shuffles the order, keeps the net property
        constexpr double k = 1.0 / 4294967296.0;
        return {owenScramble(sobol0(index), scrambleX_) * k, owenScramble(sobol1(index), scrambleY_) * k};
    }

private:
    uint32_t shuffle_, scrambleX_, scrambleY_;
};

// Orthonormal basis around unit n (Duff et al. 2017).
inline void basis(const glm::dvec3& n, glm::dvec3& t, glm::dvec3& b) {
    const double sign = std::copysign(1.0, n.z), a = -1.0 / (sign + n.z), c = n.x * n.y * a;
    t = {1.0 + sign * n.x * n.x * a, sign * c, -sign * n.x};
    b = {c, sign + n.y * n.y * a, -n.y};
}

constexpr double kTwoPi = 6.283185307179586;

// Uniform in solid angle over the hemisphere (pdf 1 / 2pi): cos(theta) = u.x.
inline glm::dvec3 uniformHemisphere(glm::dvec2 u) {
    const double z = u.x, r = std::sqrt(std::max(0.0, 1.0 - z * z));
    const float phi = float(kTwoPi * u.y);  // float trig: Embree's rays are float anyway
    return {r * std::cos(phi), r * std::sin(phi), z};
}
// Cosine-weighted (pdf cos / pi): uniform on the unit disk, lifted.
inline glm::dvec3 cosineHemisphere(glm::dvec2 u) {
    const double r = std::sqrt(u.x);
    const float phi = float(kTwoPi * u.y);
    return {r * std::cos(phi), r * std::sin(phi), std::sqrt(std::max(0.0, 1.0 - u.x))};
}

inline glm::dvec3 toWorld(const glm::dvec3& local, const glm::dvec3& n) {
    glm::dvec3 t, b;
    basis(n, t, b);
    return local.x * t + local.y * b + local.z * n;
}

} // namespace reference
