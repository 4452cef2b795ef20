// Geometry-aware (cross-bilateral) blur of AO, DO or GI, one pass along `axis`.
// Weights: Gaussian in pixels x depth similarity x normal similarity, so
// occlusion never bleeds across silhouettes or creases. Sky keeps its value.
// Requires: float loadDepth(ivec2), vec3 loadNormal(ivec2), vec4 loadSignal(ivec2), params P.

CONST_GLOBAL float BLUR_DEPTH_TOLERANCE = 0.02f; // relative depth step treated as an edge (2% of depth)
CONST_GLOBAL float BLUR_NORMAL_POWER = 16.0f;    // cos^16: ~0.5 weight at 17 degrees between normals

vec3 blurNormal(ivec2 texel) {
    vec3 n = loadNormal(texel);
    float len2 = dot(n, n);
    return (len2 > 1e-12f && len2 < 1e30f) ? n * inversesqrt(len2) : vec3(0.0f);
}

// Up to four channels at once (AO in .x; DO or GI in .xyz).
vec4 blurPixel4(ivec2 texel, ivec2 axis, int radius) {
    vec4 centre = loadSignal(texel);
    float d0 = loadDepth(texel) * P.depthScale;
    if (!isSurfaceDepth(d0) || radius <= 0) {
        return centre;
    }
    vec3 n0 = blurNormal(texel);
    float sigma = 0.5f * float(radius) + 0.5f;
    float invTwoSigma2 = 1.0f / (2.0f * sigma * sigma);
    float invTolerance = 1.0f / (BLUR_DEPTH_TOLERANCE * d0);
    vec4 sum = centre;
    float weightSum = 1.0f;
    for (int i = -radius; i <= radius; ++i) {
        ivec2 t = texel + axis * i;
        if (i == 0 || !insideBuffer(t.x, t.y)) {
            continue;
        }
        float d = loadDepth(t) * P.depthScale;
        if (!isSurfaceDepth(d)) {
            continue;
        }
        float dz = (d - d0) * invTolerance;
        float wn = pow(max(dot(blurNormal(t), n0), 0.0f), BLUR_NORMAL_POWER);
        float w = exp(-float(i * i) * invTwoSigma2 - dz * dz) * wn;
        sum += w * loadSignal(t);
        weightSum += w;
    }
    return sum / weightSum;
}

float blurPixel(ivec2 texel, ivec2 axis, int radius) {
    return blurPixel4(texel, axis, radius).x;
}
