// Geometric normals from the depth pass and the camera, where no normal pass is given (or
// --normals depth asks for them): the one reconstruction every method uses on both devices,
// and the one disc AO gives its elements (kernels/discs.glsl). Written on lane types like
// kernels/common.glsl, which it requires.
//
// Per texel and axis, the step to the neighbour on the side that continues the texel's plane:
// w (1/z under perspective, z orthographic) is affine in the pixel coordinates on a plane, so
// the side whose second difference of w is smaller continues it; never across a depth step or
// a crease, where the other side's bends. The normal is the cross product of the two steps.

// The offset to a neighbouring texel's surface point (side: +-1 along x or y), and whether
// it is a surface. viewOffset keeps it exact where the depth is large.
lvec3 depthStep(lint x, lint y, lvec3 ray, lfloat depth, int sx, int sy, OUT(lbool) surface) {
    lfloat depthS = surfaceDepth(x + sx, y + sy, surface);
    return viewOffset(ray, depth, lvec2(lfloat(float(sx) * P.invFx), lfloat(-float(sy) * P.invFy)), depthS);
}

// w: 1/z under perspective, z orthographic. On a plane it is affine in the pixel coordinates,
// so its second difference along a row is 0 and grows only across a crease or a step.
lfloat depthW(lint x, lint y, lfloat depth) {
    if (P.orthographic != 0) {
        return depth;
    }
    lvec3 ray = viewRay(lvec2(lfloat(x + P.originX) + 0.5f, lfloat(y + P.originY) + 0.5f));
    return -1.0f / positionOnRay(ray, depth).z;
}

// w of the texels 1 and 2 steps (sx, sy) from texel (x, y), and whether they are surfaces.
void depthSide(lint x, lint y, int sx, int sy, OUT(lfloat) w1, OUT(lbool) ok1, OUT(lfloat) w2, OUT(lbool) ok2) {
    w1 = depthW(x + sx, y + sy, surfaceDepth(x + sx, y + sy, ok1));
    w2 = depthW(x + 2 * sx, y + 2 * sy, surfaceDepth(x + 2 * sx, y + 2 * sy, ok2));
}

// How far a texel (w0) and its neighbours at 1 and 2 steps on one side are from one plane:
// the second difference of w; 1e30 where either neighbour is not a surface.
lfloat depthBend(lfloat w0, lfloat w1, lbool ok1, lfloat w2, lbool ok2) {
    return select(ok1 && ok2, abs(w2 - 2.0f * w1 + w0), lfloat(1e30f));
}

// Of the steps to the two neighbours along one axis that are surfaces, the one on the side
// that continues the texel's plane (the smaller bend): next to a crease the step across it
// would tilt the normal halfway to the other face. On equal bends (a plane, or no second
// neighbours) the shorter (across a depth step, the far side is the longer). `found`: at
// least one neighbour is a surface. The step is signed as if it went ahead (+x or +y).
lbool depthTakesAhead(lvec3 back, lbool backOk, lfloat backBend, lvec3 ahead, lbool aheadOk, lfloat aheadBend) {
    lbool shorter = dot(ahead, ahead) < dot(back, back);
    lbool flatter = aheadBend < backBend || (!(aheadBend > backBend) && shorter);
    return aheadOk && (!backOk || flatter);
}

lvec3 depthPlaneStep(lvec3 back, lbool backOk, lfloat backBend, lvec3 ahead, lbool aheadOk, lfloat aheadBend,
                     OUT(lbool) found) {
    found = backOk || aheadOk;
    return select(depthTakesAhead(back, backOk, backBend, ahead, aheadOk, aheadBend), ahead, back * -1.0f);
}

// A step to a neighbour steeper than this tangent (84 degrees from facing the eye) that no
// further texel shows to continue a plane crosses a depth discontinuity: it reaches another surface.
CONST_GLOBAL float DEPTH_STEEP_TAN = 10.0f;

// Whether the step s to a neighbour that is a surface (ok) stays on the texel's surface: gentle,
// or on the plane its side's next texel continues (bend within a tenth of the first difference dw of w).
lbool depthStepJoins(lvec3 s, lvec3 V, lbool ok, lfloat bend, lfloat dw) {
    lfloat along = dot(s, V);
    lfloat lateral2 = max(dot(s, s) - along * along, 0.0f);
    lbool gentle = along * along <= (DEPTH_STEEP_TAN * DEPTH_STEEP_TAN) * lateral2;
    return ok && (gentle || bend <= 0.1f * abs(dw));
}

// The unit normal of the plane the steps along x and y span, facing the eye (V); `usable`
// is false where they are parallel (or zero).
lvec3 depthNormalOfSteps(lvec3 sx, lvec3 sy, lvec3 V, OUT(lbool) usable) {
    lvec3 g = cross(sy, sx);
    lfloat g2 = dot(g, g);
    usable = g2 > 0.0f;
    g = g * inversesqrt(select(usable, g2, lfloat(1.0f)));
    return select(dot(g, V) < 0.0f, g * -1.0f, g);
}

// The step of texel (x, y) along axis (ax, ay), (1, 0) or (0, 1), on its own surface: the plane
// step (depthPlaneStep) where it joins the surface (depthStepJoins), else the other side's where
// that one does. Where neither does, the texel is a feature one or two texels wide: the step to
// a neighbour nearer the eye (the same object, seen towards its silhouette; the shorter of two),
// and none (found false) where both neighbours lie far behind it.
lvec3 depthAxisStep(lint x, lint y, lvec3 ray, lfloat depth, lfloat w0, lvec3 V, int ax, int ay, OUT(lbool) found) {
    lbool backOk;
    lbool aheadOk;
    lvec3 back = depthStep(x, y, ray, depth, -ax, -ay, backOk);
    lvec3 ahead = depthStep(x, y, ray, depth, ax, ay, aheadOk);
    lfloat wb1;
    lfloat wb2;
    lfloat wa1;
    lfloat wa2;
    lbool okB1;
    lbool okB2;
    lbool okA1;
    lbool okA2;
    depthSide(x, y, -ax, -ay, wb1, okB1, wb2, okB2);
    depthSide(x, y, ax, ay, wa1, okA1, wa2, okA2);
    lfloat backBend = depthBend(w0, wb1, okB1, wb2, okB2);
    lfloat aheadBend = depthBend(w0, wa1, okA1, wa2, okA2);
    lbool plane = depthTakesAhead(back, backOk, backBend, ahead, aheadOk, aheadBend);
    lbool backJoins = depthStepJoins(back, V, backOk, backBend, wb1 - w0);
    lbool aheadJoins = depthStepJoins(ahead, V, aheadOk, aheadBend, wa1 - w0);
    lbool keep = (plane && aheadJoins) || (!plane && backJoins);
    lbool swap = !keep && ((plane && backJoins) || (!plane && aheadJoins));
    lbool backNear = backOk && dot(back, V) > 0.0f;
    lbool aheadNear = aheadOk && dot(ahead, V) > 0.0f;
    lbool nearer = aheadNear && (!backNear || dot(ahead, ahead) < dot(back, back));
    lbool neither = !aheadJoins && !backJoins;
    lbool takeAhead = (keep && plane) || (swap && !plane) || (neither && nearer);
    found = aheadJoins || backJoins || aheadNear || backNear;
    return select(takeAhead, ahead, back * -1.0f);
}

// The unit normal facing the eye (V) as closely as a surface along step s allows: V without its
// component along s.
lvec3 depthNormalAcross(lvec3 s, lvec3 V) {
    lvec3 n = V - s * (dot(V, s) / max(dot(s, s), lfloat(1e-30f)));
    lfloat n2 = dot(n, n);
    return select(n2 > 0.0f, n * inversesqrt(select(n2 > 0.0f, n2, lfloat(1.0f))), V);
}

// The view-space unit normal of texel (x, y) from the depth alone, facing the eye. Where the
// texel has no step on its surface along one axis (a feature a texel or two wide: a pole, a
// distant facet) it faces the eye as closely as the other axis's step allows, and the eye
// where it has none along either; not a surface: (0, 0, 0).
lvec3 depthNormalLanes(lint x, lint y) {
    lbool surface;
    lfloat depth = surfaceDepth(x, y, surface);
    lvec3 ray = viewRay(lvec2(lfloat(x + P.originX) + 0.5f, lfloat(y + P.originY) + 0.5f));
    lvec3 V = viewVector(ray);
    lfloat w0 = depthW(x, y, depth);
    lbool alongX;
    lbool alongY;
    lvec3 sx = depthAxisStep(x, y, ray, depth, w0, V, 1, 0, alongX);
    lvec3 sy = depthAxisStep(x, y, ray, depth, w0, V, 0, 1, alongY);
    lbool usable;
    lvec3 g = depthNormalOfSteps(sx, sy, V, usable);
    lvec3 one = select(alongY, depthNormalAcross(sy, V), select(alongX, depthNormalAcross(sx, V), V));
    lvec3 none = lvec3(lfloat(0.0f), lfloat(0.0f), lfloat(0.0f));
    return select(surface, select(alongX && alongY && usable, g, one), none);
}
