// Horizon-based ambient occlusion (Bavoil, Sainz, Dimitrov 2008), one pixel.
//
// Directions are slices around the view vector V (as in GTAO), so every slice
// is a plane through the eye and its samples lie on one image line; this makes
// the solid-angle measure exact under perspective. In a slice with in-plane
// axis E (perpendicular to V), an elevation a is measured from E towards V:
//   uniform  (HBAO paper, Eq. 3):  occluded = sin h - sin t
//   cosine   (projected solid angle): occluded = |n_p| * [G(h) - G(t)],
//            G(a) = 1/2 (sin(2a - b)/2 + a cos b),  b = elevation of the projected normal n_p.
// With linear falloff each rise of the horizon is weighted by W(r) of the sample
// that raised it, as in the paper.
//
// Samples snap to texel centres, which moves them slightly off the slice. They
// are brought back into the slice along the tangent plane (not orthogonally),
// which keeps their height above the tangent plane, so a plane stays exactly
// unoccluded wherever the samples land.

// Antiderivative of the slice integrand at elevation with sine s.
// cosB, sinB: direction of the projected normal in the slice; nLen: its length.
float sliceIntegral(float s, float cosB, float sinB, float nLen) {
    s = clamp(s, -1.0f, 1.0f);
    if (P.cosineWeighting == 0) {
        return s;
    }
    float c = sqrt(max(1.0f - s * s, 0.0f));
    float sin2aMinusB = 2.0f * s * c * cosB - (1.0f - 2.0f * s * s) * sinB;
    return 0.5f * nLen * (0.5f * sin2aMinusB + asin(s) * cosB);
}

// Offsets 0..3 of the four steps processed together.
CONST_GLOBAL vec4 STEP_LANES = vec4(0.0f, 1.0f, 2.0f, 3.0f);

// Depth of the sample at buffer texel `t` if the step exists (`use`) and is inside the
// buffer; 0 (not a surface) otherwise.
float loadSampleDepth(ivec2 t, bool use) {
    return use && insideBuffer(t) ? loadDepth(t) * P.depthScale : 0.0f;
}

// One sample of the horizon search, in step order. sinA: the sample's elevation, at least
// sinT; a sample that does not count has sinA = sinT and leaves the slice unchanged.
void horizonStep(float sinA, float weight, float cosB, float sinB, float nLen,
                 INOUT(float) sinH, INOUT(float) integralH, INOUT(float) sliceOcclusion) {
    // Each rise of the horizon is weighted by W(r) of the sample that made it (the paper's
    // per-sample attenuation). The integral is monotonic above the tangent, so max() tracks it,
    // and it only changes where the horizon rises: the costly cosine integral is skipped elsewhere.
    if (P.linearFalloff != 0 && (P.cosineWeighting == 0 || sinA > sinH)) {
        float integralA = sliceIntegral(sinA, cosB, sinB, nLen);
        sliceOcclusion += weight * max(integralA - integralH, 0.0f);
        integralH = max(integralH, integralA);
    }
    sinH = max(sinH, sinA);
}

// Ambient occlusion in [0,1] (1 = unoccluded) for one buffer texel.
float hbaoPixel(ivec2 texel) {
    float depth = loadDepth(texel) * P.depthScale;
    if (!isSurfaceDepth(depth)) {
        return 1.0f;
    }
    ivec2 origin = bufferOrigin();
    ivec2 displayPixel = texel + origin;
    vec2 centre = vec2(displayPixel) + 0.5f;
    vec3 ray = viewRay(centre);
    vec3 positionVS = viewPosition(centre, depth);
    vec3 V = viewVector(ray);
    vec3 n = viewNormal(texel, V);

    // Screen-space extent of the sphere of radius R around the point: f R / sqrt(z^2 - R^2)
    // bounds every point within R, also those nearer the eye (the paper's f R / z misses them).
    float planarDepth = -positionVS.z;
    float radiusPixels = P.radius * P.fx;
    if (P.orthographic == 0) {
        radiusPixels *= inversesqrt(max(planarDepth * planarDepth - P.radius * P.radius, 1e-30f));
    }
    radiusPixels = min(radiusPixels, P.maxRadiusPixels);
    if (!(radiusPixels >= 1.0f)) {
        return 1.0f; // nothing within R is a whole pixel away
    }
    // The first sample sits one pixel out; the rest spread evenly to the radius.
    int steps = P.steps;
    float stepPixels = (radiusPixels - 1.0f) / float(steps);
    float radius2 = P.radius * P.radius;
    float invRadius = 1.0f / P.radius;

    uint h = hashPixel(displayPixel);
    float rotation = hashToUnit(h);
    float jitter = hashToUnit(hashU32(h));

    // Basis of the plane perpendicular to V; V.z > 0 for any visible point, so B1 is well defined.
    vec3 B1 = normalize(vec3(V.z, 0.0f, -V.x));
    vec3 B2 = cross(V, B1);

    float occlusion = 0.0f;
    for (int d = 0; d < P.directions; ++d) {
        float phi = (float(d) + rotation) * (TWO_PI / float(P.directions));
        vec3 E = cos(phi) * B1 + sin(phi) * B2;
        vec2 dir = screenDirection(ray, E);

        float nE = dot(n, E);
        float nV = dot(n, V);               // > 0 after viewNormal
        float nLen = max(sqrt(nE * nE + nV * nV), 1e-12f); // length of the normal projected into the slice
        float cosB = nE / nLen;
        float sinB = nV / nLen;
        float sinT = -cosB;                 // tangent elevation: perpendicular to n_p, on the E side
        // Off-slice samples (texel snapping) return to the slice along the tangent plane, which
        // keeps their height above it: in tangent coordinates a = T.X along the slice's tangent T
        // and b = (n.X) / |n_p| across it, rotated by the tangent elevation t into (xE, xV).
        // Algebraically X - A_t (A.X) / (1 - nA^2), but without that division, which amplifies
        // rounding by 1/(1 - nA^2) in slices that nearly contain the normal (grazing views).
        vec3 T = (nV * E - nE * V) / nLen;
        float cosT = sinB;

        // Horizon search. A sample that does not count (outside the buffer, sky, beyond R, behind
        // the half-plane) changes nothing, as one below the tangent (elevation clamped to sinT).
        float sinH = sinT;
        float integralT = sliceIntegral(sinT, cosB, sinB, nLen);
        float integralH = integralT;
        float sliceOcclusion = 0.0f;
        // Four steps at a time: the per-step arithmetic is written on vec4 lanes, which a CPU
        // compiles to SIMD and a GPU runs as four scalars; then the lanes update the horizon
        // in step order. Lanes past the last step never count.
        for (int s0 = 0; s0 < steps; s0 += 4) {
            vec4 offset = 1.0f + ((vec4(float(s0)) + STEP_LANES) + jitter) * stepPixels;
            // floor before the int conversion: ivec4() truncates towards zero, which would
            // fold row -1 (or any negative overscan coordinate) onto row 0.
            vec4 cornerX = floor(centre.x + dir.x * offset);
            vec4 cornerY = floor(centre.y + dir.y * offset);
            ivec4 texelX = ivec4(cornerX) - origin.x;
            ivec4 texelY = ivec4(cornerY) - origin.y;
            if (!insideBuffer(ivec2(texelX.x, texelY.x))) {
                break; // the image line has left the buffer for good
            }
            // Once a step leaves the buffer every later one is outside too (the line is straight
            // and the buffer convex), so masking the steps outside is the per-step `break`,
            // and when the last of the four is inside, all are.
            vec4 sampleDepth;
            if (s0 + 3 < steps && insideBuffer(ivec2(texelX.w, texelY.w))) {
                sampleDepth = vec4(loadDepth(ivec2(texelX.x, texelY.x)), loadDepth(ivec2(texelX.y, texelY.y)),
                                   loadDepth(ivec2(texelX.z, texelY.z)), loadDepth(ivec2(texelX.w, texelY.w))) *
                              P.depthScale;
            } else {
                sampleDepth = vec4(loadSampleDepth(ivec2(texelX.x, texelY.x), true),
                                   loadSampleDepth(ivec2(texelX.y, texelY.y), s0 + 1 < steps),
                                   loadSampleDepth(ivec2(texelX.z, texelY.z), s0 + 2 < steps),
                                   loadSampleDepth(ivec2(texelX.w, texelY.w), s0 + 3 < steps));
            }
            // isSurfaceDepth per lane (depths below the smallest surface depth, NaN included, are
            // moved to the sky first); holes and sky take the centre depth, which keeps X finite.
            sampleDepth = mix(vec4(P.skyDepth), sampleDepth, greaterThanEqual(sampleDepth, vec4(MIN_SURFACE_DEPTH)));
            bvec4 surface = lessThan(sampleDepth, vec4(P.skyDepth));
            sampleDepth = mix(vec4(depth), sampleDepth, surface);
            vec4 Xx;
            vec4 Xy;
            vec4 Xz;
            viewOffset4(ray, depth, (cornerX + 0.5f) - centre.x, (cornerY + 0.5f) - centre.y, sampleDepth, Xx, Xy, Xz);
            vec4 r2 = Xx * Xx + Xy * Xy + Xz * Xz;
            vec4 a = T.x * Xx + T.y * Xy + T.z * Xz;
            vec4 b = (n.x * Xx + n.y * Xy + n.z * Xz) / nLen;
            vec4 xE = cosT * a - sinT * b;
            vec4 xV = sinT * a + cosT * b;
            // A sample counts if it is a surface within R in front of the half-plane (xE <= 0 only
            // happens when snapping pushed it into the opposite half-slice); otherwise, and below
            // the tangent, its elevation is the tangent's.
            vec4 sinA = max(xV * inversesqrt(xE * xE + xV * xV), sinT);
            sinA = mix(vec4(sinT), sinA, surface);
            sinA = mix(vec4(sinT), sinA, lessThanEqual(r2, vec4(radius2)));
            sinA = mix(vec4(sinT), sinA, greaterThan(xE, vec4(0.0f)));
            // W(r) = 1 - r/R, linear falloff only
            vec4 weight = P.linearFalloff != 0 ? max(1.0f - sqrt(r2) * invRadius, 0.0f) : vec4(0.0f);
            horizonStep(sinA.x, weight.x, cosB, sinB, nLen, sinH, integralH, sliceOcclusion);
            horizonStep(sinA.y, weight.y, cosB, sinB, nLen, sinH, integralH, sliceOcclusion);
            horizonStep(sinA.z, weight.z, cosB, sinB, nLen, sinH, integralH, sliceOcclusion);
            horizonStep(sinA.w, weight.w, cosB, sinB, nLen, sinH, integralH, sliceOcclusion);
        }
        if (P.linearFalloff == 0) {
            sliceOcclusion = sliceIntegral(sinH, cosB, sinB, nLen) - integralT;
        }
        occlusion += sliceOcclusion;
    }
    // Uniform: (1/2pi) * (2pi/N_d) * sum. Cosine: (1/pi) * (2pi/N_d) * sum.
    float norm = (P.cosineWeighting != 0 ? 2.0f : 1.0f) / float(P.directions);
    return clamp(1.0f - occlusion * norm, 0.0f, 1.0f);
}
