// Screen-space directional occlusion and one indirect bounce (Ritschel, Grosch and
// Seidel, I3D 2009), one pixel.
//
// N points are placed in the normal-oriented hemisphere within r_max (cosine-
// distributed directions, so each unoccluded direction adds pi/N times its radiance
// to the irradiance). Each point is projected into the depth image: if the surface
// seen there lies in front of the point (and within r_max of the pixel), the point's
// direction is blocked; otherwise light from the environment arrives along it.
// Blocked points are where the bounce comes from: the surface seen there is a small
// area light of area A_s = pi r_max^2 / N, oriented by its own normal, radiating the
// bounce source (times its albedo); its irradiance at the pixel is
//   L_s A_s cos(theta_s) cos(theta_r) / d^2.
// Interleaved sampling: the pixels of an M x M block use disjoint subsets of one
// rotated sample set, and a geometry-aware blur of size M gathers them back.
//
// Requires: loadDepth, loadNormal (common.glsl's contract), vec3 loadRadiance(ivec2),
// vec3 loadAlbedo(ivec2), vec3 loadEnv(ivec2) on the prefiltered environment level.

// Radical inverse in base 2 (van der Corput): the second coordinate of a Hammersley set.
float radicalInverse2(uint i) {
    i = (i << 16u) | (i >> 16u);
    i = ((i & 0x55555555u) << 1u) | ((i & 0xAAAAAAAAu) >> 1u);
    i = ((i & 0x33333333u) << 2u) | ((i & 0xCCCCCCCCu) >> 2u);
    i = ((i & 0x0F0F0F0Fu) << 4u) | ((i & 0xF0F0F0F0u) >> 4u);
    i = ((i & 0x00FF00FFu) << 8u) | ((i & 0xFF00FF00u) >> 8u);
    return float(i >> 8u) * (1.0f / 16777216.0f);
}

// Orthonormal basis around a unit normal without a branch on its direction
// (Duff et al. 2017), so every normal gets a well-conditioned frame.
void tangentFrame(vec3 n, OUT(vec3) b1, OUT(vec3) b2) {
    float sgn = n.z >= 0.0f ? 1.0f : -1.0f;
    float a = -1.0f / (sgn + n.z);
    float b = n.x * n.y * a;
    b1 = vec3(1.0f + sgn * n.x * n.x * a, sgn * b, -sgn * n.x);
    b2 = vec3(b, sgn + n.y * n.y * a, -n.y);
}

// Bilinear lookup of the lat-long environment level (wraps in longitude, clamps at the poles).
vec3 environmentRadiance(vec3 dirView) {
    if (P.envWidth <= 0) {
        return vec3(P.skyRadiance) * P.envIntensity;
    }
    vec3 d = mat3(P.viewToEnv) * dirView;
    float u = 0.5f + atan(d.x, -d.z) * (1.0f / TWO_PI);
    float v = acos(clamp(d.y, -1.0f, 1.0f)) * (1.0f / PI);
    vec2 t = vec2(u * float(P.envWidth), v * float(P.envHeight)) - 0.5f;
    vec2 f = t - floor(t);
    ivec2 i0 = ivec2(floor(t));
    int x0 = ((i0.x % P.envWidth) + P.envWidth) % P.envWidth;
    int x1 = (x0 + 1) % P.envWidth;
    int y0 = clamp(i0.y, 0, P.envHeight - 1);
    int y1 = clamp(i0.y + 1, 0, P.envHeight - 1);
    vec3 top = mix(loadEnv(ivec2(x0, y0)), loadEnv(ivec2(x1, y0)), f.x);
    vec3 bottom = mix(loadEnv(ivec2(x0, y1)), loadEnv(ivec2(x1, y1)), f.x);
    return mix(top, bottom, f.y) * P.envIntensity;
}

// Display position of a view-space point; false when it cannot be seen (behind the eye).
bool projectToDisplay(vec3 p, OUT(vec2) displayPos) {
    if (P.orthographic != 0) {
        displayPos = vec2(P.cx + P.fx * p.x, P.cy - P.fy * p.y);
        return true;
    }
    if (!(p.z < 0.0f)) {
        displayPos = vec2(0.0f);
        return false;
    }
    float invDepth = 1.0f / -p.z;
    displayPos = vec2(P.cx + P.fx * p.x * invDepth, P.cy - P.fy * p.y * invDepth);
    return true;
}

// The surface seen where a view-space point projects, if it lies in front of the point,
// within r_max of the receiver and above the receiver's tangent plane: then the point is
// blocked, and `texel`/`surface` say by what. The tangent-plane condition is geometry, not
// a bias: nothing below that plane can block a direction of the hemisphere, and without it
// the pixel grid makes a flat surface shadow itself at grazing sample directions.
bool blockedBySurface(vec3 point, vec3 receiver, vec3 n, vec2 centre, OUT(ivec2) texel, OUT(vec3) surface) {
    vec2 displayPos;
    texel = ivec2(0);
    surface = vec3(0.0f);
    if (!projectToDisplay(point, displayPos)) {
        return false;
    }
    // Reads stop at maxRadiusPixels, as HBAO's do: a host that pins it gets tiles equal to the frame.
    vec2 reach = displayPos - centre;
    if (dot(reach, reach) > P.maxRadiusPixels * P.maxRadiusPixels) {
        return false;
    }
    vec2 corner = floor(displayPos);
    texel = ivec2(corner) - bufferOrigin();
    if (!insideBuffer(texel.x, texel.y)) {
        return false; // nothing is known outside the image: light passes
    }
    float d = loadDepth(texel) * P.depthScale;
    if (!isSurfaceDepth(d)) {
        return false;
    }
    surface = viewPosition(corner + 0.5f, d);
    vec3 toSurface = surface - receiver;
    float distance2 = dot(toSurface, toSurface);
    // 1e-4 of the distance: float noise in a reconstructed plane stays below it.
    bool above = dot(n, toSurface) > 1e-4f * sqrt(distance2);
    return -surface.z < -point.z && distance2 < P.radius * P.radius && above;
}

// Directional occlusion (irradiance from unblocked directions), one-bounce indirect
// irradiance, and the AO of the same samples (cosine-weighted, binary within r_max).
void ssdoPixel(ivec2 texel, OUT(vec3) directional, OUT(vec3) indirect, OUT(float) ao) {
    directional = vec3(0.0f);
    indirect = vec3(0.0f);
    ao = 1.0f;
    float depth = loadDepth(texel) * P.depthScale;
    if (!isSurfaceDepth(depth)) {
        return;
    }
    ivec2 displayPixel = texel + bufferOrigin();
    vec2 centre = vec2(displayPixel) + 0.5f;
    vec3 ray = viewRay(centre);
    vec3 receiver = viewPosition(centre, depth);
    vec3 n = viewNormal(loadNormal(texel), viewVector(ray));
    vec3 b1;
    vec3 b2;
    tangentFrame(n, b1, b2);

    // Interleaving: this pixel's subset of the sample set, and a rotation shared by its block.
    int m = max(P.interleave, 1);
    ivec2 cell = ivec2(((displayPixel.x % m) + m) % m, ((displayPixel.y % m) + m) % m);
    ivec2 block = (displayPixel - cell) / m;
    int subset = cell.x + m * cell.y;
    int stride = m * m;
    uint h = hashPixel(block.x, block.y);
    vec2 rotation = vec2(hashToUnit(h), hashToUnit(hashU32(h)));
    float distanceJitter = hashToUnit(hashU32(h + 0x68e31da4u));

    int used = 0;
    int open = 0;
    for (int i = subset; i < P.ssdoSamples; i += stride) {
        ++used;
        // Hammersley point, rotated per block (Cranley-Patterson), mapped to a cosine-weighted direction.
        float u1 = fract((float(i) + 0.5f) / float(P.ssdoSamples) + rotation.x);
        float u2 = fract(radicalInverse2(uint(i)) + rotation.y);
        float r = sqrt(u1);
        float phi = TWO_PI * u2;
        vec3 dir = (r * cos(phi)) * b1 + (r * sin(phi)) * b2 + sqrt(max(1.0f - u1, 0.0f)) * n;
        // Distance in (0, r_max]: a golden-ratio sequence, decorrelated from the direction.
        float along = fract(float(i) * 0.618033988749895f + distanceJitter);
        vec3 point = receiver + dir * (P.radius * max(along, 1e-3f));

        ivec2 senderTexel;
        vec3 sender;
        if (!blockedBySurface(point, receiver, n, centre, senderTexel, sender)) {
            ++open;
            directional += environmentRadiance(dir);
            continue;
        }
        if (P.bounce == 0) {
            continue;
        }
        // The blocking surface as a small area light (both cosines, area A_s, 1/d^2).
        vec3 toSender = sender - receiver;
        float d2 = max(dot(toSender, toSender), P.sampleArea * (1.0f / PI)); // never closer than the disc's own radius
        vec3 w = toSender * inversesqrt(d2);
        vec3 senderNormal = viewNormal(loadNormal(senderTexel), -w);
        float cosReceiver = max(dot(n, w), 0.0f);
        float cosSender = max(dot(senderNormal, -w), 0.0f);
        vec3 radiance = loadRadiance(senderTexel);
        if (P.senderAlbedo != 0) {
            radiance *= loadAlbedo(senderTexel);
        }
        indirect += radiance * (P.sampleArea * cosReceiver * cosSender / d2);
    }
    if (used == 0) {
        return;
    }
    // Cosine-weighted sampling: irradiance = pi / n * sum of radiance over open directions.
    directional *= PI / float(used);
    // Each pixel's subset stands for the whole set: its bounce sum is scaled to N samples.
    indirect *= float(P.ssdoSamples) / float(used);
    ao = float(open) / float(used);

    // Directional lights: irradiance n.l, unless a few points towards the light within r_max are blocked.
    for (int k = 0; k < P.lightCount; ++k) {
        vec3 l = vec3(P.lightDirection[k]);
        float cosL = dot(n, l);
        if (cosL <= 0.0f) {
            continue;
        }
        bool lit = true;
        for (int s = 1; s <= 4; ++s) {
            ivec2 t;
            vec3 q;
            if (blockedBySurface(receiver + l * (P.radius * float(s) * 0.25f), receiver, n, centre, t, q)) {
                lit = false;
            }
        }
        if (lit) {
            directional += vec3(P.lightIrradiance[k]) * cosL;
        }
    }
}
