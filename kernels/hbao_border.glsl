// HBAO past the buffer's edge (kernels/hbao.glsl, docs/hbao.md "The frame's border"), where
// P.hbaoBorder is HBAO_BORDER_CLAMP or HBAO_BORDER_TANGENT (HBAO_BORDER_OPEN sees open sky). The
// continued surface is, at each texel past the edge, the nearest edge texel's tangent plane met
// by the texel's ray (where it meets it in front of the eye; past the plane's horizon, the plane
// towards it; else, and for clamp, the edge texel's depth). On one plane the angle seen from the
// receiver changes monotonically along a slice, and the part within R is one segment, so its
// highest point within R is one of that segment's ends: a lane that leaves the buffer stops
// marching and takes the ends of the chord from the edge texel where it left (its own surface
// point) to the continued surface at its last step, clipped to the ball of radius R. Where the
// chord lies in the far end's plane (the edge continues one plane) it is that plane, every angle
// between its ends covered; else its ends are two samples. Edge texels come through the
// backend's gatherEdgeDepth and gatherEdgeTexel (depth and normal; the CPU tables them per frame).

// The plane through edge point e (normal m, facing the eye) along the slice's image line to
// `toRay`, which passes above the plane's horizon (a floor seen from less than R above it): the
// plane runs to infinity before toRay, in the direction of the ray where the line crosses the
// horizon. The line starts at the receiver's ray where that meets the plane in front (the
// slice's own line), else at the edge texel's. The far end is taken that way from e, past the
// ball of radius R (clipToBall keeps what lies within), as an offset from the receiver.
lvec3 towardsHorizon(lvec3 edgeRay, lvec3 toRay, lvec3 m, lvec3 e, IN(HbaoReceiver) r) {
    lvec3 fromRay = select(dot(r.ray, m) < 0.0f, r.ray, edgeRay);
    lfloat f0 = dot(fromRay, m); // < 0: meets the plane in front
    lfloat f1 = dot(toRay, m);   // >= 0: does not
    lfloat t = clamp(f0 / min(f0 - f1, lfloat(-1e-30f)), 0.0f, 1.0f);
    lvec3 crossing = normalize(fromRay + (toRay - fromRay) * t);
    lvec3 receiver = positionOnRay(r.ray, r.depth);
    lvec3 fromReceiver = e - receiver;
    return fromReceiver + crossing * (sqrt(dot(fromReceiver, fromReceiver)) + 2.0f * P.radius);
}

// The continued surface at display corner `corner` past the edge, as an offset from the receiver;
// `valid` where the nearest edge texel is a surface, m its view-space normal (tangent only).
lvec3 continuedOffset(lvec2 corner, lbool use, IN(HbaoReceiver) r, OUT(lbool) valid, OUT(lvec3) m) {
    lvec2 edgeCorner = nearestBufferCorner(corner);
    // Tangent reads the texel's normal with its depth: one record where the backend tables them.
    lvec4 edge = P.hbaoBorder == HBAO_BORDER_TANGENT
                     ? gatherEdgeTexel(edgeCorner, use)
                     : lvec4(gatherEdgeDepth(edgeCorner, use), lfloat(0.0f), lfloat(0.0f), lfloat(0.0f));
    lfloat edgeDepth = edge.x * P.depthScale;
    valid = use && isSurfaceDepth(edgeDepth);
    lfloat d = edgeDepth;
    m = lvec3(lfloat(0.0f), lfloat(0.0f), lfloat(0.0f));
    lbool pastHorizon = lfloat(0.0f) > 0.0f; // false in every lane
    lvec3 facing = m;
    lvec3 edgeRay = viewRay(lvec2(edgeCorner.x + 0.5f, edgeCorner.y + 0.5f));
    lvec3 sampleRay = viewRay(lvec2(corner.x + 0.5f, corner.y + 0.5f));
    lvec3 e = positionOnRay(edgeRay, edgeDepth);
    if (P.hbaoBorder == HBAO_BORDER_TANGENT) {
        m = select(valid, mat3(P.normalToView) * lvec3(edge.y, edge.z, edge.w), m);
        // Planar depth -z; radial depth (perspective only) is t |ray| for the point ray t.
        lfloat planeDepth = -rayMeetsPlane(sampleRay, m, e).z;
        if (P.orthographic == 0 && P.radialDepth != 0) {
            planeDepth *= sqrt(dot(sampleRay, sampleRay));
        }
        lbool meets = valid && isSurfaceDepth(planeDepth);
        d = select(meets, planeDepth, edgeDepth);
        // The normal as the eye sees the plane (a pass may hold a back face's).
        facing = select(dot(m, e) > 0.0f, -m, m);
        if (P.orthographic == 0) {
            pastHorizon = valid && !meets && dot(sampleRay, facing) >= 0.0f && dot(edgeRay, facing) < 0.0f;
        }
    }
    lvec3 X = viewOffset(r.ray, r.depth, imageOffset(corner + r.cornerToOffset), select(valid, d, r.depth));
    if (anyLane(pastHorizon)) {
        X = select(pastHorizon, towardsHorizon(edgeRay, sampleRay, facing, e, r), X);
    }
    return X;
}

// The chord of a lane that left the buffer at display corner `exitCorner` and whose last step is
// at `lastCorner`: its ends X0 (at the edge) and X1, where either is a surface (`valid`), and
// whether it lies in one plane. Where one end is not a surface the other stands alone.
void continuedChord(lvec2 exitCorner, lvec2 lastCorner, lbool left, IN(HbaoReceiver) r, OUT(lvec3) X0,
                    OUT(lvec3) X1, OUT(lbool) valid, OUT(lbool) onePlane) {
    lvec2 edgeCorner = nearestBufferCorner(exitCorner);
    lfloat edgeDepth = gatherEdgeDepth(edgeCorner, left) * P.depthScale;
    // Not the receiver's own texel (a receiver on the edge): its offset is rounding alone.
    lvec2 pixels = edgeCorner + r.cornerToOffset;
    lbool edgeValid = left && isSurfaceDepth(edgeDepth) && abs(pixels.x) + abs(pixels.y) > 0.0f;
    X0 = viewOffset(r.ray, r.depth, imageOffset(pixels), select(edgeValid, edgeDepth, r.depth));
    lbool lastValid;
    lvec3 m;
    X1 = continuedOffset(lastCorner, left, r, lastValid, m);
    // X0 within 0.57 degrees of X1's plane, as seen from X1 (the chord's direction and the normal).
    // Clamp has no plane (m = 0 passes): its chord is always one occluder.
    lvec3 chord = X0 - X1;
    lfloat across = dot(m, chord);
    onePlane = edgeValid && lastValid && across * across <= 1e-4f * dot(m, m) * dot(chord, chord);
    X0 = select(edgeValid, X0, X1);
    X1 = select(lastValid, X1, X0);
    valid = edgeValid || lastValid;
}

// An end of the chord in the slice's axes: where it counts (above the tangent, on the E side) and
// its F (linear falloff).
struct BorderPoint {
    lfloat a, b;
    lbool counts;
    lfloat f;
};

// A run of the points p0 and, where `joined`, p1, closed at once with thickness P.thickness;
// linear falloff weighs its rises by `weight` (hbao_runs.glsl).
void closeSamples(BorderPoint p0, BorderPoint p1, lbool joined, lfloat weight, IN(HbaoSlice) sl,
                  INOUT(HbaoOccluded) o) {
    OccluderRun run = noRun();
    run.firstA = p0.a;
    run.firstB = p0.b;
    run.lastA = select(joined, p1.a, p0.a);
    run.lastB = select(joined, p1.b, p0.b);
    run.topA = o.horizonA;
    run.topB = o.horizonB;
    lbool higher0 = raiseHorizon(p0.counts, p0.a, p0.b, run.topA, run.topB);
    lbool higher1 = raiseHorizon(joined && p1.counts, p1.a, p1.b, run.topA, run.topB);
    run.raised = higher0 || higher1;
    lfloat f1j = select(joined, p1.f, lfloat(0.0f));
    run.topF = max(p0.f, f1j);
    run.rise = weight * max(max(p0.f, f1j) - o.horizonF, 0.0f);
    closeRuns(run.raised, lfloat(P.thickness), run, sl.np, o);
}

// The continued surface between the chord's ends P0 and P1: cut off by the edge, it occludes as a
// run the edge cuts does, P.thickness deep (the horizon alone: the higher end). Linear falloff
// weighs its rises by `weight`.
void takeContinued(lvec3 P0, lvec3 P1, lbool use, lbool onePlane, lfloat weight, IN(HbaoSlice) sl,
                   INOUT(HbaoOccluded) o) {
    BorderPoint p0;
    BorderPoint p1;
    p0.a = dot(sl.T, P0);
    p0.b = dot(sl.n, P0);
    p1.a = dot(sl.T, P1);
    p1.b = dot(sl.n, P1);
    // Above the tangent by more than rounding (0.57 degrees, as runs): the receiver's own plane
    // continued past the edge occludes nothing.
    p0.counts = use && p0.b > 0.0f && p0.b * p0.b > 1e-4f * dot(P0, P0) && p0.a * sl.np.nV + p0.b * sl.np.nE > 0.0f;
    p1.counts = use && p1.b > 0.0f && p1.b * p1.b > 1e-4f * dot(P1, P1) && p1.a * sl.np.nV + p1.b * sl.np.nE > 0.0f;
    if (HBAO_MODEL == HBAO_HORIZON && P.linearFalloff == 0) {
        raiseHorizon(p0.counts, p0.a, p0.b, o.horizonA, o.horizonB);
        raiseHorizon(p1.counts, p1.a, p1.b, o.horizonA, o.horizonB);
        return;
    }
    p0.f = lfloat(0.0f);
    p1.f = lfloat(0.0f);
    if (P.linearFalloff != 0) {
        p0.f = sampleF(p0.a, p0.b, p0.counts, sl.np);
        p1.f = sampleF(p1.a, p1.b, p1.counts, sl.np);
    }
    if (HBAO_MODEL == HBAO_HORIZON) {
        raiseLinearHorizon(p0.f, weight, o);
        raiseLinearHorizon(p1.f, weight, o);
        return;
    }
    // The chord whole where it is one plane, else P0 alone and then P1 alone.
    if (anyLane(p0.counts || (p1.counts && onePlane))) {
        closeSamples(p0, p1, onePlane, weight, sl, o);
    }
    lbool alone1 = p1.counts && !onePlane;
    if (anyLane(alone1)) {
        BorderPoint q = p1;
        q.counts = alone1;
        BorderPoint none = p1;
        none.counts = lfloat(0.0f) > 0.0f; // false in every lane
        closeSamples(q, none, none.counts, weight, sl, o);
    }
}

// The chord of the lanes that `left` the buffer on a march (continuedChord), and where they left.
struct BorderChord {
    lvec2 exitCorner;
    lvec3 X0, X1;
    lbool valid, onePlane;
};

BorderChord borderChord(IN(HbaoReceiver) r, IN(HbaoMarch) m, lbool left) {
    BorderChord c;
    c.exitCorner = floor(m.start + m.step * m.stepsInside);
    lvec2 lastCorner = floor(m.start + m.step * float(P.steps - 1));
    continuedChord(c.exitCorner, lastCorner, left, r, c.X0, c.X1, c.valid, c.onePlane);
    return c;
}

// The lanes that `left` the buffer (off the interior: where the march left it) take the continued
// surface's chord, where it can rise above the horizon.
void takeBorder(IN(HbaoReceiver) r, IN(HbaoSlice) sl, IN(HbaoMarch) m, lbool left, INOUT(HbaoOccluded) o) {
    BorderChord c = borderChord(r, m, left);
    lvec3 X0 = c.X0;
    lvec3 X1 = c.X1;
    // Only a point above the horizon adds anything, and which side of the horizon's line a point
    // lies on is linear along the chord: where both ends are on or under that line, so is all of
    // it (the receiver's own ground continued, say), and the lane takes nothing.
    lbool rises = c.valid && (aboveHorizon(dot(sl.T, X0), dot(sl.n, X0), o.horizonA, o.horizonB) ||
                              aboveHorizon(dot(sl.T, X1), dot(sl.n, X1), o.horizonA, o.horizonB));
    if (anyLane(rises)) {
        lvec3 P0;
        lvec3 P1;
        lbool meets;
        clipToBall(X0, X1, r.radius2, P0, P1, meets);
        // Linear falloff: the chord's rises weighed at its near end (the angle a plane covers
        // grows fastest nearest the receiver; measured against the mean and the far end's W).
        lfloat weight = falloffWeight(dot(P0, P0), r.invRadius);
        takeContinued(P0, P1, rises && meets, c.onePlane, weight, sl, o);
    }
}
