// HBAO (kernels/hbao.glsl): the receiver, a slice's axes, F's closed forms, what a slice has
// found so far, and the march along its image line. Every model shares these.

// The pixel whose AO is computed.
struct HbaoReceiver {
    lbool computing;      // a surface whose R spans a whole pixel; the other lanes return 1
    lfloat depth;
    lfloat planarDepth;   // -z
    lfloat radiusPixels;  // R on the screen, at most P.maxRadiusPixels
    lvec2 centre;         // display coordinates of the pixel's centre
    lvec3 ray;            // viewRay(centre)
    lvec2 cornerToOffset; // a sample texel's pixel offset is its corner + this (exact in float)
    lvec3 V;              // towards the eye
    lvec3 n;              // the view-space normal, facing the eye
    lfloat stepPixels;    // the march's step; the first sample sits one pixel out
    lfloat footprint;     // world width one step stands for at the pixel's depth (runs' widths)
    lfloat rotation;      // the slices' turn, in slices
    lfloat jitter;        // the first step's, in steps
    bool discInside;      // every lane's samples lie inside the buffer: no bounds test
    float radius2;        // R^2
    float invRadius;      // 1 / R
};

// Where a helper returns early shapes llvmpipe's code, and with it the last bit of some results
// (tests/bench/same_outputs.py finds them): the helpers return at their end, but where the
// kernel returned early before it was split into them.

// The receiver's frame at buffer texels (x, y), surfaces: its ray, view vector and normal, and R
// on the screen; lanes where R spans no whole pixel stop computing.
void receiverFrame(lint x, lint y, INOUT(HbaoReceiver) r) {
    lint displayX = x + P.originX;
    lint displayY = y + P.originY;
    r.centre = lvec2(lfloat(displayX) + 0.5f, lfloat(displayY) + 0.5f);
    r.ray = viewRay(r.centre);
    r.cornerToOffset = lvec2(0.5f - r.centre.x, 0.5f - r.centre.y);
    r.V = viewVector(r.ray);
    r.n = viewNormal(gatherNormal(x, y, r.computing), r.V);

    // Screen-space extent of the sphere of radius R around the point: f R / sqrt(z^2 - R^2)
    // bounds every point within R, also those nearer the eye (the paper's f R / z misses them).
    // f is the larger focal length: with non-square pixels (fy = pixel aspect x fx) the sphere's
    // image is an ellipse, and the march must reach its long axis; samples past R count nothing.
    r.planarDepth = -positionOnRay(r.ray, r.depth).z;
    r.radiusPixels = lfloat(P.radius * max(P.fx, P.fy));
    if (P.orthographic == 0) {
        r.radiusPixels *= inversesqrt(max(r.planarDepth * r.planarDepth - P.radius * P.radius, 1e-30f));
    }
    r.radiusPixels = min(r.radiusPixels, P.maxRadiusPixels);
    r.computing = r.computing && r.radiusPixels >= 1.0f; // else nothing within R is a whole pixel away
}

// The receiver's march: its step, whether every sample lies in the buffer, and its noise.
void receiverSteps(lint x, lint y, INOUT(HbaoReceiver) r) {
    r.stepPixels = (r.radiusPixels - 1.0f) * (1.0f / float(P.steps));
    // Every sample lies within radiusPixels of the centre: when that square (with a texel to
    // spare for rounding) is inside the depth buffer for every lane, no step needs a bounds test.
    vec2 origin = vec2(bufferOrigin());
    lvec2 reach = lvec2(r.radiusPixels, r.radiusPixels);
    r.discInside = !anyLane(r.computing && !(insideBuffer(floor(r.centre - reach) - origin, 1.0f) &&
                                             insideBuffer(floor(r.centre + reach) - origin, 1.0f)));
    r.radius2 = P.radius * P.radius;
    r.footprint = max(r.stepPixels, lfloat(1.0f)) * P.invFx * (P.orthographic != 0 ? lfloat(1.0f) : r.planarDepth);
    r.invRadius = 1.0f / P.radius;
    luint h = hashPixel(x + P.originX, y + P.originY);
    r.rotation = hashToUnit(h);
    r.jitter = hashToUnit(hashU32(h));
}

// The slices' azimuths: slice d lies at angle (d + rotation) 2 pi / N_d around V, one sine and
// cosine per pixel, then each next slice by a fixed rotation.
struct HbaoAzimuth {
    lvec3 B1, B2;           // a basis of the plane perpendicular to V
    lfloat cosPhi, sinPhi;  // the next slice's angle
    float cosStep, sinStep; // from one slice to the next
};

HbaoAzimuth firstAzimuth(IN(HbaoReceiver) r) {
    HbaoAzimuth az;
    // V.z > 0 for any visible point, so B1 is well defined.
    az.B1 = normalize(lvec3(r.V.z, 0.0f, -r.V.x));
    az.B2 = cross(r.V, az.B1);
    float sliceAngle = TWO_PI / float(P.directions);
    az.cosStep = cos(sliceAngle);
    az.sinStep = sin(sliceAngle);
    az.cosPhi = cos(r.rotation * sliceAngle);
    az.sinPhi = sin(r.rotation * sliceAngle);
    return az;
}

// The receiver's normal projected into a slice: n_p = |n_p| (cos b, sin b) in its (E, V) axes.
// What F and the runs' backs need of a slice (passed on its own to a call kept out of line).
struct ProjectedNormal {
    lfloat nE, nV;        // the normal's components along E and V (nV > 0)
    lfloat nLen, invNLen; // |n_p| and its inverse
    lfloat cosB, sinB;
};

// A slice: the plane through the eye that holds V and the direction E. A sample in it is taken
// in the coordinates of the receiver's tangent plane: a along the tangent, b above it.
struct HbaoSlice {
    lvec2 dir;            // the image direction of E (display pixels, unit length)
    lvec3 T;              // the tangent's axis: elevation t (sin t = -cos b), on the E side
    lvec3 n;              // the normal's axis (the receiver's normal)
    ProjectedNormal np;
    lfloat backShiftA;    // pushing a point the thickness T along -V (as the bitmask paper does)
    lfloat backShiftB;    // moves (a, b) by (backShiftA, backShiftB)
    lfloat runJump;       // P.runJump in the slice's axes
};

// The next slice of `az`, which then turns to the one after.
HbaoSlice nextSlice(IN(HbaoReceiver) r, INOUT(HbaoAzimuth) az) {
    HbaoSlice sl;
    lvec3 E = az.cosPhi * az.B1 + az.sinPhi * az.B2;
    lfloat nextCos = az.cosPhi * az.cosStep - az.sinPhi * az.sinStep;
    az.sinPhi = az.sinPhi * az.cosStep + az.cosPhi * az.sinStep;
    az.cosPhi = nextCos;
    sl.dir = screenDirection(r.ray, E);
    sl.n = r.n;
    sl.np.nE = dot(r.n, E);
    sl.np.nV = dot(r.n, r.V); // > 0 after viewNormal
    sl.np.invNLen = inversesqrt(max(sl.np.nE * sl.np.nE + sl.np.nV * sl.np.nV, 1e-24f));
    sl.np.nLen = (sl.np.nE * sl.np.nE + sl.np.nV * sl.np.nV) * sl.np.invNLen;
    sl.np.cosB = sl.np.nE * sl.np.invNLen;
    sl.np.sinB = sl.np.nV * sl.np.invNLen;
    // T and n are both |n_p| times unit length: every use of (a, b) is an angle or a sign, which
    // a common positive scale leaves alone. A sample is on the E side when its E coordinate,
    // a cos t - b sin t ~ a nV + b nE, is positive.
    sl.T = sl.np.nV * E - sl.np.nE * r.V;
    sl.backShiftA = P.thickness * sl.np.nE;
    sl.backShiftB = -P.thickness * sl.np.nV;
    // A depth change along V, scaled by |n_p|^2 like a and b.
    sl.runJump = P.runJump * sl.np.nLen * sl.np.nLen;
    return sl;
}

// F, the occlusion per unit of slice of everything from the tangent up to the angle theta,
// for a unit (cos theta, sin theta) above the tangent:
//   uniform (the paper's Eq. 3, sin h - sin t):             F = cos b (1 - cos theta) + sin b sin theta
//   cosine (projected solid angle; integral of cos to n):   F = |n_p| / 2 (sin b sin^2 theta
//                                                               + cos b (theta - sin theta cos theta))
// Both grow with theta, so the highest sample is the horizon.
lfloat sliceOcclusionAt(lfloat cosTheta, lfloat sinTheta, IN(ProjectedNormal) np) {
    if (P.cosineWeighting == 0) {
        return np.cosB * (1.0f - cosTheta) + np.sinB * sinTheta;
    }
    lfloat theta = atan(sinTheta, cosTheta);
    return 0.5f * np.nLen * (np.sinB * sinTheta * sinTheta + np.cosB * (theta - sinTheta * cosTheta));
}

// F of a sample at (a, b) in the slice's axes, 0 outside `counts`.
lfloat sampleF(lfloat a, lfloat b, lbool counts, IN(ProjectedNormal) np) {
    lfloat invLen = inversesqrt(max(a * a + b * b, 1e-30f));
    return select(counts, sliceOcclusionAt(a * invLen, b * invLen, np), lfloat(0.0f));
}

// Linear falloff's weight 1 - r/R of a point at distance r (r^2 = r2), 0 beyond R.
lfloat falloffWeight(lfloat r2, float invRadius) {
    return max(1.0f - sqrt(r2) * invRadius, 0.0f);
}

// What a slice has found so far. Its occluded set is a union of intervals of angle: the one that
// reaches down to the tangent ends at the horizon; the others set sectors of a bitmask above it.
struct HbaoOccluded {
    lfloat horizonA, horizonB; // the horizon's direction in the slice's axes; (1, 0): the tangent
    lfloat horizonF;           // linear falloff: F at the horizon
    lfloat occlusion;          // linear falloff: the weighted rises of F so far
    luint sectors;             // occluded sectors above the horizon's interval (hbao_bitmask.glsl)
};

HbaoOccluded nothingOccluded() {
    HbaoOccluded o;
    o.horizonA = lfloat(1.0f); // the tangent
    o.horizonB = o.horizonF = o.occlusion = lfloat(0.0f);
    o.sectors = luint(0u);
    return o;
}

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

// One sample of the march, in the slice's axes. Samples snap to texel centres, which moves them
// slightly off the slice; taking a and b from the full 3D offset brings them back into it along
// the tangent plane, keeping their height above it, so a plane stays exactly unoccluded.
struct HbaoSample {
    lvec2 corner;  // display corner of its texel
    lvec2 w;       // its image offset from the receiver (viewOffset's w)
    lfloat depth;  // its depth; the receiver's where it is no surface (keeps X finite)
    lvec3 X;       // its surface point's offset from the receiver
    lfloat r2;     // |X|^2
    lfloat a, b;   // X along the tangent and above it
    lbool sampled; // its texel is in the buffer (deep layers may lie behind sky)
    lbool surface; // ... and holds a surface (deep spans clip to R themselves)
    lbool above;   // ... above the tangent by more than rounding (0.57 degrees): runs
    lbool counts;  // ... within R, above the tangent and on the E side: can occlude
};

// The march along the slice's image line, in display coordinates (so any tiling rounds alike).
struct HbaoMarch {
    lvec2 start;        // the first sample's position
    lvec2 position;     // the next sample's
    lvec2 step;
    bool interior;      // every lane's samples are inside the buffer: no bounds test
    lfloat stepsInside; // off the interior: steps each lane took inside the buffer (they come first)
    lbool aheadUse;     // the next step's texel is read, and
    lfloat aheadDepth;  // its depth, loaded one step ahead
};

// The depth a march step at display corner `corner` reads, and in `use` the lanes that read it:
// every lane computing on an interior slice, else those whose texel is in the buffer.
lfloat loadStep(lvec2 corner, lbool computing, bool interior, OUT(lbool) use) {
    use = computing;
    if (!interior) {
        use = use && insideBuffer(corner - vec2(bufferOrigin()), 0.0f);
    }
    return gatherDepthAtDisplay(corner, use);
}

HbaoMarch startMarch(IN(HbaoReceiver) r, IN(HbaoSlice) sl) {
    HbaoMarch m;
    vec2 origin = vec2(bufferOrigin());
    m.step = sl.dir * r.stepPixels;
    m.position = r.centre + sl.dir * (1.0f + r.jitter * r.stepPixels);
    m.start = m.position;
    m.stepsInside = lfloat(0.0f);
    // Each coordinate moves monotonically, so when the first and the last sample of every lane
    // are inside the depth buffer (the last with a texel to spare for rounding), all are.
    m.interior = r.discInside;
    if (!m.interior) {
        lvec2 last = m.position + m.step * float(P.steps - 1);
        m.interior = !anyLane(r.computing && !(insideBuffer(floor(m.position) - origin, 0.0f) &&
                                                insideBuffer(floor(last) - origin, 1.0f)));
    }
    // Each step's depth is loaded one step ahead, so the load's latency overlaps the work on the
    // sample before (the step's work is too long for the CPU to reach it alone).
    m.aheadDepth = loadStep(floor(m.position), r.computing, m.interior, m.aheadUse);
    return m;
}

// Step s of the march: its texel's display corner and depth (loaded the step before), and the
// lanes whose texel is in the buffer.
lbool advanceMarch(IN(HbaoReceiver) r, int s, INOUT(HbaoMarch) m, OUT(lvec2) corner, OUT(lfloat) loaded) {
    corner = floor(m.position);
    m.position = m.position + m.step;
    lbool counts = m.aheadUse;
    loaded = m.aheadDepth;
    if (s + 1 < P.steps) {
        m.aheadDepth = loadStep(floor(m.position), r.computing, m.interior, m.aheadUse);
    }
    return counts;
}

// The sample at smp.corner, whose texel is in the buffer in lanes `counts`, its depth `loaded`.
void sampleAt(IN(HbaoReceiver) r, IN(HbaoSlice) sl, lfloat loaded, lbool counts, INOUT(HbaoSample) smp) {
    smp.sampled = counts;
    smp.depth = loaded * P.depthScale;
    counts = counts && isSurfaceDepth(smp.depth);
    smp.depth = select(counts, smp.depth, r.depth);
    // Scaled after the exact subtraction: scaling first would cancel digits.
    smp.w = imageOffset(smp.corner + r.cornerToOffset);
    smp.X = viewOffset(r.ray, r.depth, smp.w, smp.depth);
    smp.r2 = dot(smp.X, smp.X);
    smp.a = dot(sl.T, smp.X);
    smp.b = dot(sl.n, smp.X);
    smp.surface = counts;
    // Runs take samples above the tangent by more than rounding: the receiver's own plane,
    // stored at half precision too, starts none.
    smp.above = counts && smp.b > 0.0f && smp.b * smp.b > 1e-4f * smp.r2;
    // Below the tangent plane a sample cannot raise the horizon; snapping can push one across V.
    // Then theta is in (0, pi - b): F grows with theta, and two angles there compare exactly by
    // the sign of their cross product.
    smp.counts = counts && smp.r2 <= r.radius2 && smp.b > 0.0f && smp.a * sl.np.nV + smp.b * sl.np.nE > 0.0f;
}
