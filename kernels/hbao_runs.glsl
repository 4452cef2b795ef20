// HBAO_RUNS (kernels/hbao.glsl): samples applied per occluder, for HBAO_MEASURED_THICKNESS
// (`--thickness auto`) and for HBAO_FIXED_THICKNESS with linear falloff. One T cannot suit both
// a pole (about as deep as it is wide) and a sphere or a wall (deep behind its silhouette), so the
// measured thickness is taken per occluder. Along a slice, consecutive samples above the tangent
// plane whose depth (along V) changes by at most P.runJump form a run: one occluder as this slice
// crosses it. A run that ends inside the search (the next sample is on or below the tangent
// plane, sky, or jumps in depth) was crossed whole, and its depth is P.runDepthPerWidth times its
// width (first to last sample, plus one step), at most P.thickness; a run cut off by the search's
// end or the buffer's edge may be any depth and gets P.thickness, as every run does with a fixed
// T. Its samples share that thickness, so a run is applied when it ends, as one interval: from
// the lower of its ends' backs to its top. Linear falloff weights each occluder's rise once.
struct OccluderRun {
    lfloat firstA, firstB;     // its first sample
    lfloat lastA, lastB;       // its last sample so far
    lfloat topA, topB;         // its highest sample within R, from the horizon when it started
    lbool raised;              // some sample rose above that horizon: only then does the run add
    lbool going;               // the last sample was in a run (above the tangent)
    lfloat topF;               // linear falloff: F at its top
    lfloat rise;               // linear falloff: sum of W(r) times each sample's rise of F above
                               // the horizon and the run's earlier samples
    lvec3 light;               // HBAO_GI: its rising samples' radiance, each times its weight (riseWeight)
    lfloat lightWeight;        // ... the sum of those weights
    lfloat lightRise;          // ... the weight of this step's sample (0: it did not raise the top)
    lvec2 lightCorner;         // ... its first rising sample's texel (the run sends if the receiver sees its face)
    lvec3 lightX;              // ... and that sample's offset from the receiver
};

OccluderRun noRun() {
    OccluderRun run;
    run.firstA = run.firstB = run.lastA = run.lastB = lfloat(0.0f);
    run.topA = lfloat(1.0f); // (1, 0): the tangent
    run.topB = run.topF = run.rise = lfloat(0.0f);
    run.raised = run.going = lfloat(0.0f) > 0.0f; // false in every lane
    run.light = lvec3(lfloat(0.0f), lfloat(0.0f), lfloat(0.0f));
    run.lightWeight = run.lightRise = lfloat(0.0f);
    run.lightCorner = lvec2(lfloat(0.0f), lfloat(0.0f));
    run.lightX = lvec3(lfloat(0.0f), lfloat(0.0f), lfloat(0.0f));
    return run;
}

// The thickness of a run crossed whole: with a measured thickness, k times its width across the
// slice (first to last sample plus the step one sample stands for, `foot`), in world units, at
// most P.thickness; with a fixed one, P.thickness.
lfloat runThickness(IN(OccluderRun) run, lfloat invNLen, lfloat foot) {
    lfloat t = lfloat(P.thickness);
    if (HBAO_MODEL == HBAO_MEASURED_THICKNESS) {
        lfloat dA = run.lastA - run.firstA;
        lfloat dB = run.lastB - run.firstB;
        lfloat width = sqrt(dA * dA + dB * dB) * invNLen + foot;
        t = min(P.runDepthPerWidth * width, lfloat(P.thickness));
    }
    return t;
}

// A run's lowest back: the lower of its ends' backs (its first and last samples pushed t along -V).
void runBack(IN(OccluderRun) run, lfloat t, IN(ProjectedNormal) np, OUT(lfloat) backA, OUT(lfloat) backB) {
    lfloat firstBackA = run.firstA + t * np.nE;
    lfloat firstBackB = run.firstB - t * np.nV;
    lfloat lastBackA = run.lastA + t * np.nE;
    lfloat lastBackB = run.lastB - t * np.nV;
    // Both lie on the E side (a push along -V keeps the E coordinate): their angles compare by
    // the sign of a cross product.
    lbool firstLower = firstBackA * lastBackB - firstBackB * lastBackA > 0.0f;
    backA = select(firstLower, firstBackA, lastBackA);
    backB = select(firstLower, firstBackB, lastBackB);
}

// Applies the runs ending in lanes `ends`, each with its thickness t. The lower of its ends'
// backs (its first and last samples pushed t along -V) stands for the lowest back. When that is
// not above the horizon the run's interval joins the horizon's, which rises to the run's top;
// else it sets the sectors between the two.
//
// Linear falloff: a run that joins adds its weighted rises, scaled down by the share of its
// rise that sectors set earlier already count (each angle is weighted once, by the first
// occluder over it, as the horizon does); an apart run adds its new sectors at its mean weight.
//
// The compiler keeps this call out of line with linear falloff; the run and the projected normal
// come as copies, so the march's own stay in registers (by reference they went to the stack:
// bench_hbao 2% slower with AVX-512).
void closeRuns(lbool ends, lfloat t, OccluderRun run, ProjectedNormal np, INOUT(HbaoOccluded) o) {
    lfloat backA;
    lfloat backB;
    runBack(run, t, np, backA, backB);
    lbool joins = joinsHorizon(backA, backB, o.horizonA, o.horizonB);
    lbool higher = raiseHorizon(ends && joins, run.topA, run.topB, o.horizonA, o.horizonB);
    lfloat runRange = max(run.topF - o.horizonF, 1e-30f);
    if (P.linearFalloff != 0) {
        lfloat counted = lfloat(0.0f);
        if (anyLane(higher && lfloat(o.sectors) > 0.0f)) {
            counted = sectorOcclusionBetween(o.sectors, o.horizonF, max(run.topF, o.horizonF), np);
        }
        o.occlusion += select(higher, run.rise * max(1.0f - counted / runRange, 0.0f), lfloat(0.0f));
        o.horizonF = select(higher, max(run.topF, o.horizonF), o.horizonF);
    }
    lbool apart = ends && !joins;
    if (anyLane(apart)) {
        lint front = sectorBound(sectorPseudoAngle(run.topA, run.topB));
        lint back = sectorBound(sectorPseudoAngle(backA, backB));
        luint interval = select(apart, bitsBelow(front) & ~bitsBelow(back), luint(0u));
        if (P.linearFalloff != 0) {
            luint added = interval & ~o.sectors;
            if (anyLane(lfloat(added) > 0.0f)) {
                o.occlusion += (run.rise / runRange) * sectorOcclusion(added, o.horizonF, np);
            }
        }
        o.sectors = o.sectors | interval;
    }
}

// Linear falloff's part of a sample (`inside`: it can occlude, in a run): a sample within rounding
// of the tangent raises the horizon as it would without runs (its back lies below the tangent for
// any thickness that matters), so a large T is the linear horizon; one in a run adds its weighted
// rise to the run's. Binary visibility drops the former: it adds at most F at 0.57 degrees.
void weighSampleInRun(IN(HbaoSample) smp, lbool inside, IN(HbaoReceiver) r, IN(HbaoSlice) sl,
                      INOUT(OccluderRun) run, INOUT(HbaoOccluded) o) {
    lbool onTangent = smp.counts && !smp.above;
    lfloat f;
    lfloat weight;
    linearTerms(smp, smp.counts, sl, r.invRadius, f, weight);
    raiseHorizonByF(onTangent, smp.a, smp.b, f, o);
    lfloat insideF = select(inside, f, lfloat(0.0f));
    run.rise += weight * max(insideF - max(o.horizonF, run.topF), 0.0f);
    run.topF = max(run.topF, insideF);
    raiseLinearHorizon(select(onTangent, f, lfloat(0.0f)), weight, o);
}

// HBAO_GI: the weight of a sample's radiance in its run's light, the share of F_cos its rise over
// the run's top (topA, topB) covers: dF_cos / dtheta = |n_p| sin(theta) sin(theta + B) (cosineF in
// hbao_gi.glsl), theta its angle above the tangent, dtheta the pseudo-angle's rise times
// (|cos| + sin)^2. Never 0, so a run that rose has a weight.
lfloat riseWeight(IN(HbaoSample) smp, lfloat topA, lfloat topB, IN(ProjectedNormal) np) {
    lfloat invLen = inversesqrt(max(smp.a * smp.a + smp.b * smp.b, 1e-30f));
    lfloat c = smp.a * invLen;
    lfloat s = smp.b * invLen;
    lfloat dTheta = (sectorPseudoAngle(smp.a, smp.b) - sectorPseudoAngle(topA, topB)) * (abs(c) + s) * (abs(c) + s);
    return max(dTheta * s * max(s * np.cosB + c * np.sinB, 0.0f), 1e-7f);
}

// Whether sample `smp` continues the run going on (lanes where it does not and a run went on end it).
lbool continuesRun(IN(HbaoSample) smp, IN(HbaoSlice) sl, IN(OccluderRun) run) {
    lfloat toEye = (smp.b - run.lastB) * sl.np.nV - (smp.a - run.lastA) * sl.np.nE;
    return run.going && smp.above && abs(toEye) <= sl.runJump;
}

// The run ending at sample `smp`: the lanes where it adds (`matters`; a run whose top is not
// above the horizon adds nothing: its sectors would lie under the horizon, its rises are none,
// and most runs end so) and its thickness there.
lbool endingRun(IN(HbaoSample) smp, IN(HbaoReceiver) r, IN(HbaoSlice) sl, IN(OccluderRun) run,
                lbool continues, OUT(lfloat) t) {
    // The top starts at the horizon, which only a close raises while the run goes on, so the
    // test is a flag set as the top rises, not a cross product a step.
    lbool matters = run.going && !continues && run.raised;
    t = lfloat(P.thickness);
    if (anyLane(matters)) {
        // A run ending past the edge (its end not seen) may be any depth.
        lbool leftBuffer = !insideBuffer(smp.corner - vec2(bufferOrigin()), 0.0f);
        t = select(leftBuffer, t, runThickness(run, sl.np.invNLen, r.footprint));
    }
    return matters;
}

// What sample `smp` does to the run going on, found once a step for the AO's close and the
// light's (hbao_gi.glsl), which acts before it: whether it continues the run, and where it ends
// one that adds (`matters`), that run's thickness t.
struct RunStep {
    lbool continues;
    lbool matters;
    lfloat t;
};

RunStep runStepAt(IN(HbaoSample) smp, IN(HbaoReceiver) r, IN(HbaoSlice) sl, IN(OccluderRun) run) {
    RunStep st;
    st.continues = lfloat(0.0f) > 0.0f; // false in every lane
    st.matters = st.continues;
    st.t = lfloat(P.thickness);
    if (anyLane(smp.above || run.going)) {
        st.continues = continuesRun(smp, sl, run);
        st.matters = endingRun(smp, r, sl, run, st.continues, st.t);
    }
    return st;
}

// A sample where some lane's run goes on or starts: it continues the run, or ends it (which then
// closes) and starts the next, or lies in none.
void followRun(IN(HbaoSample) smp, IN(HbaoReceiver) r, IN(HbaoSlice) sl, IN(RunStep) st, INOUT(OccluderRun) run,
               INOUT(HbaoOccluded) o) {
    lbool continues = st.continues;
    lbool ends = run.going && !continues;
    if (anyLane(st.matters)) {
        closeRuns(st.matters, st.t, run, sl.np, o);
    }
    // A sample that does not continue a run starts one, or lies in none: either way the run's
    // state restarts from it (outside a run the top stays at the horizon).
    run.topA = select(continues, run.topA, o.horizonA);
    run.topB = select(continues, run.topB, o.horizonB);
    if (P.linearFalloff != 0) {
        run.topF = select(ends, lfloat(0.0f), run.topF);
        run.rise = select(ends, lfloat(0.0f), run.rise);
    }
    run.firstA = select(continues, run.firstA, smp.a);
    run.firstB = select(continues, run.firstB, smp.b);
    lbool inside = smp.counts && smp.above; // can occlude
    lbool higher = inside && run.topA * smp.b - run.topB * smp.a > 0.0f;
    lfloat topA = run.topA;
    lfloat topB = run.topB;
    run.topA = select(higher, smp.a, run.topA);
    run.topB = select(higher, smp.b, run.topB);
    if (HBAO_GI != 0) {
        // The light's weights: the share of F_cos each sample's rise covers (a new run's top is the horizon).
        lvec3 none = lvec3(lfloat(0.0f), lfloat(0.0f), lfloat(0.0f));
        run.light = select(continues, run.light, none);
        run.lightWeight = select(continues, run.lightWeight, lfloat(0.0f));
        run.lightRise = lfloat(0.0f);
        if (anyLane(higher)) {
            run.lightRise = select(higher, riseWeight(smp, topA, topB, sl.np), lfloat(0.0f));
        }
    }
    run.raised = (continues && run.raised) || higher;
    if (P.linearFalloff != 0) {
        weighSampleInRun(smp, inside, r, sl, run, o);
    }
    run.lastA = smp.a;
    run.lastB = smp.b;
    run.going = smp.above;
}

// HBAO_RUNS's step, `st` its runStepAt.
void takeSampleInRuns(IN(HbaoSample) smp, IN(HbaoReceiver) r, IN(HbaoSlice) sl, IN(RunStep) st,
                      INOUT(OccluderRun) run, INOUT(HbaoOccluded) o) {
    if (!anyLane(smp.above || run.going)) {
        // No run goes on and none starts (a receiver on open ground): only the linear falloff's
        // on-tangent samples need this step.
        run.lightRise = lfloat(0.0f);
        if (P.linearFalloff != 0) {
            lfloat f;
            lfloat weight;
            linearTerms(smp, smp.counts, sl, r.invRadius, f, weight);
            raiseHorizonByF(smp.counts, smp.a, smp.b, f, o);
            raiseLinearHorizon(f, weight, o);
        }
    } else {
        followRun(smp, r, sl, st, run, o);
    }
}

// Runs still going when the search ends (or leaves the buffer) may be any depth: P.thickness.
void closeUnfinishedRun(IN(OccluderRun) run, IN(HbaoSlice) sl, INOUT(HbaoOccluded) o) {
    lbool unclosed = run.going && run.raised;
    if (anyLane(unclosed)) {
        closeRuns(unclosed, lfloat(P.thickness), run, sl.np, o);
    }
}
