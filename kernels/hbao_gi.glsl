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
// weighed exactly). Where the AO applies samples per occluder run (HBAO_RUNS: the measured
// thickness), the light does too, when the run ends, with the radiance of the samples that raised
// it, if the receiver sees the face of the first (its normal, packed beside the radiance, points
// back at the receiver): a face turned away stands for one the buffer does not hold. Past the
// buffer's edge the border policy's continued surface radiates its edge texel's light; sky
// samples send nothing.

#include "shared_exponent.glsl" // the bounce source's texel word (gatherRadianceBitsAtDisplay)
#include "normal_word.glsl"     // ... and its surface's normal's (gatherNormalWordAtDisplay)

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
    lvec3 irradiance;          // the sum of L dF_cos over this slice and the ones before
};

// A slice's light before its march; the sum goes on from the slices before (one sum, not one per
// slice beside the pixel's, keeps three fewer registers live through the march).
HbaoGi nothingLit(lvec3 irradianceBefore) {
    HbaoGi g;
    g.horizonA = lfloat(1.0f);
    g.horizonB = lfloat(0.0f);
    g.horizonF = lfloat(0.0f);
    g.sectors = luint(0u);
    g.irradiance = irradianceBefore;
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
    // Only the sectors some lane has set: most slices set few, far apart.
    for (uint left = any; left != 0u; left &= left - 1u) {
        int k = findLSB(left);
        lfloat lowerF = wCos * P.sectorTerms[k].z + wSin * P.sectorTerms[k].w;
        lfloat upperF = wCos * P.sectorTerms[k + 1].z + wSin * P.sectorTerms[k + 1].w;
        lfloat share = max(min(upperF, highF) - max(lowerF, lowF), 0.0f);
        between += lfloat((sectors >> uint(k)) & luint(1u)) * share;
    }
    return between;
}

// Covers, in lanes `counts`, the angles from the back (backA, backB) up to the front (a, b), and
// returns the measure not covered before (in lanes `gains`).
// An interval that reaches down to the horizon's (always without a thickness) may raise it, less
// what sectors already covered there; one apart from it sets sectors not set before.
lfloat newlyCovered(lfloat a, lfloat b, lfloat backA, lfloat backB, lbool counts, IN(ProjectedNormal) np,
                    INOUT(HbaoGi) g, OUT(lbool) gains) {
    lbool joins = counts;
    if (HBAO_MODEL != HBAO_HORIZON) {
        joins = joins && joinsHorizon(backA, backB, g.horizonA, g.horizonB);
    }
    lbool raises = joins && aboveHorizon(a, b, g.horizonA, g.horizonB);
    lbool apart = counts && !joins;
    gains = raises || apart;
    lfloat gained = lfloat(0.0f);
    if (!anyLane(gains)) {
        return gained;
    }
    if (anyLane(raises)) {
        lfloat invLen = inversesqrt(max(a * a + b * b, 1e-30f));
        lfloat f = max(cosineF(a * invLen, b * invLen, np), g.horizonF);
        lfloat rise = f - g.horizonF;
        if (HBAO_MODEL != HBAO_HORIZON) {
            rise = max(rise - coveredBetween(select(raises, g.sectors, luint(0u)), g.horizonF, f, np), 0.0f);
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
    return gained;
}

// newlyCovered's measure lit by the radiance read at display corner `corner`, layer `layer` (0:
// the visible surface; HBAO_DEEP's hidden ones after it).
void coverGi(lfloat a, lfloat b, lfloat backA, lfloat backB, lbool counts, lvec2 corner, int layer,
             IN(ProjectedNormal) np, INOUT(HbaoGi) g) {
    lbool gains;
    lfloat gained = newlyCovered(a, b, backA, backB, counts, np, g, gains);
    if (anyLane(gains)) {
        g.irradiance += sharedExponentRgb(gatherRadianceBitsAtDisplay(corner, layer, gains)) * gained;
    }
}

// Whether the receiver sees the face the buffer holds at sample `smp`: that face's normal, turned
// towards the eye, points back along X. A sample on an occluder's far side (a pole's front, seen
// from the ground behind the pole) stands in for a face the receiver sees and the buffer does not
// hold, so its light is unknown: it sends none (screen space may miss light, never add it).
lbool facesReceiver(luint normalBits, lvec3 X, lbool use) {
    // The word's normal faces the eye. Within about 3 degrees of edge-on counts as facing (|n| >=
    // 511 in the word): a receiver at a crease sits on both faces, up to its pixel's rounding.
    lfloat away = dot(normalFromWord(normalBits), X);
    return use && (away < 0.0f || away * away < 680.0f * dot(X, X));
}

// A sample's light without runs: its interval, from its front to the fixed thickness behind it
// (pushed along -V, as the AO's; the horizon's: down to the tangent).
void takeSampleGi(IN(HbaoSample) smp, IN(HbaoSlice) sl, INOUT(HbaoGi) g) {
    if (anyLane(smp.counts)) {
        coverGi(smp.a, smp.b, smp.a + sl.backShiftA, smp.b + sl.backShiftB, smp.counts, smp.corner, 0, sl.np, g);
    }
}

// HBAO_RUNS's light (the default, measured thickness): the AO applies a run when it ends, as one
// interval from its lowest back to its top, and so does the light, before the AO's close moves
// the horizon. The run's newly covered measure takes the mean radiance of the samples that raised
// its top, each weighted by its share of F_cos (riseWeight), where the receiver sees the face of
// the run's first rising sample (the nearest face it meets along the slice); else the run sends
// nothing. The light keeps F at the horizon, its sum and the run's radiance beside the AO's state
// (the horizon and sectors are the AO's), and computes F once a closing run, not once a sample.
void litHorizonIsOccluded(IN(HbaoOccluded) o, INOUT(HbaoGi) g) {
    g.horizonA = o.horizonA;
    g.horizonB = o.horizonB;
    g.sectors = o.sectors;
}

// The light of the runs ending in lanes `ends`, each with its thickness t, where the receiver sees
// the face of the run's first rising sample (its normal read here, once a run).
void lightRun(lbool ends, lfloat t, IN(OccluderRun) run, IN(ProjectedNormal) np, IN(HbaoOccluded) o,
              INOUT(HbaoGi) g) {
    litHorizonIsOccluded(o, g);
    lfloat backA;
    lfloat backB;
    runBack(run, t, np, backA, backB);
    lbool gains;
    lfloat gained = newlyCovered(run.topA, run.topB, backA, backB, ends, np, g, gains);
    lbool sends = facesReceiver(gatherNormalWordAtDisplay(run.lightCorner, ends), run.lightX, ends);
    lvec3 none = lvec3(lfloat(0.0f), lfloat(0.0f), lfloat(0.0f));
    g.irradiance += select(sends, run.light * (gained / max(run.lightWeight, 1e-30f)), none);
}

// A sample that raised its run's top: its radiance, times its weight, joins the run's. The run's
// first such sample, the face the receiver meets first, is kept to decide when the run ends
// whether it sends. (A test at every rising sample, which let a step's tread, sampled past the
// nose it stands for, leave its share to the riser, cost a gather a step for 1% of the error:
// docs/notes/2026-11-28-horizon-gi-faces.md.)
void lightRisingSample(IN(HbaoSample) smp, INOUT(OccluderRun) run) {
    lbool rising = run.lightRise > 0.0f;
    if (anyLane(rising)) {
        lbool first = rising && run.lightWeight <= 0.0f;
        run.lightCorner = lvec2(select(first, smp.corner.x, run.lightCorner.x),
                                select(first, smp.corner.y, run.lightCorner.y));
        run.lightX = select(first, smp.X, run.lightX);
        run.light += sharedExponentRgb(gatherRadianceBitsAtDisplay(smp.corner, 0, rising)) * run.lightRise;
        run.lightWeight += run.lightRise;
    }
}

// Before the AO's step (takeSampleInRuns) closes the run that step `st` ends: its light.
void lightEndingRun(IN(RunStep) st, IN(HbaoSlice) sl, IN(OccluderRun) run, IN(HbaoOccluded) o, INOUT(HbaoGi) g) {
    if (anyLane(st.matters)) {
        lightRun(st.matters, st.t, run, sl.np, o, g);
    }
}

// After the march: the light of a run still going (closeUnfinishedRun's, P.thickness deep).
void lightUnfinishedRun(IN(OccluderRun) run, IN(HbaoSlice) sl, IN(HbaoOccluded) o, INOUT(HbaoGi) g) {
    lbool unclosed = run.going && run.raised;
    if (anyLane(unclosed)) {
        lightRun(unclosed, lfloat(P.thickness), run, sl.np, o, g);
    }
}

// The cosine-weighted measure a slice's AO state covers: F_cos at its horizon and the sectors set
// above it (what the AO's integral is with cosine weighting).
lfloat occludedCosine(IN(HbaoOccluded) o, IN(ProjectedNormal) np) {
    lfloat invLen = inversesqrt(max(o.horizonA * o.horizonA + o.horizonB * o.horizonB, 1e-30f));
    lfloat f = cosineF(o.horizonA * invLen, o.horizonB * invLen, np);
    return f + coveredBetween(o.sectors, f, lfloat(3.0e38f), np);
}

// HBAO_RUNS's light past the buffer's edge: what the AO's continued surface newly covered (`was`:
// the AO's state before it), radiating the edge texel's light, so the light follows the border's
// runs exactly as inside the buffer. The light's F at the horizon is the AO's horizon's.
void lightBorderAsOccluded(IN(HbaoReceiver) r, IN(HbaoSlice) sl, IN(HbaoMarch) m, lbool left, IN(HbaoOccluded) was,
                           IN(HbaoOccluded) o, INOUT(HbaoGi) g) {
    lbool raised = aboveHorizon(o.horizonA, o.horizonB, was.horizonA, was.horizonB);
    lbool setMore = lfloat(o.sectors ^ was.sectors) > 0.0f;
    lbool gains = left && (raised || setMore);
    if (!anyLane(gains)) {
        return;
    }
    lfloat before = g.horizonF + coveredBetween(was.sectors, g.horizonF, lfloat(3.0e38f), sl.np);
    lfloat gained = select(gains, max(occludedCosine(o, sl.np) - before, 0.0f), lfloat(0.0f));
    BorderChord c = borderChord(r, m, left);
    luint bits = gatherRadianceBitsAtDisplay(nearestBufferCorner(c.exitCorner), 0, gains);
    g.irradiance += sharedExponentRgb(bits) * gained;
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
    BorderChord c = borderChord(r, m, left);
    lvec3 P0;
    lvec3 P1;
    lbool meets;
    clipToBall(c.X0, c.X1, r.radius2, P0, P1, meets);
    lbool use = c.valid && meets;
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
    lbool span = counts0 && counts1 && c.onePlane;
    lfloat lowA = select(span, select(oneHigher, a0, a1), frontA);
    lfloat lowB = select(span, select(oneHigher, b0, b1), frontB);
    coverGi(frontA, frontB, lowA + sl.backShiftA, lowB + sl.backShiftB, counts0 || counts1,
            nearestBufferCorner(c.exitCorner), 0, sl.np, g);
}
