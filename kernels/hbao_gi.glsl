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
// (docs/hbao.md). Past the buffer's edge nothing bounces; sky samples bounce nothing.

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

// A sample's light: the measure it newly covers times its radiance. Its interval joins the
// horizon's (always without a thickness) and may raise it, less what sectors already covered
// there; or, apart from it, sets sectors not set before.
void takeSampleGi(IN(HbaoSample) smp, IN(HbaoSlice) sl, INOUT(HbaoGi) g) {
    if (!anyLane(smp.counts)) {
        return;
    }
    lfloat backA = smp.a + sl.backShiftA;
    lfloat backB = smp.b + sl.backShiftB;
    lbool joins = smp.counts;
    if (HBAO_MODEL != HBAO_HORIZON) {
        joins = joins && joinsHorizon(backA, backB, g.horizonA, g.horizonB);
    }
    lbool raises = joins && aboveHorizon(smp.a, smp.b, g.horizonA, g.horizonB);
    lbool apart = smp.counts && !joins;
    lbool gains = raises || apart;
    if (!anyLane(gains)) {
        return;
    }
    lfloat gained = lfloat(0.0f);
    if (anyLane(raises)) {
        lfloat invLen = inversesqrt(max(smp.a * smp.a + smp.b * smp.b, 1e-30f));
        lfloat f = max(cosineF(smp.a * invLen, smp.b * invLen, sl.np), g.horizonF);
        lfloat rise = f - g.horizonF;
        if (HBAO_MODEL != HBAO_HORIZON) {
            rise = max(rise - coveredBetween(g.sectors, g.horizonF, f, sl.np), 0.0f);
        }
        gained = select(raises, rise, gained);
        g.horizonA = select(raises, smp.a, g.horizonA);
        g.horizonB = select(raises, smp.b, g.horizonB);
        g.horizonF = select(raises, f, g.horizonF);
    }
    if (HBAO_MODEL != HBAO_HORIZON && anyLane(apart)) {
        lint front = sectorBound(sectorPseudoAngle(smp.a, smp.b));
        lint back = sectorBound(select(backB > 0.0f, sectorPseudoAngle(backA, backB), lfloat(0.0f)));
        luint interval = select(apart, bitsBelow(front) & ~bitsBelow(back), luint(0u));
        lfloat share = coveredBetween(interval & ~g.sectors, g.horizonF, lfloat(3.0e38f), sl.np);
        gained = select(apart, share, gained);
        g.sectors = g.sectors | interval;
    }
    g.irradiance += gatherRadianceAtDisplay(smp.corner, gains) * gained;
}
