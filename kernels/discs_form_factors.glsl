// Disc AO's weights and form factors (kernels/discs.glsl): how open a node is, a disc's and a
// polygon's form factor, their union per azimuth slice, and reading a node of the pyramid.
// Included by discs.glsl at this point of the kernel; docs/discs.md derives them.

// Open weight of a node `dist` node sizes from the receiver: smooth from 1 at k (where every
// grandparent of a visited node is still fully open, as k >= k/2 + 1/2) to 0 at k + 1/2 (the
// edge of the block the finer window covers). Without blending: open inside that block, by index.
lfloat discOpen(lfloat dist, lfloat indexDist, int window) {
    float k = float(window);
    if (P.discBlend == 0) {
        return select(indexDist < k + 0.5f, lfloat(1.0f), lfloat(0.0f));
    }
    lfloat s = clamp((dist - k) * 2.0f, 0.0f, 1.0f);
    return 1.0f - s * s * (3.0f - 2.0f * s);
}

// Share of an element at distance d inside R (binary visibility, or W = 1 - r/R for linear
// falloff): a ramp across the element's radius, so elements straddling R count in part.
lfloat discRangeWeight(lfloat d, lfloat area) {
    lfloat inside = clamp(0.5f + (P.radius - d) * (0.5f * inversesqrt(max(area * (1.0f / PI), 1e-30f))), 0.0f, 1.0f);
    if (P.linearFalloff != 0) {
        inside = inside * max(1.0f - d * (1.0f / P.radius), 0.0f);
    }
    return inside;
}

// Cosine-weighted form factor of a disc (area A, normal ne) at v from the receiver: exact
// for a disc facing the receiver on its axis, A / (A + pi d^2), and A cos cos / (pi d^2) far
// away. The emitter's side does not matter: a surface seen from behind stands for its solid.
lfloat discFormFactor(lvec3 v, lfloat d2, lvec3 nr, lvec3 ne, lfloat area, float horizon) {
    lfloat invD = inversesqrt(max(d2, 1e-30f));
    lfloat cosR = max(dot(nr, v) * invD - horizon, 0.0f);
    lfloat cosE = abs(dot(ne, v)) * invD;
    lfloat projected = cosE * area;
    // The receiver's own pixel (d = 0, no polygon) has cosR = 0 and must not give 0 / 0.
    return cosR * projected / max(PI * d2 + projected, 1e-30f);
}

// Lambert's term of one polygon edge a -> b seen from the origin: the angle it subtends times
// the receiver normal's component along the edge plane's unit normal.
lfloat discEdgeTerm(lvec3 a, lvec3 b, lvec3 nr) {
    lvec3 c = cross(a, b);
    lfloat s2 = dot(c, c);
    return atan(sqrt(s2), dot(a, b)) * dot(nr, c) * inversesqrt(max(s2, 1e-36f));
}

// One edge a -> b (heights ha, hb above the clip plane) clipped to the part above it; adds
// its term and records where the boundary leaves (exitP) and re-enters (entryP) the half-space.
void discClipEdge(lvec3 a, lfloat ha, lvec3 b, lfloat hb, lvec3 nr, INOUT(lfloat) sum, INOUT(lvec3) exitP,
                  INOUT(lvec3) entryP) {
    lbool inA = ha > 0.0f;
    lbool inB = hb > 0.0f;
    lfloat denom = ha - hb;
    denom = select(abs(denom) > 1e-30f, denom, lfloat(1.0f));
    lvec3 crossing = a + (b - a) * (ha / denom);
    lvec3 s0 = select(inA, a, crossing);
    lvec3 s1 = select(inB, b, crossing);
    sum += select(inA || inB, discEdgeTerm(s0, s1, nr), lfloat(0.0f));
    exitP = select(inA && !inB, crossing, exitP);
    entryP = select(inB && !inA, crossing, entryP);
}

// Exact form factor of the parallelogram c +- du +- dv (c from the receiver, du and dv half
// its sides), clipped to the receiver's upper half-space (correction b): Lambert's formula,
// |sum of edge terms| / 2 pi. The clip plane is raised by `horizon` of the distance, as
// the discs' horizon is.
lfloat discQuadFormFactor(lvec3 nr, lvec3 c, lvec3 du, lvec3 dv, float horizon) {
    lvec3 q0 = c - du - dv;
    lvec3 q1 = c + du - dv;
    lvec3 q2 = c + du + dv;
    lvec3 q3 = c - du + dv;
    lfloat lift = horizon * sqrt(dot(c, c));
    lfloat h0 = dot(nr, q0) - lift;
    lfloat h1 = dot(nr, q1) - lift;
    lfloat h2 = dot(nr, q2) - lift;
    lfloat h3 = dot(nr, q3) - lift;
    lfloat sum = lfloat(0.0f);
    lvec3 exitP = c;
    lvec3 entryP = c;
    discClipEdge(q0, h0, q1, h1, nr, sum, exitP, entryP);
    discClipEdge(q1, h1, q2, h2, nr, sum, exitP, entryP);
    discClipEdge(q2, h2, q3, h3, nr, sum, exitP, entryP);
    discClipEdge(q3, h3, q0, h0, nr, sum, exitP, entryP);
    lbool crossed = (h0 > 0.0f || h1 > 0.0f || h2 > 0.0f || h3 > 0.0f) &&
                    !(h0 > 0.0f && h1 > 0.0f && h2 > 0.0f && h3 > 0.0f);
    sum += select(crossed, discEdgeTerm(exitP, entryP, nr), lfloat(0.0f));
    return abs(sum) * (1.0f / TWO_PI);
}

// The exact form factor of a node's footprint: the image on the node's tangent plane of its
// screen block (node (ex, ey) of `level`), scaled to its area (a block part sky keeps its
// shape, smaller).
lfloat discPolygonFormFactor(lvec3 xr, lvec3 nr, lvec3 e, lvec3 ne, lfloat area, lint ex, lint ey, int level) {
    float size = float(1 << level);
    lvec3 ray = viewRay(lvec2((lfloat(ex) + 0.5f) * size + float(P.originX), (lfloat(ey) + 0.5f) * size + float(P.originY)));
    lvec3 du;
    lvec3 dv;
    discAxes(ray, e, ne, du, dv);
    lvec3 n = cross(du, dv);
    lfloat scale = 0.5f * sqrt(area * inversesqrt(max(dot(n, n), 1e-36f)));
    return discQuadFormFactor(nr, e - xr, du * scale, dv * scale, DISC_HORIZON);
}

// Occluders behind occluders (the stairs: each riser hides the next tread) must not count
// twice, as a plain sum of form factors does. The receiver's hemisphere is cut into
// DISC_SLICES azimuth slices; each keeps the sum of the form factors that fall in it and the
// highest elevation h any of them reaches. Within a slice nothing can occlude more than all
// directions below h, (1 / DISC_SLICES) sin^2(h) (uniform weighting: sin(h)), so the slice
// counts at most that: a riser in front caps the treads and risers it hides. A thin pole covers a small part
// of its slice and is never capped; a plane's elements have form factor 0. Each form factor is
// spread over the slices its direction falls in (a tent at least one slice wide, so the
// result moves smoothly with the receiver).
CONST_GLOBAL int DISC_SLICES = 8;

struct DiscBins {
    lfloat cover[DISC_SLICES];  // form factors gathered in each slice
    lfloat top[DISC_SLICES];    // share of the slice below the highest elevation reached in it
    lfloat sum;                 // the plain sum (P.discUnion == 0)
    lvec3 t1;                   // the receiver's tangent frame: azimuth 0 ...
    lvec3 t2;                   // ... and a quarter turn on
};

void discStartBins(OUT(DiscBins) bins, lvec3 nr) {
    for (int i = 0; i < DISC_SLICES; ++i) {
        bins.cover[i] = lfloat(0.0f);
        bins.top[i] = lfloat(0.0f);
    }
    bins.sum = lfloat(0.0f);
    lvec3 a = select(abs(nr.y) < 0.9f, lvec3(lfloat(0.0f), lfloat(1.0f), lfloat(0.0f)),
                     lvec3(lfloat(1.0f), lfloat(0.0f), lfloat(0.0f)));
    lvec3 t = cross(a, nr);
    bins.t1 = t * inversesqrt(max(dot(t, t), lfloat(1e-30f)));
    bins.t2 = cross(nr, bins.t1);
}

// Adds form factor ff of an element at v from the receiver (normal nr); reach2: its radius
// squared, which widens its tent and raises its top.
void discAdd(INOUT(DiscBins) bins, lvec3 nr, lvec3 v, lfloat d2, lfloat reach2, lfloat ff) {
    // Nothing to add (every lane's element under its horizon: a plane's own, or out of range).
    if (!anyLane(ff > 0.0f)) {
        return;
    }
    lfloat invD = inversesqrt(max(d2, lfloat(1e-30f)));
    lfloat s = clamp(dot(nr, v) * invD, 0.0f, 1.0f);
    lfloat rho = min(sqrt(reach2) * invD, lfloat(1.5f));
    if (P.cosineWeighting == 0) {
        // Uniform weighting (--weighting uniform): the share of the hemisphere's solid angle,
        // d(omega) / 2 pi = (d(omega) cos / pi) / (2 cos) with cos = sin(elevation) at the
        // element's centre; near the horizon at least half its angular radius up (the slice
        // caps the rest).
        ff = ff / (2.0f * max(s, max(0.5f * rho, lfloat(0.05f))));
    }
    if (P.discUnion == 0) {
        bins.sum += ff;
        return;
    }
    float slices = float(DISC_SLICES);
    lfloat c = sqrt(max(1.0f - s * s, lfloat(1e-6f)));
    // Top: the elevation h + rho, to first order; as the slice's share below it: sin^2 for
    // cosine weighting, sin for uniform.
    lfloat top = min(s + c * rho, 1.0f);
    if (P.cosineWeighting != 0) {
        top = top * top;
    }
    // Azimuth in slices, as a diamond angle (0..4 round the circle, octant edges at multiples
    // of 1/2): eight slices of equal weight without an arc tangent (the true angle gained
    // 0.03 dB on the report's mean).
    lfloat ax = dot(bins.t1, v);
    lfloat ay = dot(bins.t2, v);
    lfloat q = ay / max(abs(ax) + abs(ay), lfloat(1e-30f));
    lfloat u = select(ax < 0.0f, 2.0f - q, select(ay < 0.0f, 4.0f + q, q)) * (slices * 0.25f);
    lfloat invW = 1.0f / clamp(rho / c * (slices / TWO_PI), 1.0f, 0.5f * slices);
    lfloat ta[DISC_SLICES];
    lfloat sa = lfloat(0.0f);
    for (int j = 0; j < DISC_SLICES; ++j) {
        lfloat dist = abs(u - float(j));
        dist = min(dist, slices - dist);
        ta[j] = max(1.0f - dist * invW, 0.0f);
        sa += ta[j];
    }
    lfloat scale = ff / sa;
    lbool covering = ff > 0.0f;
    for (int j = 0; j < DISC_SLICES; ++j) {
        bins.cover[j] += ta[j] * scale;
        bins.top[j] = max(bins.top[j], select(covering && ta[j] > 0.0f, top, lfloat(0.0f)));
    }
}

lfloat discOcclusion(DiscBins bins) {
    if (P.discUnion == 0) {
        return bins.sum;
    }
    lfloat occlusion = lfloat(0.0f);
    for (int j = 0; j < DISC_SLICES; ++j) {
        occlusion += min(bins.cover[j], bins.top[j] * (1.0f / float(DISC_SLICES)));
    }
    return occlusion;
}

// Node `index`'s element (channels first..first+6: centre, area, normal; first = 8: its wall,
// 17: its second element).
void discGather(lint index, int first, lbool use, OUT(lvec3) c, OUT(lfloat) area, OUT(lvec3) n) {
    c = gatherDisc3(index, first, use);
    area = gatherDisc(index, first + 3, use);
    n = gatherDisc3(index, first + 4, use);
}

// Past the buffer's edge (--border tangent, as HBAO's): node (ex, ey) of `level` is the edge
// node's element (already in e, ne, area) continued along its tangent plane to the node's own
// ray, with the area of that ray's footprint: a floor or wall running out of the frame goes on
// occluding, and a plane stays a plane (its continuation lies in every receiver's tangent
// plane). A plane seen edge-on or continued past the horizon gives nothing (use is cleared).
void discContinue(lbool continued, lint ex, lint ey, int level, INOUT(lvec3) e, lvec3 ne, INOUT(lfloat) area,
                  INOUT(lbool) use) {
    float size = float(1 << level);
    lint cx = clamp(ex, lint(0), lint(discLevelWidth(level) - 1));
    lint cy = clamp(ey, lint(0), lint(discLevelHeight(level) - 1));
    lvec3 rayE = viewRay(lvec2((lfloat(cx) + 0.5f) * size + float(P.originX), (lfloat(cy) + 0.5f) * size + float(P.originY)));
    lvec3 ray = viewRay(lvec2((lfloat(ex) + 0.5f) * size + float(P.originX), (lfloat(ey) + 0.5f) * size + float(P.originY)));
    lvec3 p = rayMeetsPlane(ray, ne, e);
    lbool ok = continued;
    if (P.orthographic != 0) {
        ok = ok && abs(ne.z) > DISC_MIN_NV;
    } else {
        // Beyond 89 degrees from the ray (DISC_MIN_NV, as for footprints) the plane's
        // continuation is ill-conditioned: a far, grazing plane's rounding would lift it.
        // Only within a factor 2 of the node's depth: a coarse node's mean position is rounded
        // at its own depth, and carried much nearer the eye that offset would lift the plane
        // (the stiff suite's plane from 1e-3 to 1e6). Planar depth t = -p.z.
        ok = ok && abs(dot(ne, ray)) > DISC_MIN_NV * sqrt(dot(ray, ray)) && -p.z > -0.5f * e.z && -p.z < -2.0f * e.z;
    }
    p = select(ok, p, e); // elsewhere the node keeps its own element (and p need not be finite)
    lvec3 du;
    lvec3 dv;
    discAxes(rayE, e, ne, du, dv);
    lvec3 c0 = cross(du, dv);
    discAxes(ray, p, ne, du, dv);
    lvec3 c1 = cross(du, dv);
    lfloat ratio = sqrt(dot(c1, c1) / max(dot(c0, c0), lfloat(1e-36f)));
    area = select(ok, area * ratio, area);
    e = select(ok, p, e);
    use = use && (ok || !continued);
}
