// Shared per-pixel helpers: hashing, camera reconstruction, pass validation.
// Written on lane types (lfloat, lvec3, ...: one pixel in GLSL, several on the CPU; see
// cpu/lanes.h). Requires a parameter block `P` with the KernelParams members used here.

CONST_GLOBAL float PI = 3.14159265358979f;
CONST_GLOBAL float TWO_PI = 6.28318530717959f;

// Integer finaliser (a well-mixed 32-bit hash); the same bits on CPU and GPU.
luint hashU32(luint x) {
    x ^= x >> 16u;
    x *= 0x7feb352du;
    x ^= x >> 15u;
    x *= 0x846ca68bu;
    x ^= x >> 16u;
    return x;
}

luint hashPixel(lint displayX, lint displayY) {
    return hashU32(luint(displayX) ^ hashU32(luint(displayY) + 0x9e3779b9u));
}

// Top 24 bits -> [0, 1): exactly representable, so both backends agree bit for bit.
lfloat hashToUnit(luint h) {
    return lfloat(h >> 8u) * (1.0f / 16777216.0f);
}

// Smallest normal float: denormal depths carry no usable precision and are treated as holes.
CONST_GLOBAL float MIN_SURFACE_DEPTH = 1.17549435e-38f;

// A depth that describes a surface: finite, positive, nearer than the sky. NaN fails every comparison.
lbool isSurfaceDepth(lfloat depth) {
    return depth >= MIN_SURFACE_DEPTH && depth < P.skyDepth;
}

ivec2 bufferOrigin() {
    return ivec2(P.originX, P.originY);
}

lbool insideBuffer(lint x, lint y) {
    return x >= 0 && y >= 0 && x < P.width && y < P.height;
}

// The same for the texel whose corner (whole numbers, as floor() gives) is `corner`, at
// least `margin` texels from the buffer's edges.
lbool insideBuffer(lvec2 corner, float margin) {
    return corner.x >= margin && corner.y >= margin && corner.x < float(P.width) - margin &&
           corner.y < float(P.height) - margin;
}

// The display corner of the buffer texel nearest the one at display corner `corner` (itself
// when inside): the edge texel that stands in for a texel past the buffer's edge.
lvec2 nearestBufferCorner(lvec2 corner) {
    vec2 origin = vec2(bufferOrigin());
    return lvec2(clamp(corner.x, origin.x, origin.x + float(P.width - 1)),
                 clamp(corner.y, origin.y, origin.y + float(P.height - 1)));
}

// Depth of the buffer texels (x, y) in world units, and which of them are surfaces (inside
// the buffer, finite, nearer than the sky). The others get depth 1: harmless in arithmetic
// whose result they discard. Requires the backend's gatherDepth(x, y, use).
lfloat surfaceDepth(lint x, lint y, OUT(lbool) surface) {
    surface = insideBuffer(x, y);
    lfloat depth = gatherDepth(x, y, surface) * P.depthScale;
    surface = surface && isSurfaceDepth(depth);
    return select(surface, depth, 1.0f);
}

#include "view_ray.glsl"

// View-space position (OpenGL camera: looking down -Z) of a point on `ray` at a given depth.
lvec3 positionOnRay(lvec3 ray, lfloat depth) {
    if (P.orthographic != 0) {
        return lvec3(ray.x, ray.y, -depth);
    }
    if (P.radialDepth != 0) {
        return ray * (depth * inversesqrt(dot(ray, ray)));
    }
    return ray * depth;
}

lvec3 viewPosition(lvec2 displayPos, lfloat depth) {
    return positionOnRay(viewRay(displayPos), depth);
}

// viewOffset's w for a sample `pixels` display pixels from the receiver's centre (whole and half
// numbers, so the sum that forms them is exact): (pixels.x / fx, -pixels.y / fy).
lvec2 imageOffset(lvec2 pixels) {
    return lvec2(pixels.x * P.invFx, pixels.y * -P.invFy);
}

// S - P for a sample whose ray is rayS = rayP + (w, 0), without forming S and P: at large
// depth both are big and nearly equal, and their difference would cancel most significant
// digits. S - P = (dS - dP) rayP + dS w, every term small where the answer is small. w is
// (pixel offset.x / fx, -pixel offset.y / fy), an image-plane offset for orthographic cameras.
lvec3 viewOffset(lvec3 rayP, lfloat depthP, lvec2 w, lfloat depthS) {
    if (P.orthographic != 0) {
        return lvec3(w.x, w.y, depthP - depthS);
    }
    if (P.radialDepth != 0) {
        lvec3 rayS = lvec3(rayP.x + w.x, rayP.y + w.y, rayP.z);
        return rayS * (depthS * inversesqrt(dot(rayS, rayS))) - rayP * (depthP * inversesqrt(dot(rayP, rayP)));
    }
    lfloat dd = depthS - depthP;
    return lvec3(dd * rayP.x + depthS * w.x, dd * rayP.y + depthS * w.y, dd * rayP.z);
}

// Where `ray` (viewRay's) meets the plane through point e with normal m: the point, not finite
// where the ray runs along the plane (callers guard for it). Perspective: ray t with planar depth
// t = -z. Orthographic: the point on the plane straight down the view axis from (ray.x, ray.y).
lvec3 rayMeetsPlane(lvec3 ray, lvec3 m, lvec3 e) {
    if (P.orthographic != 0) {
        return lvec3(ray.x, ray.y, e.z - (m.x * (ray.x - e.x) + m.y * (ray.y - e.y)) / m.z);
    }
    return ray * (dot(m, e) / dot(m, ray));
}

// Where the plane through a texel's surface point (on `ray` at `depth`) with unit normal m meets
// the ray through image offset `delta` from that texel's centre (display pixels times
// (1/fx, -1/fy), as viewOffset's w), as an offset from the surface point: the finite form of
// discAxes' footprint derivative. Formed from the offset alone, never by subtracting two
// positions, so it lies in the plane up to rounding of its own size (a plane's footprints stay
// on it). Where the plane meets that ray behind the eye or farther than maxLength away, the
// offset is cut to maxLength in the plane's direction of escape.
lvec3 planeStep(lvec3 ray, lfloat depth, lvec3 m, lvec2 delta, lfloat maxLength) {
    lvec3 d = lvec3(delta.x, delta.y, lfloat(0.0f));
    lfloat md = dot(m, d);
    lvec3 away;   // direction of the offset, up to a positive factor
    lfloat scale; // its length over |away| where the plane meets the ray
    if (P.orthographic != 0) {
        // Rays run along -z: the point d + s (0, 0, -1) on the plane.
        away = lvec3(d.x, d.y, -md / select(abs(m.z) > 1e-30f, m.z, lfloat(1e-30f)));
        scale = lfloat(1.0f);
    } else {
        // The point t' (ray + d) with m . (t' (ray + d) - t ray) = 0, t the ray's parameter at the
        // point: offset t ((m.ray) d - (m.d) ray) / (m.ray + m.d).
        lfloat t = P.radialDepth != 0 ? depth * inversesqrt(dot(ray, ray)) : depth;
        lfloat mr = dot(m, ray);
        away = ray * md - d * mr; // the numerator negated: the denominator is negative where the ray meets it
        lfloat den = -(mr + md);
        scale = select(den > 0.0f, t / max(den, 1e-30f), lfloat(1e30f));
    }
    lfloat len2 = dot(away, away);
    lfloat inv = inversesqrt(max(len2, 1e-36f));
    return away * min(scale, maxLength * inv);
}

// Image-plane direction (display pixels, y down) in which a point on `ray` moves
// when displaced along the view-space direction dirVS. The derivative of the
// projection is linear in the point, so the ray stands in for it at any depth.
lvec2 screenDirection(lvec3 ray, lvec3 dirVS) {
    lvec2 d;
    if (P.orthographic != 0) {
        d = lvec2(P.fx * dirVS.x, -P.fy * dirVS.y);
    } else {
        // derivative of (x / -z, y / -z), up to a positive factor
        d = lvec2(P.fx * (dirVS.x * -ray.z + ray.x * dirVS.z), -P.fy * (dirVS.y * -ray.z + ray.y * dirVS.z));
    }
    return d * inversesqrt(max(dot(d, d), 1e-30f));
}

// Orthonormal basis around a unit normal without a branch on its direction
// (Duff et al. 2017), so every normal gets a well-conditioned frame.
void tangentFrame(lvec3 n, OUT(lvec3) b1, OUT(lvec3) b2) {
    lfloat sgn = select(n.z >= 0.0f, lfloat(1.0f), lfloat(-1.0f));
    lfloat a = -1.0f / (sgn + n.z);
    lfloat b = n.x * n.y * a;
    b1 = lvec3(1.0f + sgn * n.x * n.x * a, sgn * b, -sgn * n.x);
    b2 = lvec3(b, sgn + n.y * n.y * a, -n.y);
}

// Smallest n.V kept: only back-facing (or exactly edge-on) normals are bent. A surface seen
// at a grazing angle keeps its true normal, or its own samples would rise above a bent tangent plane.
CONST_GLOBAL float MIN_NORMAL_DOT_VIEW = 1e-6f;

// View-space unit normal facing the viewer, from a normal as the pass stores it. Missing
// normals (zero, NaN) fall back to the view vector; back-facing ones are bent just past
// the silhouette, so a bad normal never produces NaN or a hemisphere facing away from the eye.
lvec3 viewNormal(lvec3 passNormal, lvec3 V) {
    lvec3 n = mat3(P.normalToView) * passNormal;
    lfloat len2 = dot(n, n);
    lbool usable = len2 > 1e-12f && len2 < 1e30f;
    n = select(usable, n * inversesqrt(select(usable, len2, 1.0f)), V);
    lfloat nv = dot(n, V);
    lbool backFacing = nv < MIN_NORMAL_DOT_VIEW;
    if (anyLane(backFacing)) {
        n = select(backFacing, normalize(n + V * (MIN_NORMAL_DOT_VIEW - nv)), n);
    }
    return n;
}
