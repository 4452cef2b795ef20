// Horizon-based ambient occlusion (Bavoil, Sainz, Dimitrov 2008), written on lane types:
// one pixel per GPU thread, several pixels per CPU register (cpu/lanes.h). Per-pixel
// branches are masks; loops are uniform over the lanes.
//
// Directions are slices around the view vector V (as in GTAO), so every slice
// is a plane through the eye and its samples lie on one image line; this makes
// the solid-angle measure exact under perspective.
//
// Within a slice a sample is taken in the coordinates of the pixel's tangent plane:
// a along the slice's tangent T, b above it (along the normal projected into the slice,
// n_p = |n_p| (cos b, sin b) in the slice's (E, V) axes). A sample at angle theta above
// the tangent (cos theta, sin theta) = (a, b) / |(a, b)| occludes, per unit of slice:
//   uniform (HBAO paper, Eq. 3; sin h - sin t):          F = cos b (1 - cos theta) + sin b sin theta
//   cosine (projected solid angle; integral of cos to n): F = |n_p| / 2 (sin b sin^2 theta
//                                                               + cos b (theta - sin theta cos theta))
// Both grow with theta, so the horizon is the sample with the largest theta. Without
// falloff the search compares angles by the sign of a cross product and evaluates F once
// per slice; linear falloff
// weights each rise of F by W(r) = 1 - r/R of the sample that made it, as in the paper,
// which needs F per sample (no arcsine: an inverse square root, and for cosine one
// arctangent).
//
// Thickness (Therrien, Levesque, Gilet 2023, visibility bitmask): with a finite thickness a sample
// occludes only the angles between its front face and its front face pushed a thickness t
// away from the eye (along -V, the pixel's view direction, as in the paper), not everything
// below it. The occluded set of a slice is then a union of intervals of theta. The interval
// that reaches down to the tangent grows a continuous horizon exactly as above (so an
// infinite t gives the same numbers); intervals above it set bits of a 32-sector mask, and
// each set sector adds its exact share of F above that horizon (F's closed forms at the
// sector's bounds). Sectors are uniform in a pseudo-angle p in [0, 2] (p = b / (|a| + b),
// mirrored for a < 0), which needs one division per sample instead of an arctangent; a
// sector counts when the interval covers its centre. `--thickness auto` and linear falloff take
// samples by runs (OccluderRun below).
//
// Deep input (HBAO_DEEP, docs/deep.md): every surface on a sample texel's ray, with the
// solid spans the renderer saw, is an interval of the same bitmask (occupyDeepLayer below), and
// so is each sample's footprint on its tangent plane (occupyFootprint below).
//
// Samples snap to texel centres, which moves them slightly off the slice. Taking a and b
// from the full 3D offset brings them back into the slice along the tangent plane (not
// orthogonally): their height above the tangent plane is kept, so a plane stays exactly
// unoccluded wherever the samples land.

// F for a unit (cos theta, sin theta) above the tangent; cosB, sinB: the projected normal's
// direction in the slice, nLen its length.
lfloat sliceOcclusionAt(lfloat cosTheta, lfloat sinTheta, lfloat cosB, lfloat sinB, lfloat nLen) {
    if (P.cosineWeighting == 0) {
        return cosB * (1.0f - cosTheta) + sinB * sinTheta;
    }
    lfloat theta = atan(sinTheta, cosTheta);
    return 0.5f * nLen * (sinB * sinTheta * sinTheta + cosB * (theta - sinTheta * cosTheta));
}

// F of a sample at (a, b) in the slice's axes, 0 outside `counts`.
lfloat sampleF(lfloat a, lfloat b, lbool counts, lfloat cosB, lfloat sinB, lfloat nLen) {
    lfloat invLen = inversesqrt(max(a * a + b * b, 1e-30f));
    return select(counts, sliceOcclusionAt(a * invLen, b * invLen, cosB, sinB, nLen), lfloat(0.0f));
}

// Linear falloff's weight 1 - r/R of a point at distance r (r^2 = r2), 0 beyond R.
lfloat falloffWeight(lfloat r2, float invRadius) {
    return max(1.0f - sqrt(r2) * invRadius, 0.0f);
}

// Linear falloff: the sample's F (0 outside `counts`) and its weight.
void linearTerms(lfloat a, lfloat b, lfloat r2, lbool counts, lfloat cosB, lfloat sinB, lfloat nLen, float invRadius,
                 OUT(lfloat) f, OUT(lfloat) weight) {
    f = sampleF(a, b, counts, cosB, sinB, nLen);
    weight = falloffWeight(r2, invRadius);
}

// HBAO's linear-falloff step: F above the horizon's adds its rise, weighted, and raises it.
void raiseLinearHorizon(lfloat f, lfloat weight, INOUT(lfloat) horizonF, INOUT(lfloat) sliceOcclusion) {
    sliceOcclusion += weight * max(f - horizonF, 0.0f);
    horizonF = max(horizonF, f);
}

// The occlusion the set sectors add between F values lowF and highF (lowF <= highF): each sector
// adds the part of [F(lower bound), F(upper bound)] within [lowF, highF] (F grows with the angle,
// so cutting F's values is cutting the bounds). F is linear in (cos b, sin b); the bounds' terms
// are uniform (P.sectorTerms). Only sectors some lane has set are visited.
lfloat sectorOcclusionBetween(luint sectors, lfloat lowF, lfloat highF, lfloat cosB, lfloat sinB, lfloat nLen) {
    lfloat scale = P.cosineWeighting != 0 ? 0.5f * nLen : lfloat(1.0f);
    lfloat wCos = scale * cosB;
    lfloat wSin = scale * sinB;
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
lfloat sectorOcclusion(luint sectors, lfloat horizonF, lfloat cosB, lfloat sinB, lfloat nLen) {
    return sectorOcclusionBetween(sectors, horizonF, lfloat(3.0e38f), cosB, sinB, nLen);
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

// Whether (a, b) in the slice's axes lies above (counter-clockwise of) the line of the horizon
// (horizonA, horizonB), the side a raise needs: the sign of a cross product, no angle.
lbool aboveHorizon(lfloat a, lfloat b, lfloat horizonA, lfloat horizonB) {
    return horizonA * b - horizonB * a > 0.0f;
}

// Whether an interval whose back is (backA, backB) joins the horizon's: its back lies under the
// tangent or not above the horizon.
lbool joinsHorizon(lfloat backA, lfloat backB, lfloat horizonA, lfloat horizonB) {
    return backB <= 0.0f || horizonA * backB - horizonB * backA <= 0.0f;
}

// Raises the horizon to (a, b) in the lanes of `mask` where it lies above (counter-clockwise
// of) the horizon: no square root or division, one compare. Returns the lanes it raised.
lbool raiseHorizon(lbool mask, lfloat a, lfloat b, INOUT(lfloat) horizonA, INOUT(lfloat) horizonB) {
    lbool higher = mask && aboveHorizon(a, b, horizonA, horizonB);
    horizonA = select(higher, a, horizonA);
    horizonB = select(higher, b, horizonB);
    return higher;
}

// Linear falloff's form of raiseHorizon: F grows with the angle, so comparing the sample's F with
// the horizon's (before it takes f) orders them as the cross product does, up to rounding, on a
// value the falloff has computed anyway; the step then carries no product through the horizon.
void raiseHorizonByF(lbool mask, lfloat a, lfloat b, lfloat f, lfloat horizonF, INOUT(lfloat) horizonA,
                     INOUT(lfloat) horizonB) {
    lbool higher = mask && f > horizonF;
    horizonA = select(higher, a, horizonA);
    horizonB = select(higher, b, horizonB);
}

// Marks the occupied interval of one sample, front (a, b) to back (backA, backB) in the slice's
// axes: when its back is not above the horizon it joins the horizon's interval (and may raise
// it), else it sets the sectors between its two ends.
void occupyInterval(lfloat a, lfloat b, lfloat backA, lfloat backB, lbool counts, INOUT(lfloat) horizonA,
                    INOUT(lfloat) horizonB, INOUT(luint) sectors) {
    lbool joins = joinsHorizon(backA, backB, horizonA, horizonB);
    raiseHorizon(counts && joins, a, b, horizonA, horizonB);
    // Only an interval apart from the horizon's sets sectors; in most registers none is.
    lbool apart = counts && !joins;
    if (anyLane(apart)) {
        lint front = sectorBound(sectorPseudoAngle(a, b));
        lint back = sectorBound(select(backB > 0.0f, sectorPseudoAngle(backA, backB), lfloat(0.0f)));
        luint interval = bitsBelow(front) & ~bitsBelow(back);
        sectors = sectors | select(apart, interval, luint(0u));
    }
}

// Deep input (HBAO_DEEP, docs/deep.md): the backend's gatherDeepAtDisplay(corner, c, use)
// reads channel c of P.deepLayers (front, back) depth pairs per texel, layer 0 the visible
// surface, +inf fronts past a ray's last surface. A back beyond its front is a solid the
// renderer saw the ray cross (a span); else the surface's depth is unknown and the thickness
// rule pushes its front back, as without deep input.
//
// The part P0 .. P1 of the segment from X0 to X1 (offsets from the receiver) inside the ball of
// radius R around the receiver; `meets` when there is one.
void clipToBall(lvec3 X0, lvec3 X1, float radius2, OUT(lvec3) P0, OUT(lvec3) P1, OUT(lbool) meets) {
    // |X0 + t d|^2 = R^2: the chord of the ball along the segment, t in [0, 1].
    lvec3 d = X1 - X0;
    lfloat dd = max(dot(d, d), 1e-30f);
    lfloat fd = dot(X0, d);
    lfloat c = dot(X0, X0) - radius2;
    lfloat disc = fd * fd - dd * c;
    lfloat root = sqrt(max(disc, 0.0f));
    lfloat invDd = 1.0f / dd;
    lfloat t0 = max((-fd - root) * invDd, 0.0f);
    lfloat t1 = min((-fd + root) * invDd, 1.0f);
    meets = disc >= 0.0f && t0 <= t1;
    P0 = X0 + d * t0;
    P1 = X0 + d * t1;
}

// One layer at a sample texel, front frontX and back backX (offsets from the receiver): a span
// counts for its part inside the sphere of radius R (a long span whose front lies beyond R may
// still pass close by), a point sample when its front is within R; then, as for the visible
// layer, only when that front is above the tangent plane and on the E side.
void occupySpan(lvec3 frontX, lvec3 backX, lbool span, lbool use, lvec3 T, lvec3 n, lfloat nE, lfloat nV,
                float radius2, lfloat backShiftA, lfloat backShiftB, INOUT(lfloat) horizonA, INOUT(lfloat) horizonB,
                INOUT(luint) sectors) {
    lvec3 spanFront;
    lvec3 back;
    lbool chord;
    clipToBall(frontX, backX, radius2, spanFront, back, chord);
    lbool meets = (span && chord) || (!span && dot(frontX, frontX) <= radius2);
    lvec3 front = select(span, spanFront, frontX);
    lfloat a = dot(T, front);
    lfloat b = dot(n, front);
    lfloat backA = select(span, dot(T, back), a + backShiftA);
    lfloat backB = select(span, dot(n, back), b + backShiftB);
    lbool counts = use && meets && b > 0.0f && a * nV + b * nE > 0.0f;
    occupyInterval(a, b, backA, backB, counts, horizonA, horizonB, sectors);
}

// The texel one pixel from a sample texel (display corner `corner`, surface point on sampleRay at
// sampleDepth) along `offset`: whether it is a surface, its view-space normal (not normalised)
// and its surface point's offset D from the sample's.
void neighbourTexel(lvec2 corner, lvec2 offset, lvec3 sampleRay, lfloat sampleDepth, lbool use,
                    OUT(lbool) surface, OUT(lvec3) normal, OUT(lvec3) D) {
    vec2 origin = vec2(bufferOrigin());
    lvec2 texel = floor(corner + lvec2(0.5f, 0.5f) + offset);
    surface = use && insideBuffer(texel - origin, 0.0f);
    lfloat depth = gatherDepthAtDisplay(texel, surface) * P.depthScale;
    surface = surface && isSurfaceDepth(depth);
    normal = mat3(P.normalToView) * gatherNormal(lint(texel.x - origin.x), lint(texel.y - origin.y), surface);
    lvec2 w = imageOffset(texel - corner);
    D = viewOffset(sampleRay, sampleDepth, w, select(surface, depth, sampleDepth));
}

// Whether a neighbour (normal mn) continues the plane of normal m: its normal within 3.6 degrees.
lbool continuesPlane(lbool surface, lvec3 mn, lvec3 m) {
    lfloat c = dot(m, mn);
    return surface && c > 0.0f && c * c > 0.996f * dot(mn, mn);
}

// A footprint half `step` from the sample, cut where it crosses the tangent plane of the
// neighbour on its side (normal mn, point D from the sample): a crease inside the pixel, such as
// a box's convex edge, ends the plane there.
lvec3 cutAtNeighbour(lvec3 step, lbool surface, lvec3 mn, lvec3 D) {
    lfloat across = dot(mn, step);
    lfloat s = dot(mn, D) / select(abs(across) > 1e-30f, across, lfloat(1e-30f));
    return step * select(surface && s >= 0.0f && s < 1.0f, s, lfloat(1.0f));
}

// The sample before the current one along a slice (the receiver itself before the first):
// its offset X from the receiver, its view-space normal, its image offset w (viewOffset's units).
struct FootprintPrevious {
    lvec3 X;
    lvec3 m;
    lvec2 w;
    lbool surface;
};

// A sample texel's visible surface is not a point but its pixel's footprint: on the texel's
// tangent plane (view-space normal m), the segment between the rays through the pixel's two
// edges along the slice's image direction `dir`. Seen at a grazing angle one pixel holds metres
// of depth (a floor in front of a wall's foot), which the centre's depth alone steps over. The
// segment lies in the texel's plane, so on the receiver's own plane it stays on the tangent and
// occludes nothing. A half of it is kept only where the texel on the other side continues the
// plane (a silhouette's tangent plane runs along the eye's ray and would stand for a wall there),
// is cut at the run jump (P.runJump), and the whole is clipped to the ball of radius R. It adds
// the angles between its ends (none below the tangent); the sample's own interval is set as before.
void occupyFootprint(lvec3 X, lvec2 corner, lvec3 sampleRay, lfloat sampleDepth, lvec3 m, lvec2 dir, lvec2 w,
                     lbool use, INOUT(FootprintPrevious) previous, lvec3 T, lvec3 n, lfloat nE, lfloat nV,
                     float radius2, INOUT(lfloat) horizonA, INOUT(lfloat) horizonB, INOUT(luint) sectors) {
    FootprintPrevious before = previous;
    previous.X = X;
    previous.m = m;
    previous.w = w;
    previous.surface = use;
    // From the pixel's centre to its border along dir: in pixels, and in viewOffset's image units.
    lfloat toEdge = 0.5f / max(max(abs(dir.x), abs(dir.y)), 1e-6f);
    lvec2 delta = lvec2(dir.x * (toEdge * P.invFx), dir.y * (toEdge * -P.invFy));
    lvec2 across = dir * (2.0f * toEdge);
    lbool behindSurface;
    lvec3 behindNormal;
    lvec3 behindD;
    neighbourTexel(corner, across * -1.0f, sampleRay, sampleDepth, use, behindSurface, behindNormal, behindD);
    lbool aheadSurface;
    lvec3 aheadNormal;
    lvec3 aheadD;
    neighbourTexel(corner, across, sampleRay, sampleDepth, use, aheadSurface, aheadNormal, aheadD);
    // The half towards -dir needs the plane to go on at +dir, and the other way round.
    lbool back = use && continuesPlane(aheadSurface, aheadNormal, m);
    lbool ahead = use && continuesPlane(behindSurface, behindNormal, m);
    if (!anyLane(back || ahead)) {
        return;
    }
    // A neighbour on this plane cuts nothing (its crossing would be rounding over rounding).
    lvec3 step0 = cutAtNeighbour(planeStep(sampleRay, sampleDepth, m, delta * -1.0f, lfloat(P.runJump)),
                                 behindSurface && !ahead, behindNormal, behindD);
    // Back across the gap to the previous sample, cut where the plane meets that sample's plane.
    // As far as it can still reach the ball of radius R around the receiver.
    lvec3 gap = planeStep(sampleRay, sampleDepth, m, before.w - w, sqrt(dot(X, X)) + P.radius);
    lfloat across0 = dot(before.m, gap);
    lfloat cut = dot(before.m, before.X - X) / select(abs(across0) > 1e-30f, across0, lfloat(1e-30f));
    // On one plane with the previous sample (parallel, and its point within 3.6 degrees of this
    // plane as seen from the sample) the cut is rounding over rounding: the whole gap is that
    // plane. Not with the receiver: its own plane occludes nothing, and a plane curving away from
    // it would meet its ray in front of it, the direction of the eye.
    lvec3 toBefore = before.X - X;
    lfloat offPlane = dot(m, toBefore);
    lbool samePlane = continuesPlane(before.surface, before.m, m) && dot(before.w, before.w) > 0.0f &&
                      offPlane * offPlane <= 0.004f * dot(toBefore, toBefore);
    lbool crosses = before.surface && !samePlane && cut >= 0.0f && cut <= 1.0f;
    lbool gapPlane = crosses || samePlane;
    // The pixel's own half is the least it reaches (so a crease next to the sample changes nothing abruptly).
    lvec3 toPrevious = gap * select(crosses, cut, lfloat(1.0f));
    step0 = select(gapPlane && dot(toPrevious, toPrevious) > dot(step0, step0), toPrevious, step0);
    lvec3 step1 = cutAtNeighbour(planeStep(sampleRay, sampleDepth, m, delta, lfloat(P.runJump)), aheadSurface && !back,
                                 aheadNormal, aheadD);
    lvec3 X0 = X + step0 * select(back, lfloat(1.0f), lfloat(0.0f));
    lvec3 X1 = X + step1 * select(ahead, lfloat(1.0f), lfloat(0.0f));
    lvec3 P0;
    lvec3 P1;
    lbool meets;
    clipToBall(X0, X1, radius2, P0, P1, meets);
    lfloat a0 = dot(T, P0);
    lfloat b0 = dot(n, P0);
    lfloat a1 = dot(T, P1);
    lfloat b1 = dot(n, P1);
    // An end within rounding of the tangent (0.57 degrees as seen at the sample's distance, as
    // runs) is on it: near the receiver (a footprint reaching back to it) its angle is rounding alone.
    lfloat near2 = 1e-4f * dot(X, X);
    b0 = select(b0 * b0 > 1e-4f * (a0 * a0 + b0 * b0) + near2, b0, lfloat(0.0f));
    b1 = select(b1 * b1 > 1e-4f * (a1 * a1 + b1 * b1) + near2, b1, lfloat(0.0f));
    // The higher end (by angle; an end under the tangent is the lower) bounds the interval.
    lbool firstHigher = b1 <= 0.0f || (b0 > 0.0f && a1 * b0 - b1 * a0 > 0.0f);
    lfloat topA = select(firstHigher, a0, a1);
    lfloat topB = select(firstHigher, b0, b1);
    lfloat lowA = select(firstHigher, a1, a0);
    lfloat lowB = select(firstHigher, b1, b0);
    // A low end within 10^-4 rad above the horizon (often the previous sample's own point, which
    // raised it) joins it: whether it lies just above or on it is rounding.
    lbool nearHorizon = horizonA * lowB - horizonB * lowA <=
                        1e-4f * sqrt((horizonA * horizonA + horizonB * horizonB) * (lowA * lowA + lowB * lowB));
    lowA = select(nearHorizon, lfloat(1.0f), lowA);
    lowB = select(nearHorizon, lfloat(0.0f), lowB);
    lbool counts = (back || ahead) && meets && topB > 0.0f && topA * nV + topB * nE > 0.0f;
    occupyInterval(topA, topB, lowA, lowB, counts, horizonA, horizonB, sectors);
}

// Hidden layer k (>= 1) at a sample texel: a surface on that texel's ray behind the visible one.
void occupyDeepLayer(int k, lvec2 corner, lbool use, lvec3 ray, lfloat depth, lvec2 w, lvec3 T, lvec3 n, lfloat nE,
                     lfloat nV, float radius2, lfloat backShiftA, lfloat backShiftB, INOUT(lfloat) horizonA,
                     INOUT(lfloat) horizonB, INOUT(luint) sectors) {
    lfloat front = gatherDeepAtDisplay(corner, 2 * k, use) * P.depthScale;
    lbool counts = use && isSurfaceDepth(front);
    if (anyLane(counts)) {
        lfloat back = gatherDeepAtDisplay(corner, 2 * k + 1, counts) * P.depthScale;
        lbool span = counts && back > front && isSurfaceDepth(back);
        front = select(counts, front, depth);
        lvec3 frontX = viewOffset(ray, depth, w, front);
        lvec3 backX = viewOffset(ray, depth, w, select(span, back, front));
        occupySpan(frontX, backX, span, counts, T, n, nE, nV, radius2, backShiftA, backShiftB, horizonA, horizonB,
                   sectors);
    }
}

// Adaptive thickness (`--thickness auto`, HBAO_MEASURED_THICKNESS, P.hbaoRuns). One T cannot suit both a
// pole (about as deep as it is wide) and a sphere or a wall (deep behind its silhouette), so
// the thickness is measured per occluder. Along a slice, consecutive samples above the tangent
// plane whose depth (along V) changes by at most P.runJump form a run: one occluder as this
// slice crosses it. A run that ends inside the search (the next sample is on or below the
// tangent plane, sky, or jumps in depth) was crossed whole, and its depth is taken as
// P.runDepthPerWidth times its width (first to last sample, plus one step), at most
// P.thickness; a run cut off by the search's end or the buffer's edge may be any depth and
// gets P.thickness. Its samples share that thickness, so a run is applied when it ends, as
// one interval: from the lower of its ends' backs to its top. Linear falloff with a fixed T
// takes this path too (P.hbaoRuns), every run P.thickness deep.
struct OccluderRun {
    lfloat firstA, firstB;     // its first sample
    lfloat lastA, lastB;       // its last sample so far
    lfloat topA, topB;         // its highest sample within R, from the horizon when it started
    lbool raised;              // some sample rose above that horizon: only then does the run add
    lfloat topF;               // linear falloff: F at its top
    lfloat rise;               // linear falloff: sum of W(r) times each sample's rise of F above
                               // the horizon and the run's earlier samples
};

// The thickness of a run crossed whole: k times its width across the slice (first to last
// sample plus the step one sample stands for, `foot`), in world units, at most P.thickness.
lfloat runThickness(OccluderRun run, lfloat invNLen, lfloat foot) {
    lfloat dA = run.lastA - run.firstA;
    lfloat dB = run.lastB - run.firstB;
    lfloat width = sqrt(dA * dA + dB * dB) * invNLen + foot;
    if (P.hbaoModel != HBAO_MEASURED_THICKNESS) {
        return lfloat(P.thickness);
    }
    return min(P.runDepthPerWidth * width, lfloat(P.thickness));
}

// Applies the runs ending in lanes `ends`, each with its thickness t. The
// lower of its ends' backs (its first and last samples pushed t along -V) stands for the
// lowest back. When that is not above the horizon the run's interval joins the horizon's,
// which rises to the run's top; else it sets the sectors between the two.
//
// Linear falloff: a run that joins adds its weighted rises, scaled down by the share of its
// rise that sectors set earlier already count (each angle is weighted once, by the first
// occluder over it, as the horizon does); an apart run adds its new sectors at its mean weight.
void closeRuns(lbool ends, lfloat t, OccluderRun run, lfloat nE, lfloat nV, lfloat cosB, lfloat sinB,
               lfloat nLen, INOUT(lfloat) horizonA, INOUT(lfloat) horizonB, INOUT(lfloat) horizonF,
               INOUT(luint) sectors, INOUT(lfloat) sliceOcclusion) {
    lfloat firstBackA = run.firstA + t * nE;
    lfloat firstBackB = run.firstB - t * nV;
    lfloat lastBackA = run.lastA + t * nE;
    lfloat lastBackB = run.lastB - t * nV;
    // Both lie on the E side (a push along -V keeps the E coordinate): their angles compare by
    // the sign of a cross product.
    lbool firstLower = firstBackA * lastBackB - firstBackB * lastBackA > 0.0f;
    lfloat backA = select(firstLower, firstBackA, lastBackA);
    lfloat backB = select(firstLower, firstBackB, lastBackB);
    lbool joins = joinsHorizon(backA, backB, horizonA, horizonB);
    lbool higher = raiseHorizon(ends && joins, run.topA, run.topB, horizonA, horizonB);
    lfloat runRange = max(run.topF - horizonF, 1e-30f);
    if (P.linearFalloff != 0) {
        lfloat counted = lfloat(0.0f);
        if (anyLane(higher && lfloat(sectors) > 0.0f)) {
            counted = sectorOcclusionBetween(sectors, horizonF, max(run.topF, horizonF), cosB, sinB, nLen);
        }
        sliceOcclusion += select(higher, run.rise * max(1.0f - counted / runRange, 0.0f), lfloat(0.0f));
        horizonF = select(higher, max(run.topF, horizonF), horizonF);
    }
    lbool apart = ends && !joins;
    if (anyLane(apart)) {
        lint front = sectorBound(sectorPseudoAngle(run.topA, run.topB));
        lint back = sectorBound(sectorPseudoAngle(backA, backB));
        luint interval = select(apart, bitsBelow(front) & ~bitsBelow(back), luint(0u));
        if (P.linearFalloff != 0) {
            luint added = interval & ~sectors;
            if (anyLane(lfloat(added) > 0.0f)) {
                sliceOcclusion += (run.rise / runRange) * sectorOcclusion(added, horizonF, cosB, sinB, nLen);
            }
        }
        sectors = sectors | interval;
    }
}

// Border clamp (1) and tangent (2) (docs/hbao.md, "The frame's border"). Past the buffer's edge the
// continued surface is, at each texel, the nearest edge texel's tangent plane met by the texel's
// ray (where it meets it in front of the eye; else, and for clamp, the edge texel's depth).
// On one plane the angle seen from the receiver changes monotonically along a slice, and the part
// within R is one segment, so its highest point within R is one of that segment's ends: a lane
// that leaves the buffer stops marching and takes the ends of the chord from the edge texel where
// it left (its own surface point) to the continued surface at its last step, clipped to the ball
// of radius R. Where the chord lies in the far end's plane (the edge continues one plane) it is
// that plane, every angle between its ends covered; else its ends are two samples. Edge texels
// come through the backend's gatherEdgeDepth and gatherEdgeTexel (depth and normal; the CPU tables
// them per frame).
//
// The continued surface at display corner `corner` past the edge, as an offset from the receiver;
// `valid` where the nearest edge texel is a surface, m its view-space normal (tangent only).
lvec3 continuedOffset(lvec2 corner, lbool use, lvec3 ray, lfloat depth, lvec2 cornerToOffset, OUT(lbool) valid,
                      OUT(lvec3) m) {
    lvec2 edgeCorner = nearestBufferCorner(corner);
    // Tangent reads the texel's normal with its depth: one record where the backend tables them.
    lvec4 edge = P.hbaoBorder == 2 ? gatherEdgeTexel(edgeCorner, use)
                                   : lvec4(gatherEdgeDepth(edgeCorner, use), lfloat(0.0f), lfloat(0.0f), lfloat(0.0f));
    lfloat edgeDepth = edge.x * P.depthScale;
    valid = use && isSurfaceDepth(edgeDepth);
    lfloat d = edgeDepth;
    m = lvec3(lfloat(0.0f), lfloat(0.0f), lfloat(0.0f));
    if (P.hbaoBorder == 2) {
        m = select(valid, mat3(P.normalToView) * lvec3(edge.y, edge.z, edge.w), m);
        lvec3 e = positionOnRay(viewRay(lvec2(edgeCorner.x + 0.5f, edgeCorner.y + 0.5f)), edgeDepth);
        lvec3 sampleRay = viewRay(lvec2(corner.x + 0.5f, corner.y + 0.5f));
        // Planar depth -z; radial depth (perspective only) is t |ray| for the point ray t.
        lfloat planeDepth = -rayMeetsPlane(sampleRay, m, e).z;
        if (P.orthographic == 0 && P.radialDepth != 0) {
            planeDepth *= sqrt(dot(sampleRay, sampleRay));
        }
        d = select(valid && isSurfaceDepth(planeDepth), planeDepth, edgeDepth);
    }
    return viewOffset(ray, depth, imageOffset(corner + cornerToOffset), select(valid, d, depth));
}

// The chord of a lane that left the buffer at display corner `exitCorner` and whose last step is
// at `lastCorner`: its ends X0 (at the edge) and X1, where either is a surface (`valid`), and
// whether it lies in one plane. Where one end is not a surface the other stands alone.
void continuedChord(lvec2 exitCorner, lvec2 lastCorner, lbool left, lvec3 ray, lfloat depth, lvec2 cornerToOffset,
                    OUT(lvec3) X0, OUT(lvec3) X1, OUT(lbool) valid, OUT(lbool) onePlane) {
    lvec2 edgeCorner = nearestBufferCorner(exitCorner);
    lfloat edgeDepth = gatherEdgeDepth(edgeCorner, left) * P.depthScale;
    // Not the receiver's own texel (a receiver on the edge): its offset is rounding alone.
    lvec2 pixels = edgeCorner + cornerToOffset;
    lbool edgeValid = left && isSurfaceDepth(edgeDepth) && abs(pixels.x) + abs(pixels.y) > 0.0f;
    X0 = viewOffset(ray, depth, imageOffset(pixels), select(edgeValid, edgeDepth, depth));
    lbool lastValid;
    lvec3 m;
    X1 = continuedOffset(lastCorner, left, ray, depth, cornerToOffset, lastValid, m);
    // X0 within 0.57 degrees of X1's plane, as seen from X1 (the chord's direction and the normal).
    // Clamp has no plane (m = 0 passes): its chord is always one occluder.
    lvec3 chord = X0 - X1;
    lfloat across = dot(m, chord);
    onePlane = edgeValid && lastValid && across * across <= 1e-4f * dot(m, m) * dot(chord, chord);
    X0 = select(edgeValid, X0, X1);
    X1 = select(lastValid, X1, X0);
    valid = edgeValid || lastValid;
}

// A run of the samples (a0, b0) and, where `joined`, (a1, b1) (F values f0, f1; c0, c1 where each
// counts), closed at once with thickness P.thickness; linear falloff weighs its rises by `weight`.
void closeSamples(lfloat a0, lfloat b0, lbool c0, lfloat f0, lfloat a1, lfloat b1, lbool c1, lfloat f1, lbool joined,
                  lfloat weight, lfloat nE, lfloat nV, lfloat cosB, lfloat sinB, lfloat nLen,
                  INOUT(lfloat) horizonA, INOUT(lfloat) horizonB, INOUT(lfloat) horizonF, INOUT(luint) sectors,
                  INOUT(lfloat) sliceOcclusion) {
    OccluderRun run;
    run.firstA = a0;
    run.firstB = b0;
    run.lastA = select(joined, a1, a0);
    run.lastB = select(joined, b1, b0);
    run.topA = horizonA;
    run.topB = horizonB;
    lbool higher0 = raiseHorizon(c0, a0, b0, run.topA, run.topB);
    lbool higher1 = raiseHorizon(joined && c1, a1, b1, run.topA, run.topB);
    run.raised = higher0 || higher1;
    lfloat f1j = select(joined, f1, lfloat(0.0f));
    run.topF = max(f0, f1j);
    run.rise = weight * max(max(f0, f1j) - horizonF, 0.0f);
    closeRuns(run.raised, lfloat(P.thickness), run, nE, nV, cosB, sinB, nLen, horizonA, horizonB, horizonF, sectors,
              sliceOcclusion);
}

// The continued surface between the chord's ends P0 and P1: cut off by the edge, it occludes as a
// run the edge cuts does, P.thickness deep (the horizon alone: the higher end). Linear falloff
// weighs its rises by `weight`.
void takeContinued(lvec3 P0, lvec3 P1, lbool use, lbool onePlane, lfloat weight, lvec3 T, lvec3 n,
                   lfloat nE, lfloat nV, lfloat cosB, lfloat sinB, lfloat nLen, INOUT(lfloat) horizonA,
                   INOUT(lfloat) horizonB, INOUT(lfloat) horizonF, INOUT(luint) sectors, INOUT(lfloat) sliceOcclusion) {
    lfloat a0 = dot(T, P0);
    lfloat b0 = dot(n, P0);
    lfloat a1 = dot(T, P1);
    lfloat b1 = dot(n, P1);
    // Above the tangent by more than rounding (0.57 degrees, as runs): the receiver's own plane
    // continued past the edge occludes nothing.
    lbool counts0 = use && b0 > 0.0f && b0 * b0 > 1e-4f * dot(P0, P0) && a0 * nV + b0 * nE > 0.0f;
    lbool counts1 = use && b1 > 0.0f && b1 * b1 > 1e-4f * dot(P1, P1) && a1 * nV + b1 * nE > 0.0f;
    if (P.hbaoModel == HBAO_HORIZON && P.linearFalloff == 0) {
        raiseHorizon(counts0, a0, b0, horizonA, horizonB);
        raiseHorizon(counts1, a1, b1, horizonA, horizonB);
        return;
    }
    lfloat f0 = lfloat(0.0f);
    lfloat f1 = lfloat(0.0f);
    if (P.linearFalloff != 0) {
        f0 = sampleF(a0, b0, counts0, cosB, sinB, nLen);
        f1 = sampleF(a1, b1, counts1, cosB, sinB, nLen);
    }
    if (P.hbaoModel == HBAO_HORIZON) {
        raiseLinearHorizon(f0, weight, horizonF, sliceOcclusion);
        raiseLinearHorizon(f1, weight, horizonF, sliceOcclusion);
        return;
    }
    // The chord whole where it is one plane, else P0 alone and then P1 alone.
    if (anyLane(counts0 || (counts1 && onePlane))) {
        closeSamples(a0, b0, counts0, f0, a1, b1, counts1, f1, onePlane, weight, nE, nV, cosB, sinB, nLen,
                     horizonA, horizonB, horizonF, sectors, sliceOcclusion);
    }
    lbool alone1 = counts1 && !onePlane;
    if (anyLane(alone1)) {
        lbool none = lfloat(0.0f) > 0.0f; // false in every lane
        closeSamples(a1, b1, alone1, f1, a1, b1, none, f1, none, weight, nE, nV, cosB, sinB, nLen, horizonA,
                     horizonB, horizonF, sectors, sliceOcclusion);
    }
}

// The depth a march step at display corner `corner` reads, and in `use` the lanes that read it:
// every lane computing on an interior slice, else those whose texel is in the buffer.
lfloat loadStep(lvec2 corner, lbool computing, bool interior, OUT(lbool) use) {
    use = computing;
    if (!interior) {
        use = use && insideBuffer(corner - vec2(bufferOrigin()), 0.0f);
    }
    return gatherDepthAtDisplay(corner, use);
}

// Ambient occlusion in [0,1] (1 = unoccluded) of the buffer texels (x, y); texels outside
// the buffer, sky and holes get 1.
lfloat hbaoLanes(lint x, lint y) {
    lbool computing;
    lfloat depth = surfaceDepth(x, y, computing);
    if (!anyLane(computing)) {
        return lfloat(1.0f);
    }
    lint displayX = x + P.originX;
    lint displayY = y + P.originY;
    lvec2 centre = lvec2(lfloat(displayX) + 0.5f, lfloat(displayY) + 0.5f);
    lvec3 ray = viewRay(centre);
    // Pixel offset of a sample texel = its corner + this; exact in float (whole and half numbers).
    lvec2 cornerToOffset = lvec2(0.5f - centre.x, 0.5f - centre.y);
    lvec3 V = viewVector(ray);
    lvec3 n = viewNormal(gatherNormal(x, y, computing), V);

    // Screen-space extent of the sphere of radius R around the point: f R / sqrt(z^2 - R^2)
    // bounds every point within R, also those nearer the eye (the paper's f R / z misses them).
    lfloat planarDepth = -positionOnRay(ray, depth).z;
    lfloat radiusPixels = lfloat(P.radius * P.fx);
    if (P.orthographic == 0) {
        radiusPixels *= inversesqrt(max(planarDepth * planarDepth - P.radius * P.radius, 1e-30f));
    }
    radiusPixels = min(radiusPixels, P.maxRadiusPixels);
    computing = computing && radiusPixels >= 1.0f; // else nothing within R is a whole pixel away
    if (!anyLane(computing)) {
        return lfloat(1.0f);
    }
    // The first sample sits one pixel out; the rest spread evenly to the radius.
    lfloat stepPixels = (radiusPixels - 1.0f) * (1.0f / float(P.steps));
    // Every sample lies within radiusPixels of the centre: when that square (with a texel to
    // spare for rounding) is inside the depth buffer for every lane, no step needs a bounds test.
    vec2 origin = vec2(bufferOrigin());
    lvec2 reach = lvec2(radiusPixels, radiusPixels);
    bool discInside = !anyLane(computing && !(insideBuffer(floor(centre - reach) - origin, 1.0f) &&
                                               insideBuffer(floor(centre + reach) - origin, 1.0f)));
    float radius2 = P.radius * P.radius;
    // World width one step stands for at the pixel's depth (thickness auto's run widths).
    lfloat footprint = max(stepPixels, lfloat(1.0f)) * P.invFx * (P.orthographic != 0 ? lfloat(1.0f) : planarDepth);
    float invRadius = 1.0f / P.radius;

    luint h = hashPixel(displayX, displayY);
    lfloat rotation = hashToUnit(h);
    lfloat jitter = hashToUnit(hashU32(h));

    // Basis of the plane perpendicular to V; V.z > 0 for any visible point, so B1 is well defined.
    lvec3 B1 = normalize(lvec3(V.z, 0.0f, -V.x));
    lvec3 B2 = cross(V, B1);

    // Slice d lies at angle (d + rotation) 2 pi / N_d: one sine and cosine per pixel, then
    // each next slice by a fixed rotation.
    float sliceAngle = TWO_PI / float(P.directions);
    float cosStep = cos(sliceAngle);
    float sinStep = sin(sliceAngle);
    lfloat cosPhi = cos(rotation * sliceAngle);
    lfloat sinPhi = sin(rotation * sliceAngle);

    lfloat occlusion = lfloat(0.0f);
    for (int d = 0; d < P.directions; ++d) {
        lvec3 E = cosPhi * B1 + sinPhi * B2;
        lfloat nextCos = cosPhi * cosStep - sinPhi * sinStep;
        sinPhi = sinPhi * cosStep + cosPhi * sinStep;
        cosPhi = nextCos;
        lvec2 dir = screenDirection(ray, E);

        lfloat nE = dot(n, E);
        lfloat nV = dot(n, V); // > 0 after viewNormal
        lfloat invNLen = inversesqrt(max(nE * nE + nV * nV, 1e-24f));
        lfloat nLen = (nE * nE + nV * nV) * invNLen; // length of the normal projected into the slice
        lfloat cosB = nE * invNLen;
        lfloat sinB = nV * invNLen;
        // Tangent-plane axes of the slice: T along it (elevation t, sin t = -cos b, on the E
        // side), n across it, both |n_p| times unit length: every use of (a, b) below is an
        // angle or a sign, which a common positive scale leaves alone. A sample is on the E
        // side when its E coordinate, a cos t - b sin t ~ a nV + b nE, is positive.
        lvec3 T = nV * E - nE * V;

        // The horizon so far: the tangent itself, (a, b) = (1, 0), theta = 0, F = 0.
        lfloat horizonA = lfloat(1.0f);
        lfloat horizonB = lfloat(0.0f);
        lfloat horizonF = lfloat(0.0f);
        lfloat sliceOcclusion = lfloat(0.0f);
        // Pushing a sample t along -V moves it by (a, b) += t (nE, -nV) in the slice's axes.
        lfloat backShiftA = P.thickness * nE;
        lfloat backShiftB = -P.thickness * nV;
        luint sectors = luint(0u); // occluded sectors above the horizon's interval
        // Deep input (bitmask 2) measures its solids; runs estimate them for flat input only.
        bool adaptive = P.hbaoRuns != 0;
        lbool inRun = lfloat(0.0f) > 0.0f; // false in every lane
        FootprintPrevious previous; // deep input's footprints: the receiver before the first sample
        previous.X = lvec3(lfloat(0.0f), lfloat(0.0f), lfloat(0.0f));
        previous.m = n;
        previous.w = lvec2(lfloat(0.0f), lfloat(0.0f));
        previous.surface = computing;
        OccluderRun run;
        run.firstA = lfloat(0.0f);
        run.firstB = lfloat(0.0f);
        run.lastA = lfloat(0.0f);
        run.lastB = lfloat(0.0f);
        run.topA = lfloat(1.0f);
        run.topB = lfloat(0.0f);
        run.raised = inRun;
        run.topF = lfloat(0.0f);
        run.rise = lfloat(0.0f);
        // A depth change along V, in the slice's axes (scaled by |n_p|^2 like a and b).
        lfloat runJump = P.runJump * nLen * nLen;
        // March along the image line in display coordinates (so any tiling rounds alike): the
        // first sample one pixel out, then evenly to the radius.
        lvec2 step = dir * stepPixels;
        lvec2 position = centre + dir * (1.0f + jitter * stepPixels);
        lvec2 start = position;
        // Off the interior, how many steps each lane took inside the buffer (the line is straight and
        // the buffer convex, so they come first): where its line left the buffer, if it did.
        lfloat stepsInside = lfloat(0.0f);
        // Each coordinate moves monotonically, so when the first and the last sample of every
        // lane are inside the depth buffer (the last with a texel to spare for rounding), all are,
        // and the steps skip the bounds test: the common case away from the frame's edges.
        bool interior = discInside;
        if (!interior) {
            lvec2 last = position + step * float(P.steps - 1);
            interior = !anyLane(computing && !(insideBuffer(floor(position) - origin, 0.0f) &&
                                                insideBuffer(floor(last) - origin, 1.0f)));
        }
        // Each step's depth is loaded one step ahead, so the load's latency overlaps the work on
        // the sample before (the step's work is too long for the CPU to reach it alone).
        lbool aheadUse;
        lfloat aheadDepth = loadStep(floor(position), computing, interior, aheadUse);
        for (int s = 0; s < P.steps; ++s) {
            lvec2 corner = floor(position);
            position = position + step;
            lbool counts = aheadUse;
            lfloat loaded = aheadDepth;
            if (s + 1 < P.steps) {
                aheadDepth = loadStep(floor(position), computing, interior, aheadUse);
            }
            if (!interior) {
                stepsInside += select(counts, lfloat(1.0f), lfloat(0.0f));
                // The image line is straight and the buffer convex: once every lane has left it,
                // every later step is outside too.
                if (!anyLane(counts)) {
                    break;
                }
            }
            lbool sampled = counts; // before the surface test: deep layers may lie behind sky
            lfloat sampleDepth = loaded * P.depthScale;
            counts = counts && isSurfaceDepth(sampleDepth);
            sampleDepth = select(counts, sampleDepth, depth); // holes and sky: keep X finite
            // Scaled after the exact subtraction: scaling first would cancel digits.
            lvec2 w = imageOffset(corner + cornerToOffset);
            lvec3 X = viewOffset(ray, depth, w, sampleDepth);
            lfloat r2 = dot(X, X);
            lfloat a = dot(T, X);
            lfloat b = dot(n, X);
            // A sample counts if it is a surface within R, above the tangent plane (below it, it
            // cannot raise the horizon) and on the E side (snapping can push one across V). Then
            // theta is in (0, pi - b): F grows with theta, and two angles there compare exactly by
            // the sign of their cross product.
            lbool surface = counts; // before the radius and tangent-plane tests: deep spans clip to R
            // Runs take samples above the tangent by more than rounding (0.57 degrees): the
            // receiver's own plane, stored at half precision too, starts none.
            lbool above = counts && b > 0.0f && b * b > 1e-4f * r2;
            counts = counts && r2 <= radius2 && b > 0.0f && a * nV + b * nE > 0.0f;
            if (adaptive && !anyLane(above || inRun)) {
                // No run goes on and none starts (a receiver on open ground): only the linear
                // falloff's on-tangent samples below need this step.
                if (P.linearFalloff != 0) {
                    lfloat f;
                    lfloat weight;
                    linearTerms(a, b, r2, counts, cosB, sinB, nLen, invRadius, f, weight);
                    raiseHorizonByF(counts, a, b, f, horizonF, horizonA, horizonB);
                    raiseLinearHorizon(f, weight, horizonF, sliceOcclusion);
                }
            } else if (adaptive) {
                lfloat toEye = (b - run.lastB) * nV - (a - run.lastA) * nE;
                lbool continues = inRun && above && abs(toEye) <= runJump;
                lbool ends = inRun && !continues;
                // A run whose top is not above the horizon adds nothing (its sectors would lie under
                // the horizon, its rises are none): most runs end so, and skip the close. The top
                // starts at the horizon, which only a close raises while the run goes on, so the
                // test is a flag set as the top rises, not a cross product a step.
                lbool matters = ends && run.raised;
                if (anyLane(matters)) {
                    // A run ending past the edge (its end not seen) may be any depth.
                    lbool leftBuffer = !insideBuffer(corner - origin, 0.0f);
                    lfloat t = select(leftBuffer, lfloat(P.thickness), runThickness(run, invNLen, footprint));
                    closeRuns(matters, t, run, nE, nV, cosB, sinB, nLen, horizonA, horizonB, horizonF, sectors,
                              sliceOcclusion);
                }
                // A sample that does not continue a run starts one, or lies in none: either way the
                // run's state restarts from it (outside a run the top stays at the horizon).
                run.topA = select(continues, run.topA, horizonA);
                run.topB = select(continues, run.topB, horizonB);
                if (P.linearFalloff != 0) {
                    run.topF = select(ends, lfloat(0.0f), run.topF);
                    run.rise = select(ends, lfloat(0.0f), run.rise);
                }
                run.firstA = select(continues, run.firstA, a);
                run.firstB = select(continues, run.firstB, b);
                lbool inside = counts && above; // can occlude
                lbool higher = inside && run.topA * b - run.topB * a > 0.0f;
                run.topA = select(higher, a, run.topA);
                run.topB = select(higher, b, run.topB);
                run.raised = (continues && run.raised) || higher;
                if (P.linearFalloff != 0) {
                    // Linear falloff: a sample within rounding of the tangent raises the horizon as
                    // it would without runs (its back lies below the tangent for any thickness that
                    // matters), so a large T is the linear horizon. Binary visibility drops it: it
                    // adds at most F at 0.57 degrees, and nothing on the receiver's own plane.
                    lbool onTangent = counts && !above;
                    lfloat f;
                    lfloat weight;
                    linearTerms(a, b, r2, counts, cosB, sinB, nLen, invRadius, f, weight);
                    raiseHorizonByF(onTangent, a, b, f, horizonF, horizonA, horizonB);
                    lfloat insideF = select(inside, f, lfloat(0.0f));
                    run.rise += weight * max(insideF - max(horizonF, run.topF), 0.0f);
                    run.topF = max(run.topF, insideF);
                    raiseLinearHorizon(select(onTangent, f, lfloat(0.0f)), weight, horizonF, sliceOcclusion);
                }
                run.lastA = a;
                run.lastB = b;
                inRun = above;
            } else if (P.linearFalloff != 0) {
                lfloat f;
                lfloat weight;
                linearTerms(a, b, r2, counts, cosB, sinB, nLen, invRadius, f, weight);
                raiseLinearHorizon(f, weight, horizonF, sliceOcclusion);
            } else if (P.hbaoModel == HBAO_DEEP) {
                // Deep input: the visible layer's span where the renderer saw the ray leave its solid,
                // then every hidden layer (inside the buffer: past it, the continued surface's samples).
                lfloat back = gatherDeepAtDisplay(corner, 1, surface) * P.depthScale;
                lbool span = surface && back > sampleDepth && isSurfaceDepth(back);
                lvec3 backX = viewOffset(ray, depth, w, select(span, back, sampleDepth));
                occupySpan(X, backX, span, surface, T, n, nE, nV, radius2, backShiftA, backShiftB, horizonA, horizonB,
                           sectors);
                // The texel's footprint on its tangent plane.
                lvec3 sampleRay = lvec3(ray.x + w.x, ray.y + w.y, ray.z);
                lvec3 m = viewNormal(gatherNormal(lint(corner.x - origin.x), lint(corner.y - origin.y), surface),
                                     viewVector(sampleRay));
                occupyFootprint(X, corner, sampleRay, sampleDepth, m, dir, w, surface, previous, T, n, nE, nV,
                                radius2, horizonA, horizonB, sectors);
                for (int k = 1; k < P.deepLayers; ++k) {
                    occupyDeepLayer(k, corner, sampled, ray, depth, w, T, n, nE, nV, radius2, backShiftA, backShiftB,
                                    horizonA, horizonB, sectors);
                }
            } else if (P.hbaoModel == HBAO_FIXED_THICKNESS) {
                occupyInterval(a, b, a + backShiftA, b + backShiftB, counts, horizonA, horizonB, sectors);
            } else {
                raiseHorizon(counts, a, b, horizonA, horizonB);
            }
        }
        lbool unclosed = inRun && run.raised;
        if (adaptive && anyLane(unclosed)) {
            // Runs still going when the search ends (or leaves the buffer) may be any depth.
            closeRuns(unclosed, lfloat(P.thickness), run, nE, nV, cosB, sinB, nLen, horizonA, horizonB, horizonF, sectors,
                      sliceOcclusion);
        }
        lbool left = computing && stepsInside < float(P.steps);
        if (P.hbaoBorder != 0 && !interior && anyLane(left)) {
            // The lanes that left the buffer take the continued surface's samples (above).
            lvec2 exitCorner = floor(start + step * stepsInside);
            lvec2 lastCorner = floor(start + step * float(P.steps - 1));
            lvec3 X0;
            lvec3 X1;
            lbool valid;
            lbool onePlane;
            continuedChord(exitCorner, lastCorner, left, ray, depth, cornerToOffset, X0, X1, valid, onePlane);
            // Only a point above the horizon adds anything, and which side of the horizon's line a
            // point lies on is linear along the chord: where both ends are on or under that line, so
            // is all of it (the receiver's own ground continued, say), and the lane takes nothing.
            lbool rises = valid && (aboveHorizon(dot(T, X0), dot(n, X0), horizonA, horizonB) ||
                                    aboveHorizon(dot(T, X1), dot(n, X1), horizonA, horizonB));
            if (anyLane(rises)) {
                lvec3 P0;
                lvec3 P1;
                lbool meets;
                clipToBall(X0, X1, radius2, P0, P1, meets);
                // Linear falloff: the chord's rises weighed at its near end (the angle a plane covers
                // grows fastest nearest the receiver; measured against the mean and the far end's W).
                lfloat weight = falloffWeight(dot(P0, P0), invRadius);
                takeContinued(P0, P1, rises && meets, onePlane, weight, T, n, nE, nV, cosB, sinB, nLen, horizonA,
                              horizonB, horizonF, sectors, sliceOcclusion);
            }
        }
        if (P.linearFalloff == 0) {
            lfloat invLen = inversesqrt(horizonA * horizonA + horizonB * horizonB);
            sliceOcclusion = sliceOcclusionAt(horizonA * invLen, horizonB * invLen, cosB, sinB, nLen);
            if (P.hbaoModel != HBAO_HORIZON) {
                // Sectors wholly below the horizon add nothing: clear them, and skip the sum when none is left.
                lint horizonSector = min(lint(sectorPseudoAngle(horizonA, horizonB) * 16.0f), lint(31));
                sectors = sectors & ~bitsBelow(horizonSector);
                if (anyLane(lfloat(sectors) > 0.0f)) {
                    sliceOcclusion += sectorOcclusion(sectors, sliceOcclusion, cosB, sinB, nLen);
                }
            }
        }
        occlusion += sliceOcclusion;
    }
    // Uniform: (1/2pi) * (2pi/N_d) * sum. Cosine: (1/pi) * (2pi/N_d) * sum.
    float norm = (P.cosineWeighting != 0 ? 2.0f : 1.0f) / float(P.directions);
    return select(computing, clamp(1.0f - occlusion * norm, 0.0f, 1.0f), 1.0f);
}
