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

// Ambient occlusion in [0,1] (1 = unoccluded) for one buffer texel.
float hbaoPixel(ivec2 texel) {
    float depth = loadDepth(texel) * P.depthScale;
    if (!isSurfaceDepth(depth)) {
        return 1.0f;
    }
    ivec2 displayPixel = texel + bufferOrigin();
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
        vec3 A = cross(E, V); // slice-plane normal
        vec2 dir = screenDirection(ray, E);

        float nA = dot(n, A);
        float nE = dot(n, E);
        float nV = dot(n, V);               // >= 0.01 after viewNormal
        float nLen = sqrt(nE * nE + nV * nV); // length of the normal projected into the slice
        float cosB = nE / nLen;
        float sinB = nV / nLen;
        float sinT = -cosB;                 // tangent elevation: perpendicular to n_p, on the E side
        // Off-slice samples return to the slice along the tangent plane: X' = X - A_t (A.X) / (1 - nA^2).
        // Folded into the axes, so each sample costs two dot products: xE = E'.X, xV = V'.X.
        float inv = nA / max(1.0f - nA * nA, 1e-6f);
        vec3 sliceE = E + (nE * inv) * A;
        vec3 sliceV = V + (nV * inv) * A;

        // Branch-free horizon search: a sample that does not count (sky, beyond R, behind the
        // half-plane, below the tangent) gets the tangent elevation and cannot raise the horizon.
        float sinH = sinT;
        float integralT = sliceIntegral(sinT, cosB, sinB, nLen);
        float integralH = integralT;
        float sliceOcclusion = 0.0f;
        for (int s = 0; s < steps; ++s) {
            float offset = 1.0f + (float(s) + jitter) * stepPixels;
            vec2 samplePos = floor(centre + dir * offset) + 0.5f;
            ivec2 sampleTexel = ivec2(samplePos) - bufferOrigin();
            if (!insideBuffer(sampleTexel)) {
                break; // the image line has left the buffer for good
            }
            float sampleDepth = loadDepth(sampleTexel) * P.depthScale;
            bool surface = isSurfaceDepth(sampleDepth);
            vec3 X = viewOffset(ray, depth, samplePos - centre, surface ? sampleDepth : depth);
            float r2 = dot(X, X);
            float xE = dot(sliceE, X);
            float xV = dot(sliceV, X);
            // xE <= 0 only happens when snapping pushed the sample into the opposite half-slice.
            bool counts = surface && r2 <= radius2 && xE > 0.0f;
            float sinA = counts ? max(xV * inversesqrt(xE * xE + xV * xV), sinT) : sinT;
            if (P.linearFalloff != 0) {
                // Each rise of the horizon is weighted by W(r) of the sample that made it (the paper's
                // per-sample attenuation). The integral is monotonic above the tangent, so max() tracks it.
                float integralA = sliceIntegral(sinA, cosB, sinB, nLen);
                float w = max(1.0f - sqrt(r2) * invRadius, 0.0f);
                sliceOcclusion += w * max(integralA - integralH, 0.0f);
                integralH = max(integralH, integralA);
            }
            sinH = max(sinH, sinA);
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
