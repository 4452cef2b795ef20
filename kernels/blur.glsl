// Geometry-aware (cross-bilateral) blur of AO, DO or GI, one pass along `axis`, written on
// lane types (one pixel per GPU thread, a row of pixels per CPU register; cpu/lanes.h).
// Weights: Gaussian in pixels x depth similarity x normal similarity, so
// occlusion never bleeds across silhouettes or creases. Sky keeps its value.
// Requires: lfloat gatherDepth(lint x, lint y, lbool use), lvec3 gatherNormal(...) and
// lvec4 gatherSignal(...) (0 where `use` is false), params P.

CONST_GLOBAL float BLUR_DEPTH_TOLERANCE = 0.02f; // relative depth step treated as an edge (2% of depth)

// Normal similarity: cos^16 of the angle between unit normals (~0.5 weight at 17 degrees),
// by four squarings rather than a pow.
lfloat blurNormalWeight(lfloat cosAngle) {
    lfloat c = max(cosAngle, 0.0f);
    c = c * c;
    c = c * c;
    c = c * c;
    return c * c;
}

lvec3 blurNormal(lint x, lint y, lbool use) {
    lvec3 n = gatherNormal(x, y, use);
    lfloat len2 = dot(n, n);
    lbool usable = len2 > 1e-12f && len2 < 1e30f;
    return select(usable, n * inversesqrt(select(usable, len2, 1.0f)), lvec3(vec3(0.0f)));
}

// Up to four channels at once (AO in .x; DO or GI in .xyz) of the buffer texels (x, y).
lvec4 blurLanes(lint x, lint y, ivec2 axis, int radius) {
    lbool computing = insideBuffer(x, y);
    lvec4 centre = gatherSignal(x, y, computing);
    lfloat d0 = gatherDepth(x, y, computing) * P.depthScale;
    computing = computing && isSurfaceDepth(d0);
    if (!anyLane(computing) || radius <= 0) {
        return centre;
    }
    d0 = select(computing, d0, 1.0f); // lanes that sit out compute on a harmless depth
    lvec3 n0 = blurNormal(x, y, computing);
    float sigma = 0.5f * float(radius) + 0.5f;
    float invTwoSigma2 = 1.0f / (2.0f * sigma * sigma);
    // Capped: at a denormal depth the reciprocal overflows, and inf x 0 (a neighbour at the same
    // depth) would be NaN. The cap leaves every depth above 5e-29 as it was.
    lfloat invTolerance = min(1.0f / (BLUR_DEPTH_TOLERANCE * d0), 1e30f);
    // A reach in world units (P.blurReach > 0): the spatial weight also falls with a neighbour's
    // distance across the surface, about i pixel footprints, so a wide blur keeps detail of that size.
    lfloat footprint2 = lfloat(0.0f);
    if (P.blurReach > 0.0f) {
        lfloat footprint = (P.orthographic != 0 ? lfloat(P.invFx) : d0 * P.invFx) / P.blurReach;
        footprint2 = 0.5f * footprint * footprint;
    }
    // The weighted mean as the centre plus its neighbours' weighted departures from it: a region
    // of one value keeps that value exactly, where a GPU's approximate division (2.5 ulp under
    // ARB_shader_precision) would turn sum / sum into 1 +- 1 ulp, and a plane's AO would leave [0, 1].
    lvec4 departure = lvec4(lfloat(0.0f), lfloat(0.0f), lfloat(0.0f), lfloat(0.0f));
    lfloat weightSum = lfloat(1.0f);
    for (int i = -radius; i <= radius; ++i) {
        if (i == 0) {
            continue;
        }
        lint tx = x + axis.x * i;
        lint ty = y + axis.y * i;
        lbool use = computing && insideBuffer(tx, ty);
        lfloat d = gatherDepth(tx, ty, use) * P.depthScale;
        use = use && isSurfaceDepth(d);
        lfloat dz = (d - d0) * invTolerance;
        // exp(-i^2 / 2 sigma^2 - dz^2): the spatial factor is the same for every pixel.
        float spatial = exp(-float(i * i) * invTwoSigma2);
        lfloat w = spatial * exp(-dz * dz - float(i * i) * footprint2) * blurNormalWeight(dot(blurNormal(tx, ty, use), n0));
        w = select(use, w, 0.0f);
        departure += w * (gatherSignal(tx, ty, use) - centre);
        weightSum += w;
    }
    return select(computing, centre + departure / weightSum, centre);
}
