// HBAO_FIXED_THICKNESS (kernels/hbao.glsl), and the visibility bitmask every thickness uses
// (Therrien, Levesque & Gilet 2023). A sample occludes only the angles between its front and its
// front pushed the thickness T away from the eye (along -V, the pixel's view direction, as in the
// bitmask paper), not everything below it. The interval that reaches down to the tangent grows
// the horizon (so an infinite T gives HBAO_HORIZON's numbers); intervals above it set bits of a
// 32-sector mask, and each set sector adds its exact share of F above the horizon (F's closed
// forms at the sector's bounds, P.sectorTerms) where the bitmask paper counts bits. Sectors are
// uniform in a pseudo-angle p in [0, 2] (p = b / (|a| + b), mirrored for a < 0), one division
// per sample instead of an arctangent; a sector counts when the interval covers its centre.

// The occlusion the set sectors add between F values lowF and highF (lowF <= highF): each sector
// adds the part of [F(lower bound), F(upper bound)] within [lowF, highF] (F grows with the angle,
// so cutting F's values is cutting the bounds). F is linear in (cos b, sin b); the bounds' terms
// are uniform (P.sectorTerms). Only sectors some lane has set are visited.
lfloat sectorOcclusionBetween(luint sectors, lfloat lowF, lfloat highF, IN(ProjectedNormal) np) {
    lfloat scale = P.cosineWeighting != 0 ? 0.5f * np.nLen : lfloat(1.0f);
    lfloat wCos = scale * np.cosB;
    lfloat wSin = scale * np.sinB;
    uint any = lanesOr(sectors);
    int first = findLSB(any);
    int last = findMSB(any);
    lfloat between = lfloat(0.0f);
    for (int k = first; k <= last; ++k) {
        vec4 lower = P.sectorTerms[k];
        vec4 upper = P.sectorTerms[k + 1];
        lfloat lowerF = P.cosineWeighting != 0 ? wCos * lower.z + wSin * lower.w : wCos * lower.x + wSin * lower.y;
        lfloat upperF = P.cosineWeighting != 0 ? wCos * upper.z + wSin * upper.w : wCos * upper.x + wSin * upper.y;
        // The sector's span [lowerF, upperF] cut to [lowF, highF].
        lfloat share = max(min(upperF, highF) - max(lowerF, lowF), 0.0f);
        between += lfloat((sectors >> uint(k)) & luint(1u)) * share;
    }
    return between;
}

// Occlusion the set sectors add above the horizon, whose own is horizonF.
lfloat sectorOcclusion(luint sectors, lfloat horizonF, IN(ProjectedNormal) np) {
    return sectorOcclusionBetween(sectors, horizonF, lfloat(3.0e38f), np);
}

// Pseudo-angle of (a, b), b >= 0, above the tangent: 0 along it, 1 along the normal, 2 opposite;
// monotone in the angle. Sector k of the mask spans p in [k, k + 1] / 16.
lfloat sectorPseudoAngle(lfloat a, lfloat b) {
    lfloat q = b / max(abs(a) + b, 1e-30f);
    return select(a >= 0.0f, q, 2.0f - q);
}

// The sector whose lower bound is nearest p: bits [sector(back), sector(front)) are the
// sectors whose centres lie between the two.
lint sectorBound(lfloat p) {
    return min(lint(p * 16.0f + 0.5f), lint(32));
}

// Bits 0 .. n-1 set, n in [0, 32] (no shift by 32, which neither language defines).
luint bitsBelow(lint n) {
    luint low = (luint(1u) << luint(min(n, lint(31)))) - luint(1u);
    return low | select(n >= 32, luint(0x80000000u), luint(0u));
}

// Whether an interval whose back is (backA, backB) joins the horizon's: its back lies under the
// tangent or not above the horizon.
lbool joinsHorizon(lfloat backA, lfloat backB, lfloat horizonA, lfloat horizonB) {
    return backB <= 0.0f || horizonA * backB - horizonB * backA <= 0.0f;
}

// Marks the occupied interval of one sample, front (a, b) to back (backA, backB) in the slice's
// axes: when its back is not above the horizon it joins the horizon's interval (and may raise
// it), else it sets the sectors between its two ends.
void occupyInterval(lfloat a, lfloat b, lfloat backA, lfloat backB, lbool counts, INOUT(HbaoOccluded) o) {
    lbool joins = joinsHorizon(backA, backB, o.horizonA, o.horizonB);
    raiseHorizon(counts && joins, a, b, o.horizonA, o.horizonB);
    // Only an interval apart from the horizon's sets sectors; in most registers none is.
    lbool apart = counts && !joins;
    if (anyLane(apart)) {
        lint front = sectorBound(sectorPseudoAngle(a, b));
        lint back = sectorBound(select(backB > 0.0f, sectorPseudoAngle(backA, backB), lfloat(0.0f)));
        luint interval = bitsBelow(front) & ~bitsBelow(back);
        o.sectors = o.sectors | select(apart, interval, luint(0u));
    }
}

// HBAO_FIXED_THICKNESS's step: the sample's interval, from its front to its front pushed T back.
void takeSampleFixed(IN(HbaoSample) smp, IN(HbaoSlice) sl, INOUT(HbaoOccluded) o) {
    occupyInterval(smp.a, smp.b, smp.a + sl.backShiftA, smp.b + sl.backShiftB, smp.counts, o);
}
