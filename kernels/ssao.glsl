// Screen-space ambient occlusion as Crytek shipped it (Mittring 2007), written on lane types
// like kernels/hbao.glsl: the cheap baseline the other methods are measured against.
//
// N points are placed within R of the pixel: in the whole sphere (the original), or in the
// normal-oriented hemisphere (P.ssaoHemisphere), cosine-distributed for the cosine
// weighting. Each point is projected into the depth buffer; it is occluded when the surface
// seen there lies in front of it and within R of the pixel (the range check, which keeps a
// distant foreground object from darkening what it hides). AO is the unoccluded fraction; in
// the sphere, where a flat wall hides the points below its tangent plane, the unoccluded weight
// over the weight of the points above it (Crytek's twice the fraction where the halves weigh
// alike; with linear falloff's weights, or an odd N, they do not), clamped to 1. Where R spans
// no whole pixel, AO is 1, as HBAO's: every point meets the pixel's own texel, whose depth cannot
// tell its side.
//
// In the hemisphere, "in front" is judged by height above the pixel's tangent plane rather
// than by depth along the ray: for nearby points the two agree (the eye is above the plane),
// and the tangent-plane form survives snapping to texel centres, so a plane stays AO = 1.

// Golden angle: successive points turn by it, so any prefix of the set covers the azimuths.
CONST_GLOBAL float GOLDEN_ANGLE = 2.39996322972865f;

// The pixel every point of the set is measured from.
struct SsaoReceiver {
    lbool computing;       // the lane holds a surface
    lfloat depth;          // its depth
    lvec3 ray;             // the view ray through the pixel's centre
    lvec2 centre;          // the pixel's centre in display pixels
    lvec2 cornerToOffset;  // from a texel's corner to the offset imageOffset() takes
    lvec3 n;               // its normal, in view space, facing the eye
    lvec3 position;        // its position in view space
};

// Stratified elevation (t in [0, 1), so the hemisphere's z = 1 - t, or its sqrt, is > 0) of
// point i, around the normal in the hemisphere or around the frame's z in the sphere.
lfloat ssaoElevation(int i, lfloat jitter, float invN) {
    lfloat t = (float(i) + jitter) * invN;
    if (P.ssaoHemisphere == 0) {
        return 1.0f - 2.0f * t;
    }
    return P.cosineWeighting != 0 ? sqrt(1.0f - t) : 1.0f - t;
}

// Whether the surface seen where point D (an offset from the receiver) projects lies in front
// of it and within R of the receiver: Crytek's test, with its range check.
lbool ssaoOccludes(IN(SsaoReceiver) rc, lvec3 D, vec2 origin, float radius2, float maxReach2) {
    lvec3 q = rc.position + D;
    lbool counts = rc.computing;
    lfloat invW = lfloat(1.0f);
    if (P.orthographic == 0) {
        counts = counts && q.z < 0.0f;
        invW = 1.0f / max(-q.z, 1e-30f);
    }
    lvec2 displayPos = lvec2(P.cx + P.fx * q.x * invW, P.cy - P.fy * q.y * invW);
    // Reads stop at maxRadiusPixels, as HBAO's do, so tiles pinned to it equal the frame.
    lvec2 reach = displayPos - rc.centre;
    counts = counts && dot(reach, reach) <= maxReach2;
    lvec2 corner = floor(lvec2(select(counts, displayPos.x, rc.centre.x), select(counts, displayPos.y, rc.centre.y)));
    counts = counts && insideBuffer(corner - origin, 0.0f);
    lfloat sampleDepth = gatherDepthAtDisplay(corner, counts) * P.depthScale;
    counts = counts && isSurfaceDepth(sampleDepth);
    sampleDepth = select(counts, sampleDepth, rc.depth);
    lvec2 w = imageOffset(corner + rc.cornerToOffset);
    lvec3 X = viewOffset(rc.ray, rc.depth, w, sampleDepth);
    lfloat r2 = dot(X, X);
    lbool inFront;
    if (P.ssaoHemisphere != 0) {
        inFront = dot(rc.n, X) > dot(rc.n, D);
    } else {
        inFront = X.z > D.z;
    }
    return counts && inFront && r2 <= radius2;
}

lfloat ssaoLanes(lint x, lint y) {
    SsaoReceiver rc;
    rc.depth = surfaceDepth(x, y, rc.computing);
    if (!anyLane(rc.computing)) {
        return lfloat(1.0f);
    }
    lint displayX = x + P.originX;
    lint displayY = y + P.originY;
    rc.centre = lvec2(lfloat(displayX) + 0.5f, lfloat(displayY) + 0.5f);
    rc.ray = viewRay(rc.centre);
    rc.cornerToOffset = lvec2(0.5f - rc.centre.x, 0.5f - rc.centre.y);
    rc.n = viewNormal(gatherNormal(x, y, rc.computing), viewVector(rc.ray));
    rc.position = positionOnRay(rc.ray, rc.depth);
    lfloat radiusPixels = lfloat(P.radius * max(P.fx, P.fy));
    if (P.orthographic == 0) {
        radiusPixels *= 1.0f / max(-rc.position.z, 1e-30f);
    }
    rc.computing = rc.computing && radiusPixels >= 1.0f;
    if (!anyLane(rc.computing)) {
        return lfloat(1.0f);
    }
    vec2 origin = vec2(bufferOrigin());

    lvec3 b1;
    lvec3 b2;
    tangentFrame(rc.n, b1, b2);

    luint h = hashPixel(displayX, displayY);
    lfloat jitter = hashToUnit(h);
    lfloat jitter2 = hashToUnit(hashU32(h));
    lfloat cosA = cos(TWO_PI * jitter2);
    lfloat sinA = sin(TWO_PI * jitter2);
    float cosStep = cos(GOLDEN_ANGLE);
    float sinStep = sin(GOLDEN_ANGLE);
    float invN = 1.0f / float(P.ssaoSamples);
    float radius2 = P.radius * P.radius;
    float invRadius = 1.0f / P.radius;
    float maxReach2 = P.maxRadiusPixels * P.maxRadiusPixels;

    lfloat occlusion = lfloat(0.0f);
    lfloat weights = lfloat(0.0f);
    lfloat weightsAbove = lfloat(0.0f);  // the sphere: of the points above the tangent plane,
    lfloat weightsOpen = lfloat(0.0f);   // ... and of the open ones (summed alike: a plane gives 1 exactly)
    for (int i = 0; i < P.ssaoSamples; ++i) {
        lfloat z = ssaoElevation(i, jitter, invN);
        lfloat s = sqrt(max(1.0f - z * z, 0.0f));
        // Distances cluster towards the pixel, where occluders matter most (Crytek's choice).
        lfloat u = fract(float(i) * 0.754877666f + jitter2);
        lfloat dist = P.radius * (0.1f + 0.9f * u * u);
        lvec3 D = ((cosA * s) * b1 + (sinA * s) * b2 + z * rc.n) * dist;
        // Linear falloff weights each point by W(r) = 1 - r/R of its own distance, in the sum
        // and in the normalisation, so a flat wall still hides exactly its share of the sphere.
        lfloat weight = lfloat(1.0f);
        if (P.linearFalloff != 0) {
            weight = 1.0f - dist * invRadius;
        }
        lfloat nextCos = cosA * cosStep - sinA * sinStep;
        sinA = sinA * cosStep + cosA * sinStep;
        cosA = nextCos;

        lbool occluded = ssaoOccludes(rc, D, origin, radius2, maxReach2);
        occlusion += select(occluded, weight, 0.0f);
        weights += weight;
        weightsAbove += select(z > 0.0f, weight, 0.0f);
        weightsOpen += select(occluded, 0.0f, weight);
    }
    lfloat open = 1.0f - occlusion / weights;
    if (P.ssaoHemisphere == 0) {
        // No point above the tangent plane (N = 1, say): nothing to judge by.
        open = select(weightsAbove > 0.0f, weightsOpen / max(weightsAbove, 1e-30f), lfloat(1.0f));
    }
    return select(rc.computing, clamp(open, 0.0f, 1.0f), 1.0f);
}
