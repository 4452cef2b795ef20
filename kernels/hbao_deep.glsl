// HBAO_DEEP (kernels/hbao.glsl, docs/deep.md): every surface the renderer saw on a sample texel's
// ray, with the solid spans it crossed, is an interval of the visibility bitmask
// (hbao_bitmask.glsl), and so is each sample's footprint on its tangent plane.
//
// The backend's gatherDeepAtDisplay(corner, c, use) reads channel c of P.deepLayers (front, back)
// depth pairs per texel, layer 0 the visible surface, +inf fronts past a ray's last surface. A
// back beyond its front is a solid the renderer saw the ray cross (a span); else the surface's
// depth is unknown and the thickness rule pushes its front back, as without deep input (with no
// thickness, P.thickness = +inf, its back lies at -inf below the tangent: the horizon's interval).

// A layer's interval in a slice: front (a, b) to back (backA, backB), in lanes `counts`. The AO
// occupies it (occupyInterval), the light covers it (hbao_gi.glsl's coverGi).
struct DeepInterval {
    lfloat a, b, backA, backB;
    lbool counts;
};

// One layer at a sample texel, front frontX and back backX (offsets from the receiver): a span
// counts for its part inside the sphere of radius R (a long span whose front lies beyond R may
// still pass close by), a point sample when its front is within R; then, as for the visible
// layer, only when that front is above the tangent plane and on the E side.
DeepInterval spanInterval(lvec3 frontX, lvec3 backX, lbool span, lbool use, IN(HbaoSlice) sl, float radius2) {
    lvec3 spanFront;
    lvec3 back;
    lbool chord;
    clipToBall(frontX, backX, radius2, spanFront, back, chord);
    lbool meets = (span && chord) || (!span && dot(frontX, frontX) <= radius2);
    lvec3 front = select(span, spanFront, frontX);
    DeepInterval i;
    i.a = dot(sl.T, front);
    i.b = dot(sl.n, front);
    i.backA = select(span, dot(sl.T, back), i.a + sl.backShiftA);
    i.backB = select(span, dot(sl.n, back), i.b + sl.backShiftB);
    i.counts = use && meets && i.b > 0.0f && i.a * sl.np.nV + i.b * sl.np.nE > 0.0f;
    return i;
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

FootprintPrevious receiverFootprint(IN(HbaoReceiver) r) {
    FootprintPrevious previous;
    previous.X = lvec3(lfloat(0.0f), lfloat(0.0f), lfloat(0.0f));
    previous.m = r.n;
    previous.w = lvec2(lfloat(0.0f), lfloat(0.0f));
    previous.surface = r.computing;
    return previous;
}

// The footprint's segment P0 .. P1 (clipped to the ball of radius R) as an interval: its higher
// end (by angle; an end under the tangent is the lower) bounds it, and a low end near the horizon
// joins the horizon's. `halves`: the lanes with some half of the footprint kept.
void occupyFootprintSegment(lvec3 P0, lvec3 P1, lbool halves, lvec3 X, IN(HbaoSlice) sl, INOUT(HbaoOccluded) o) {
    lfloat a0 = dot(sl.T, P0);
    lfloat b0 = dot(sl.n, P0);
    lfloat a1 = dot(sl.T, P1);
    lfloat b1 = dot(sl.n, P1);
    // An end within rounding of the tangent (0.57 degrees as seen at the sample's distance, as
    // runs) is on it: near the receiver (a footprint reaching back to it) its angle is rounding alone.
    lfloat near2 = 1e-4f * dot(X, X);
    b0 = select(b0 * b0 > 1e-4f * (a0 * a0 + b0 * b0) + near2, b0, lfloat(0.0f));
    b1 = select(b1 * b1 > 1e-4f * (a1 * a1 + b1 * b1) + near2, b1, lfloat(0.0f));
    lbool firstHigher = b1 <= 0.0f || (b0 > 0.0f && a1 * b0 - b1 * a0 > 0.0f);
    lfloat topA = select(firstHigher, a0, a1);
    lfloat topB = select(firstHigher, b0, b1);
    lfloat lowA = select(firstHigher, a1, a0);
    lfloat lowB = select(firstHigher, b1, b0);
    // A low end within 10^-4 rad above the horizon (often the previous sample's own point, which
    // raised it) joins it: whether it lies just above or on it is rounding.
    lbool nearHorizon = o.horizonA * lowB - o.horizonB * lowA <=
                        1e-4f * sqrt((o.horizonA * o.horizonA + o.horizonB * o.horizonB) * (lowA * lowA + lowB * lowB));
    lowA = select(nearHorizon, lfloat(1.0f), lowA);
    lowB = select(nearHorizon, lfloat(0.0f), lowB);
    lbool counts = halves && topB > 0.0f && topA * sl.np.nV + topB * sl.np.nE > 0.0f;
    occupyInterval(topA, topB, lowA, lowB, counts, o);
}

// A sample texel's visible surface is not a point but its pixel's footprint: on the texel's
// tangent plane (view-space normal m), the segment between the rays through the pixel's two
// edges along the slice's image direction. Seen at a grazing angle one pixel holds metres of
// depth (a floor in front of a wall's foot), which the centre's depth alone steps over. The
// segment lies in the texel's plane, so on the receiver's own plane it stays on the tangent and
// occludes nothing. A half of it is kept only where the texel on the other side continues the
// plane (a silhouette's tangent plane runs along the eye's ray and would stand for a wall there),
// is cut at the run jump (P.runJump), and the whole is clipped to the ball of radius R. It adds
// the angles between its ends (none below the tangent); the sample's own interval is set apart.
//
// The steps it may take from the sample on its plane: its two half pixels along the slice (up to
// the run jump), and back across the gap to the previous sample, as far as that can still reach
// the ball of radius R. The cuts of occupyFootprint only shorten them.
struct FootprintSteps {
    lvec2 across; // one pixel along the slice, in pixels
    lvec3 half0, half1, gap;
};

FootprintSteps footprintSteps(IN(HbaoSample) smp, lvec3 sampleRay, lvec3 m, IN(FootprintPrevious) before, IN(HbaoSlice) sl) {
    // From the pixel's centre to its border along dir: in pixels, and in viewOffset's image units.
    lfloat toEdge = 0.5f / max(max(abs(sl.dir.x), abs(sl.dir.y)), 1e-6f);
    lvec2 delta = lvec2(sl.dir.x * (toEdge * P.invFx), sl.dir.y * (toEdge * -P.invFy));
    FootprintSteps f;
    f.across = sl.dir * (2.0f * toEdge);
    f.half0 = planeStep(sampleRay, smp.depth, m, delta * -1.0f, lfloat(P.runJump));
    f.half1 = planeStep(sampleRay, smp.depth, m, delta, lfloat(P.runJump));
    f.gap = planeStep(sampleRay, smp.depth, m, before.w - smp.w, sqrt(dot(smp.X, smp.X)) + P.radius);
    return f;
}

// Whether the footprint may occupy anything: its ends lie on the segments from the sample to the
// ends of its steps, and a point's height b = sl.n . P is linear along each. Where no step's end
// rises above the tangent's rounding band (occupyFootprintSegment's: b within 10^-2 |X|), nothing
// can count (0.98e-4 = 0.99^2 10^-4: a margin for the sums' rounding). A plane's samples seen
// from that plane (most of a floor or a wall) stop here, before the neighbours are read.
lbool footprintMayRise(IN(HbaoSample) smp, IN(FootprintSteps) f, IN(HbaoSlice) sl) {
    lfloat b = dot(sl.n, smp.X);
    lfloat rise = max(max(b, b + dot(sl.n, f.gap)), max(b + dot(sl.n, f.half0), b + dot(sl.n, f.half1)));
    return rise > 0.0f && rise * rise > 0.98e-4f * dot(smp.X, smp.X);
}

// The footprint of a sample some lane of which footprintMayRise let through: the neighbours'
// cuts, then the segment occupied.
OUT_OF_LINE void occupyFootprint(IN(HbaoSample) smp, lvec3 sampleRay, lvec3 m, IN(FootprintPrevious) before,
                                 IN(FootprintSteps) f, IN(HbaoSlice) sl, float radius2, INOUT(HbaoOccluded) o) {
    lbool use = smp.surface;
    lbool behindSurface;
    lvec3 behindNormal;
    lvec3 behindD;
    neighbourTexel(smp.corner, f.across * -1.0f, sampleRay, smp.depth, use, behindSurface, behindNormal, behindD);
    lbool aheadSurface;
    lvec3 aheadNormal;
    lvec3 aheadD;
    neighbourTexel(smp.corner, f.across, sampleRay, smp.depth, use, aheadSurface, aheadNormal, aheadD);
    // The half towards -dir needs the plane to go on at +dir, and the other way round.
    lbool back = use && continuesPlane(aheadSurface, aheadNormal, m);
    lbool ahead = use && continuesPlane(behindSurface, behindNormal, m);
    if (!anyLane(back || ahead)) {
        return;
    }
    // A neighbour on this plane cuts nothing (its crossing would be rounding over rounding).
    lvec3 step0 = cutAtNeighbour(f.half0, behindSurface && !ahead, behindNormal, behindD);
    // The gap is cut where the plane meets the previous sample's plane.
    lfloat across0 = dot(before.m, f.gap);
    lfloat cut = dot(before.m, before.X - smp.X) / select(abs(across0) > 1e-30f, across0, lfloat(1e-30f));
    // On one plane with the previous sample (parallel, and its point within 3.6 degrees of this
    // plane as seen from the sample) the cut is rounding over rounding: the whole gap is that
    // plane. Not with the receiver: its own plane occludes nothing, and a plane curving away from
    // it would meet its ray in front of it, the direction of the eye.
    lvec3 toBefore = before.X - smp.X;
    lfloat offPlane = dot(m, toBefore);
    lbool samePlane = continuesPlane(before.surface, before.m, m) && dot(before.w, before.w) > 0.0f &&
                      offPlane * offPlane <= 0.004f * dot(toBefore, toBefore);
    lbool crosses = before.surface && !samePlane && cut >= 0.0f && cut <= 1.0f;
    lbool gapPlane = crosses || samePlane;
    // The pixel's own half is the least it reaches (so a crease next to the sample changes nothing abruptly).
    lvec3 toPrevious = f.gap * select(crosses, cut, lfloat(1.0f));
    step0 = select(gapPlane && dot(toPrevious, toPrevious) > dot(step0, step0), toPrevious, step0);
    lvec3 step1 = cutAtNeighbour(f.half1, aheadSurface && !back, aheadNormal, aheadD);
    lvec3 X0 = smp.X + step0 * select(back, lfloat(1.0f), lfloat(0.0f));
    lvec3 X1 = smp.X + step1 * select(ahead, lfloat(1.0f), lfloat(0.0f));
    lvec3 P0;
    lvec3 P1;
    lbool meets;
    clipToBall(X0, X1, radius2, P0, P1, meets);
    occupyFootprintSegment(P0, P1, (back || ahead) && meets, smp.X, sl, o);
}

// The texel's footprint after the sample's own interval; `previous` becomes this sample.
void takeFootprint(IN(HbaoSample) smp, lvec3 sampleRay, IN(HbaoSlice) sl, float radius2, INOUT(FootprintPrevious) previous,
                   INOUT(HbaoOccluded) o) {
    vec2 origin = vec2(bufferOrigin());
    lvec3 m = viewNormal(gatherNormal(lint(smp.corner.x - origin.x), lint(smp.corner.y - origin.y), smp.surface),
                         viewVector(sampleRay));
    FootprintPrevious before = previous;
    previous.X = smp.X;
    previous.m = m;
    previous.w = smp.w;
    previous.surface = smp.surface;
    FootprintSteps f = footprintSteps(smp, sampleRay, m, before, sl);
    if (anyLane(smp.surface && footprintMayRise(smp, f, sl))) {
        occupyFootprint(smp, sampleRay, m, before, f, sl, radius2, o);
    }
}

// Hidden layer k (>= 1) at a sample texel: a surface on that texel's ray behind the visible one.
// Its back is read only where some lane has the layer (`more`).
DeepInterval hiddenLayerInterval(int k, IN(HbaoSample) smp, IN(HbaoReceiver) r, IN(HbaoSlice) sl, OUT(bool) more) {
    lfloat front = gatherDeepAtDisplay(smp.corner, 2 * k, smp.sampled) * P.depthScale;
    DeepInterval i;
    i.a = i.b = i.backA = i.backB = lfloat(0.0f);
    i.counts = smp.sampled && isSurfaceDepth(front);
    more = anyLane(i.counts);
    if (more) {
        lfloat back = gatherDeepAtDisplay(smp.corner, 2 * k + 1, i.counts) * P.depthScale;
        lbool span = i.counts && back > front && isSurfaceDepth(back);
        front = select(i.counts, front, r.depth);
        lvec3 frontX = viewOffset(r.ray, r.depth, smp.w, front);
        lvec3 backX = viewOffset(r.ray, r.depth, smp.w, select(span, back, front));
        i = spanInterval(frontX, backX, span, i.counts, sl, r.radius2);
    }
    return i;
}

// The visible layer's interval: its span where the renderer saw the ray leave its solid, else
// its point pushed T back (as takeSampleFixed).
DeepInterval visibleLayerInterval(IN(HbaoSample) smp, IN(HbaoReceiver) r, IN(HbaoSlice) sl) {
    lfloat back = gatherDeepAtDisplay(smp.corner, 1, smp.surface) * P.depthScale;
    lbool span = smp.surface && back > smp.depth && isSurfaceDepth(back);
    lvec3 backX = viewOffset(r.ray, r.depth, smp.w, select(span, back, smp.depth));
    return spanInterval(smp.X, backX, span, smp.surface, sl, r.radius2);
}
