// HBAO's indirect light (kernels/hbao.glsl with HBAO_GI 1), as the bitmask paper (Therrien,
// Levesque & Gilet 2023) takes it from the march that finds the occluded angles: every angle of a
// slice that a sample newly covers receives that sample's outgoing radiance L (the bounce source),
// weighted by its cosine-weighted measure, so the irradiance is
//   E = 2 pi / N_d  sum over slices  sum over newly covered spans  L dF_cos,
// F_cos the cosine form of F (hbao_slice.glsl): the same sum that makes cosine-weighted AO, with
// radiance in place of 1. The first sample to cover an angle is the one seen from the receiver
// along it (the march goes outwards), so nearer surfaces hide farther ones.
//
// What a sample covers follows the plan's model: the horizon's interval reaches down to the
// tangent (exact F, no sectors); a thickness sets the interval from the sample's front to T
// behind it, sectors above the horizon when apart from it (hbao_bitmask.glsl's 32 sectors, each
// weighed exactly). The measured thickness applies to AO; GI takes its cap T for every sample
// (docs/hbao.md). Past the buffer's edge the border policy's continued surface radiates its edge
// texel's light; sky samples send nothing.

// Irradiance of the receiver's lanes, written by hbaoLanes when HBAO_GI is 1 (a global: GLSL's
// per-invocation variable, a member of the CPU's kernel object).
lvec3 hbaoIrradiance;

// F's cosine form at a unit direction (cos theta, sin theta) above the tangent, whatever
// P.cosineWeighting: irradiance weighs every direction by its cosine to the normal.
lfloat cosineF(lfloat cosTheta, lfloat sinTheta, IN(ProjectedNormal) np) {
    lfloat theta = atan(sinTheta, cosTheta);
    return 0.5f * np.nLen * (np.sinB * sinTheta * sinTheta + np.cosB * (theta - sinTheta * cosTheta));
}

// What a slice's light has covered so far: an interval from the tangent up to its horizon, and
// sectors above it.
struct HbaoGi {
    lfloat horizonA, horizonB; // the horizon's direction in the slice's axes; (1, 0): the tangent
    lfloat horizonF;           // cosineF at the horizon
    luint sectors;             // covered sectors above the horizon (thickness models)
    lvec3 irradiance;          // the slice's sum of L dF_cos
};

HbaoGi nothingLit() {
    HbaoGi g;
    g.horizonA = lfloat(1.0f);
    g.horizonB = lfloat(0.0f);
    g.horizonF = lfloat(0.0f);
    g.sectors = luint(0u);
    g.irradiance = lvec3(lfloat(0.0f), lfloat(0.0f), lfloat(0.0f));
    return g;
}

// The cosine-weighted measure of the set sectors between F values lowF and highF (each sector's
// span of F_cos cut to [lowF, highF]; P.sectorTerms' z and w are the bounds' cosine terms).
lfloat coveredBetween(luint sectors, lfloat lowF, lfloat highF, IN(ProjectedNormal) np) {
    uint any = lanesOr(sectors);
    lfloat between = lfloat(0.0f);
    if (any == 0u) {
        return between;
    }
    lfloat wCos = 0.5f * np.nLen * np.cosB;
    lfloat wSin = 0.5f * np.nLen * np.sinB;
    int last = findMSB(any);
    for (int k = findLSB(any); k <= last; ++k) {
        lfloat lowerF = wCos * P.sectorTerms[k].z + wSin * P.sectorTerms[k].w;
        lfloat upperF = wCos * P.sectorTerms[k + 1].z + wSin * P.sectorTerms[k + 1].w;
        lfloat share = max(min(upperF, highF) - max(lowerF, lowF), 0.0f);
        between += lfloat((sectors >> uint(k)) & luint(1u)) * share;
    }
    return between;
}

// Covers, in lanes `counts`, the angles from the back (backA, backB) up to the front (a, b) with
// radiance read at display corner `corner`: the measure not covered before, times the radiance.
// An interval that reaches down to the horizon's (always without a thickness) may raise it, less
// what sectors already covered there; one apart from it sets sectors not set before.
void coverGi(lfloat a, lfloat b, lfloat backA, lfloat backB, lbool counts, lvec2 corner, IN(ProjectedNormal) np,
             INOUT(HbaoGi) g) {
    lbool joins = counts;
    if (HBAO_MODEL != HBAO_HORIZON) {
        joins = joins && joinsHorizon(backA, backB, g.horizonA, g.horizonB);
    }
    lbool raises = joins && aboveHorizon(a, b, g.horizonA, g.horizonB);
    lbool apart = counts && !joins;
    lbool gains = raises || apart;
    if (!anyLane(gains)) {
        return;
    }
    lfloat gained = lfloat(0.0f);
    if (anyLane(raises)) {
        lfloat invLen = inversesqrt(max(a * a + b * b, 1e-30f));
        lfloat f = max(cosineF(a * invLen, b * invLen, np), g.horizonF);
        lfloat rise = f - g.horizonF;
        if (HBAO_MODEL != HBAO_HORIZON) {
            rise = max(rise - coveredBetween(g.sectors, g.horizonF, f, np), 0.0f);
        }
        gained = select(raises, rise, gained);
        g.horizonA = select(raises, a, g.horizonA);
        g.horizonB = select(raises, b, g.horizonB);
        g.horizonF = select(raises, f, g.horizonF);
    }
    if (HBAO_MODEL != HBAO_HORIZON && anyLane(apart)) {
        lint front = sectorBound(sectorPseudoAngle(a, b));
        lint back = sectorBound(select(backB > 0.0f, sectorPseudoAngle(backA, backB), lfloat(0.0f)));
        luint interval = select(apart, bitsBelow(front) & ~bitsBelow(back), luint(0u));
        lfloat share = coveredBetween(interval & ~g.sectors, g.horizonF, lfloat(3.0e38f), np);
        gained = select(apart, share, gained);
        g.sectors = g.sectors | interval;
    }
    g.irradiance += gatherRadianceAtDisplay(corner, gains) * gained;
}

// A sample's light: its interval, from its front to T behind it (the horizon's: down to the tangent).
void takeSampleGi(IN(HbaoSample) smp, IN(HbaoSlice) sl, INOUT(HbaoGi) g) {
    if (anyLane(smp.counts)) {
        coverGi(smp.a, smp.b, smp.a + sl.backShiftA, smp.b + sl.backShiftB, smp.counts, smp.corner, sl.np, g);
    }
}

// Where a chord's end counts: within the ball, above the tangent by more than rounding, on the E
// side (as hbao_border.glsl's takeContinued).
lbool chordEndCounts(lvec3 X, lfloat a, lfloat b, lbool use, IN(HbaoSlice) sl) {
    return use && b > 0.0f && b * b > 1e-4f * dot(X, X) && a * sl.np.nV + b * sl.np.nE > 0.0f;
}

// Past the buffer's edge (the border policy, hbao_border.glsl): the continued surface's chord
// within R radiates the edge texel's light. Where it is one plane it covers the angles between
// its ends (the lower one T deep); else its higher end stands alone, T deep.
void takeBorderGi(IN(HbaoReceiver) r, IN(HbaoSlice) sl, IN(HbaoMarch) m, lbool left, INOUT(HbaoGi) g) {
    lvec2 exitCorner = floor(m.start + m.step * m.stepsInside);
    lvec2 lastCorner = floor(m.start + m.step * float(P.steps - 1));
    lvec3 X0;
    lvec3 X1;
    lbool valid;
    lbool onePlane;
    continuedChord(exitCorner, lastCorner, left, r, X0, X1, valid, onePlane);
    lvec3 P0;
    lvec3 P1;
    lbool meets;
    clipToBall(X0, X1, r.radius2, P0, P1, meets);
    lbool use = valid && meets;
    if (!anyLane(use)) {
        return;
    }
    lfloat a0 = dot(sl.T, P0);
    lfloat b0 = dot(sl.n, P0);
    lfloat a1 = dot(sl.T, P1);
    lfloat b1 = dot(sl.n, P1);
    lbool counts0 = chordEndCounts(P0, a0, b0, use, sl);
    lbool counts1 = chordEndCounts(P1, a1, b1, use, sl);
    lbool oneHigher = counts1 && (!counts0 || aboveHorizon(a1, b1, a0, b0));
    lfloat frontA = select(oneHigher, a1, a0);
    lfloat frontB = select(oneHigher, b1, b0);
    lbool span = counts0 && counts1 && onePlane;
    lfloat lowA = select(span, select(oneHigher, a0, a1), frontA);
    lfloat lowB = select(span, select(oneHigher, b0, b1), frontB);
    coverGi(frontA, frontB, lowA + sl.backShiftA, lowB + sl.backShiftB, counts0 || counts1,
            nearestBufferCorner(exitCorner), sl.np, g);
}
