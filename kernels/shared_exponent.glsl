// The bounce source's texel word: RGB with a shared exponent, as GL's RGB9_E5 texture format:
// 9-bit mantissas m and a 5-bit exponent e, channel = m 2^(e - 24). The CPU packs the source once
// a frame (packSharedExponent, cpu/pack_tile_impl.h); hbao_gi.glsl unpacks a word per sample, as
// it reads one depth, not three floats (their gathers were most of the light's cost).

lvec3 sharedExponentRgb(luint bits) {
    lfloat scale = uintBitsToFloat(((bits >> 27u) + luint(103u)) << 23u); // 2^(e - 15 - 9)
    lfloat r = lfloat(bits & luint(511u));
    lfloat g = lfloat((bits >> 9u) & luint(511u));
    lfloat b = lfloat((bits >> 18u) & luint(511u));
    return lvec3(r * scale, g * scale, b * scale);
}

// A channel as the word holds it: clamped to [0, 65408]; non-finite (a renderer's bad pixel): 0.
lfloat sourceChannel(lfloat v) {
    return select(lfloat(3.4028235e38f) >= abs(v), min(max(v, 0.0f), 65408.0f), lfloat(0.0f));
}

// The mantissa of channel c under the exponent whose 2^(24 - e) is `inverse`, rounded.
luint sharedMantissa(lfloat c, lfloat inverse) {
    return luint(min(lint(c * inverse + 0.5f), lint(511)));
}

luint packSharedExponent(lvec3 rgb) {
    lfloat r = sourceChannel(rgb.x);
    lfloat g = sourceChannel(rgb.y);
    lfloat b = sourceChannel(rgb.z);
    lfloat most = max(max(r, g), b);
    // e = 15 + the exponent x of the largest (most = f 2^x, f in [0.5, 1)), clamped to [0, 31]: a
    // normal float's biased exponent less 126; denormals give 0, and 0 takes 15.
    lint biased = lint(floatBitsToUint(most) >> 23u);
    lint e = select(most > 0.0f, clamp(biased - lint(111), lint(0), lint(31)), lint(15));
    // A largest that rounds up to 512 takes the next exponent (rounding is monotone, so it holds
    // the largest mantissa). uintBitsToFloat((151 - e) << 23) = 2^(24 - e), exact.
    lfloat inverse = uintBitsToFloat(luint(lint(151) - e) << 23u);
    lbool carries = lint(most * inverse + 0.5f) >= lint(512) && e < lint(31);
    e = select(carries, e + lint(1), e);
    inverse = uintBitsToFloat(luint(lint(151) - e) << 23u);
    return (luint(e) << 27u) | sharedMantissa(r, inverse) | (sharedMantissa(g, inverse) << 9u) |
           (sharedMantissa(b, inverse) << 18u);
}
