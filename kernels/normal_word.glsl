// A texel's normal in one word, in a plane beside the bounce source's words
// (kernels/shared_exponent.glsl), for HBAO's light to tell which faces a receiver sees
// (hbao_gi.glsl's facesReceiver): one gather where the pass's three floats took three, and the
// sign of a dot product is all it needs. Each component as a 10-bit number, the normal scaled so that its
// largest component is +-511 (so any length packs alike); a zero or non-finite normal packs as
// zero, which the light takes as facing (it sends, as it would without the test).

luint normalComponentBits(lfloat c) {
    return luint(lint(c + select(c < 0.0f, lfloat(-0.5f), lfloat(0.5f))) + lint(512));
}

// The word of normal n turned to face the eye (`toEye` points towards it), so that the light
// compares one sign.
luint packNormalWord(lvec3 n, lvec3 toEye) {
    n = select(dot(n, toEye) < 0.0f, -n, n);
    lfloat most = max(max(abs(n.x), abs(n.y)), abs(n.z));
    lfloat sum = abs(n.x) + abs(n.y) + abs(n.z); // NaN or inf when any component is
    lbool usable = sum > 0.0f && sum <= 3.4028235e38f;
    lfloat scale = select(usable, 511.0f / select(usable, most, lfloat(1.0f)), lfloat(0.0f));
    lvec3 m = select(usable, n, lvec3(lfloat(0.0f), lfloat(0.0f), lfloat(0.0f))) * scale;
    return normalComponentBits(m.x) | (normalComponentBits(m.y) << 10u) | (normalComponentBits(m.z) << 20u);
}

lvec3 normalFromWord(luint bits) {
    return lvec3(lfloat(bits & luint(1023u)) - 512.0f, lfloat((bits >> 10u) & luint(1023u)) - 512.0f,
                 lfloat((bits >> 20u) & luint(1023u)) - 512.0f);
}
