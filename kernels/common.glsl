// Shared per-pixel helpers: hashing, camera reconstruction, pass validation.
// Requires the backend to provide: float loadDepth(ivec2 texel); vec3 loadNormal(ivec2 texel);
// and a parameter block `P` with the KernelParams members used here.

CONST_GLOBAL float PI = 3.14159265358979f;
CONST_GLOBAL float TWO_PI = 6.28318530717959f;

// Integer finaliser (a well-mixed 32-bit hash); the same bits on CPU and GPU.
uint hashU32(uint x) {
    x ^= x >> 16u;
    x *= 0x7feb352du;
    x ^= x >> 15u;
    x *= 0x846ca68bu;
    x ^= x >> 16u;
    return x;
}

uint hashPixel(ivec2 displayPixel) {
    return hashU32(uint(displayPixel.x) ^ hashU32(uint(displayPixel.y) + 0x9e3779b9u));
}

// Top 24 bits -> [0, 1): exactly representable, so both backends agree bit for bit.
float hashToUnit(uint h) {
    return float(h >> 8u) * (1.0f / 16777216.0f);
}

// Smallest normal float: denormal depths carry no usable precision and are treated as holes.
CONST_GLOBAL float MIN_SURFACE_DEPTH = 1.17549435e-38f;

// A depth that describes a surface: finite, positive, nearer than the sky. NaN fails every comparison.
bool isSurfaceDepth(float depth) {
    return depth >= MIN_SURFACE_DEPTH && depth < P.skyDepth;
}

ivec2 bufferOrigin() {
    return ivec2(P.originX, P.originY);
}

bool insideBuffer(ivec2 texel) {
    return texel.x >= 0 && texel.y >= 0 && texel.x < P.width && texel.y < P.height;
}

// Direction through a display position, scaled so z = -1 (perspective); for an
// orthographic camera, the position on the image plane with z = 0.
vec3 viewRay(vec2 displayPos) {
    return vec3((displayPos.x - P.cx) * P.invFx, (P.cy - displayPos.y) * P.invFy, P.orthographic != 0 ? 0.0f : -1.0f);
}

// View-space position (OpenGL camera: looking down -Z) of a display position at a given depth.
vec3 viewPosition(vec2 displayPos, float depth) {
    vec3 ray = viewRay(displayPos);
    if (P.orthographic != 0) {
        return vec3(ray.x, ray.y, -depth);
    }
    if (P.radialDepth != 0) {
        return ray * (depth * inversesqrt(dot(ray, ray)));
    }
    return ray * depth;
}

// S - P for a sample `pixelOffset` pixels away from P, without forming S and P: at
// large depth both are big and nearly equal, and their difference would cancel
// most significant digits. With rayS = rayP + w (w from the pixel offset alone):
// S - P = (dS - dP) rayP + dS w, every term small where the answer is small.
vec3 viewOffset(vec3 rayP, float depthP, vec2 pixelOffset, float depthS) {
    vec2 w = vec2(pixelOffset.x * P.invFx, -pixelOffset.y * P.invFy);
    if (P.orthographic != 0) {
        return vec3(w, depthP - depthS);
    }
    if (P.radialDepth != 0) {
        vec3 rayS = rayP + vec3(w, 0.0f);
        return rayS * (depthS * inversesqrt(dot(rayS, rayS))) - rayP * (depthP * inversesqrt(dot(rayP, rayP)));
    }
    return (depthS - depthP) * rayP + depthS * vec3(w, 0.0f);
}

// viewOffset for four samples at once, as components: (x, y, z)[i] = S_i - P for the
// sample at pixelOffset (offsetX[i], offsetY[i]) with depth depthS[i]. Same arithmetic.
void viewOffset4(vec3 rayP, float depthP, vec4 offsetX, vec4 offsetY, vec4 depthS,
                 OUT(vec4) x, OUT(vec4) y, OUT(vec4) z) {
    vec4 wx = offsetX * P.invFx;
    vec4 wy = -offsetY * P.invFy;
    if (P.orthographic != 0) {
        x = wx;
        y = wy;
        z = depthP - depthS;
        return;
    }
    if (P.radialDepth != 0) {
        vec4 rayX = rayP.x + wx;
        vec4 rayY = rayP.y + wy;
        vec4 scaleS = depthS * inversesqrt(rayX * rayX + rayY * rayY + rayP.z * rayP.z);
        vec3 p = rayP * (depthP * inversesqrt(dot(rayP, rayP)));
        x = rayX * scaleS - p.x;
        y = rayY * scaleS - p.y;
        z = rayP.z * scaleS - p.z;
        return;
    }
    vec4 dd = depthS - depthP;
    x = dd * rayP.x + depthS * wx;
    y = dd * rayP.y + depthS * wy;
    z = dd * rayP.z;
}

// Unit vector towards the eye. Taken from the pixel's ray, not its position, so
// it stays exact at any depth (tiny depths would underflow a normalisation).
vec3 viewVector(vec3 ray) {
    if (P.orthographic != 0) {
        return vec3(0.0f, 0.0f, 1.0f);
    }
    return normalize(-ray);
}

// Image-plane direction (display pixels, y down) in which a point on `ray` moves
// when displaced along the view-space direction dirVS. The derivative of the
// projection is linear in the point, so the ray stands in for it at any depth.
vec2 screenDirection(vec3 ray, vec3 dirVS) {
    vec2 d;
    if (P.orthographic != 0) {
        d = vec2(P.fx * dirVS.x, -P.fy * dirVS.y);
    } else {
        // derivative of (x / -z, y / -z), up to a positive factor
        d = vec2(P.fx * (dirVS.x * -ray.z + ray.x * dirVS.z), -P.fy * (dirVS.y * -ray.z + ray.y * dirVS.z));
    }
    return d * inversesqrt(max(dot(d, d), 1e-30f));
}

// Smallest n.V kept: only back-facing (or exactly edge-on) normals are bent. A surface seen
// at a grazing angle keeps its true normal, or its own samples would rise above a bent tangent plane.
CONST_GLOBAL float MIN_NORMAL_DOT_VIEW = 1e-6f;

// View-space unit normal facing the viewer. Missing normals (zero, NaN) fall
// back to the view vector; back-facing ones are bent just past the silhouette,
// so a bad normal never produces NaN or a hemisphere facing away from the eye.
vec3 viewNormal(ivec2 texel, vec3 V) {
    vec3 n = mat3(P.normalToView) * loadNormal(texel);
    float len2 = dot(n, n);
    if (!(len2 > 1e-12f && len2 < 1e30f)) {
        return V;
    }
    n *= inversesqrt(len2);
    float nv = dot(n, V);
    if (nv < MIN_NORMAL_DOT_VIEW) {
        n = normalize(n + V * (MIN_NORMAL_DOT_VIEW - nv));
    }
    return n;
}
