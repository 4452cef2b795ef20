// HBAO_HORIZON (kernels/hbao.glsl): the depth buffer as a height field, everything below the
// highest sample occluded (the paper's horizon h). Every other model keeps a horizon too: the
// top of the occluded interval that reaches down to the tangent.
//
// Without falloff the search compares angles by the sign of a cross product, no square root or
// arctangent per sample, and F is evaluated once per slice, at the horizon. Linear falloff weights
// each rise of F by W(r) = 1 - r/R of the sample that made it (the paper's per-sample
// attenuation), which needs F per sample: an inverse square root, and for cosine an arctangent.

// Whether (a, b) in the slice's axes lies above (counter-clockwise of) the line of the horizon
// (horizonA, horizonB), the side a raise needs: the sign of a cross product, no angle.
lbool aboveHorizon(lfloat a, lfloat b, lfloat horizonA, lfloat horizonB) {
    return horizonA * b - horizonB * a > 0.0f;
}

// Raises the horizon to (a, b) in the lanes of `mask` where it lies above (counter-clockwise
// of) it: no square root or division, one compare. Returns the lanes it raised.
lbool raiseHorizon(lbool mask, lfloat a, lfloat b, INOUT(lfloat) horizonA, INOUT(lfloat) horizonB) {
    lbool higher = mask && aboveHorizon(a, b, horizonA, horizonB);
    horizonA = select(higher, a, horizonA);
    horizonB = select(higher, b, horizonB);
    return higher;
}

// Linear falloff's form of raiseHorizon: F grows with the angle, so comparing the sample's F with
// the horizon's (before it takes f) orders them as the cross product does, up to rounding, on a
// value the falloff has computed anyway; the step then carries no product through the horizon.
void raiseHorizonByF(lbool mask, lfloat a, lfloat b, lfloat f, INOUT(HbaoOccluded) o) {
    lbool higher = mask && f > o.horizonF;
    o.horizonA = select(higher, a, o.horizonA);
    o.horizonB = select(higher, b, o.horizonB);
}

// Linear falloff: the sample's F (0 outside `counts`) and its weight.
void linearTerms(IN(HbaoSample) smp, lbool counts, IN(HbaoSlice) sl, float invRadius, OUT(lfloat) f,
                 OUT(lfloat) weight) {
    f = sampleF(smp.a, smp.b, counts, sl.np);
    weight = falloffWeight(smp.r2, invRadius);
}

// The paper's attenuated step: F above the horizon's adds its rise, weighted, and raises it.
void raiseLinearHorizon(lfloat f, lfloat weight, INOUT(HbaoOccluded) o) {
    o.occlusion += weight * max(f - o.horizonF, 0.0f);
    o.horizonF = max(o.horizonF, f);
}

// HBAO_HORIZON's step: the sample raises the horizon (with linear falloff, adds its weighted rise).
void takeSampleHorizon(IN(HbaoSample) smp, IN(HbaoReceiver) r, IN(HbaoSlice) sl, INOUT(HbaoOccluded) o) {
    if (P.linearFalloff != 0) {
        lfloat f;
        lfloat weight;
        linearTerms(smp, smp.counts, sl, r.invRadius, f, weight);
        raiseLinearHorizon(f, weight, o);
    } else {
        raiseHorizon(smp.counts, smp.a, smp.b, o.horizonA, o.horizonB);
    }
}
