// Hierarchical disc AO: Bunnell's discs (GPU Gems 2, ch. 14) with the corrections of Hoberock
// and Jia (GPU Gems 3, ch. 12), on the pixels of the depth pass. Written on lane types like
// kernels/hbao.glsl; docs/discs.md derives the windows and the open criterion.
//
// Every surface pixel is an element: its view-space position, normal and the area of its
// footprint on its tangent plane. A pyramid merges 2 x 2 elements per level (area-weighted
// position and normal, summed area); the host builds it (cpu/discs_cpu.cpp) from discBase().
// A receiver visits, from its top level (where a window covers R on the screen) down to the
// pixels, a fixed window of nodes around itself at each level. A node whose centre lies
// `dist` node sizes from the receiver (Chebyshev, on the screen) is open with weight
// discOpen(dist): 1 within k, 0 from k + 1/2 on, where the finer window ends. A node contributes (1 - open(itself)) * open(parent) of its form factor, so
// each pixel's weights along its chain of ancestors sum to 1 and change continuously with
// the receiver's position: no seams where the level changes (correction a).
//
// Backend contract: gatherDisc(index, c, use) reads channel c of pyramid texel `index`.
// Channels: 0-2 mean position, 3 area, 4-6 unit mean normal, 7 visibility (pass 2); the
// node's side walls (the hidden sides of what it occludes, see discWall): 8-10 centre,
// 11 area, 12-14 unit normal, 15 length along the view ray, 16 facing (+1: the normal points
// out of the solid, towards the drop; -1: into it; between: walls facing apart merged);
// 17-19, 20, 21-23: a second element like 0-6 (area 0: none): at level 0 the part of the pixel
// past a concave crease (discCreaseStrip), above it the children far behind the rest.

CONST_GLOBAL int DISC_CHANNELS = 24;
// A footprint is stretched at most as for n.V = 0.02 (88.9 degrees from the eye): beyond,
// depth gives no usable extent and a pixel would stand for an unbounded strip.
CONST_GLOBAL float DISC_MIN_NV = 0.02f;
// Elements within this sine of the receiver's horizon do not occlude: a plane's own elements
// lie on it up to float rounding of positions, and must give AO = 1 exactly.
CONST_GLOBAL float DISC_HORIZON = 2e-3f;
// The same for walls (2.9 degrees): a wall behind a plane seen at a grazing angle starts on
// the plane, and its top edge is there up to the rounding of the plane's own positions (0.01
// was not enough for the stiff suite's plane at depths 1e-3 to 1e6).
CONST_GLOBAL float DISC_WALL_HORIZON = 0.05f;

int discLevelWidth(int level) { return (P.width + (1 << level) - 1) >> level; }
int discLevelHeight(int level) { return (P.height + (1 << level) - 1) >> level; }
int discOffsetOf(int level) { return P.discLevelOffset[level >> 2][level & 3]; }

lvec3 gatherDisc3(lint index, int c, lbool use) {
    return lvec3(gatherDisc(index, c, use), gatherDisc(index, c + 1, use), gatherDisc(index, c + 2, use));
}

// The footprint of a pixel on its tangent plane (through `pos`, normal n), as the images du,
// dv of one pixel step right and down: d(point)/d(display x) is t/fx (e_x - n_x V / n.V), with
// t = depth (-z) for a pinhole and 1 for an orthographic camera; area = |du x dv|.
void discAxes(lvec3 ray, lvec3 pos, lvec3 n, OUT(lvec3) du, OUT(lvec3) dv) {
    lvec3 V = viewVector(ray);
    lfloat t = lfloat(1.0f);
    if (P.orthographic == 0) {
        t = -pos.z;
    }
    lfloat nv = max(dot(n, V), lfloat(DISC_MIN_NV));
    lvec3 a = lvec3(lfloat(1.0f), lfloat(0.0f), lfloat(0.0f)) - V * (n.x / nv);
    lvec3 b = V * (n.y / nv) - lvec3(lfloat(0.0f), lfloat(1.0f), lfloat(0.0f));
    // Where n.V was raised the steps leave the plane; project them back onto it.
    a = a - n * dot(n, a);
    b = b - n * dot(n, b);
    du = a * (t * P.invFx);
    dv = b * (t * P.invFy);
}

// z of w (depthW, kernels/depth_normal.glsl), 1e30 for w <= 0 under perspective (a plane continued past the horizon).
lfloat discZ(lfloat w) {
    if (P.orthographic != 0) {
        return w;
    }
    return select(w > 0.0f, 1.0f / max(w, lfloat(1e-30f)), lfloat(1e30f));
}

// How far the surface hidden behind texel (x, y)'s edge towards (sx, sy) reaches along -z:
// the neighbour lies behind the texel's plane continued from the other side, and the texel
// lies in front of the neighbour's plane continued back to it, by the smaller of the two
// (across a convex crease the second is 0: the faces meet, nothing is hidden). 0 where the
// surface runs on, 1e30 where the neighbour is sky, 0 where either side is past the
// buffer's edge: unknown. wq, wa: w 1 and 2 steps towards (sx, sy); wb: 1 step back.
lfloat discDrop(lint x, lint y, lfloat z0, lfloat w0, int sx, int sy, lfloat wq, lbool okQ, lfloat wa, lbool okA,
                lfloat wb, lbool okB) {
    lfloat zq = discZ(wq);
    lfloat zNext = discZ(select(okB, 2.0f * w0 - wb, w0));
    lfloat zBack = discZ(select(okA, 2.0f * wq - wa, wq));
    lfloat drop = max(min(zq - max(zNext, z0), zBack - z0), 0.0f);
    lbool sky = insideBuffer(x + sx, y + sy) && !okQ;
    // With the other side past the buffer's edge there is no slope to continue: unknown too.
    lbool known = insideBuffer(x - sx, y - sy);
    return select(known, select(sky, lfloat(1e30f), select(okQ, drop, lfloat(0.0f))), lfloat(0.0f));
}

// A drop shorter than this many pixel sizes is a crease or float noise, not a hidden side.
CONST_GLOBAL float DISC_MIN_DROP_PIXELS = 2.0f;
// The scan across a silhouette looks this many texels away at most (discScanStep's last).
CONST_GLOBAL int DISC_SCAN_SAMPLES = 14;

// A closed shape's hidden part reaches this share of its visible width behind its silhouette:
// half for a sphere or a pole (the back half of a circle of that diameter).
CONST_GLOBAL float DISC_DEPTH_PER_WIDTH = 0.5f;

// The i-th offset of the scan: 1, 2, 3, 4, 6, 8, 12, ... 128 texels.
int discScanStep(int i) {
    if (i == 0) {
        return 1;
    }
    return (i & 1) == 1 ? 1 << ((i + 1) >> 1) : 3 << ((i - 2) >> 1);
}

// The width in texels of the surface in front of an edge whose neighbour (sx, sy) lies `drop`
// farther in z: the scan away from the edge ends at the first texel that is sky or lies more
// than half the drop behind (the far side of a pole, a sphere's other rim); 128 if none does
// (nor past the buffer's edge, which says nothing).
lfloat discWidthTexels(lint x, lint y, lfloat z0, lfloat drop, int sx, int sy) {
    lfloat width = lfloat(float(discScanStep(DISC_SCAN_SAMPLES - 1)));
    lbool found = width < 0.0f;
    int previous = 0;
    for (int i = 0; i < DISC_SCAN_SAMPLES; ++i) {
        int k = discScanStep(i);
        lint qx = x - k * sx;
        lint qy = y - k * sy;
        lbool ok;
        lfloat w = depthW(qx, qy, surfaceDepth(qx, qy, ok));
        lfloat z = w;
        if (P.orthographic == 0) {
            z = 1.0f / w;
        }
        lbool off = insideBuffer(qx, qy) && (!ok || z > z0 + 0.5f * drop);
        width = select(off && !found, lfloat(0.5f * float(previous + k)), width);
        found = found || off;
        previous = k;
    }
    return width;
}

// The length of the wall behind one edge (drop: in z, zLen: ray length per unit of z; pixel:
// the pixel's size in the world): the drop along the ray, at most the thickness T, at most R
// (beyond R nothing counts), and at most DISC_DEPTH_PER_WIDTH of the width of the surface in
// front: a closed shape's hidden back is about half as deep as it is wide (a pole's is its
// radius, not T). 0 below the noise floor.
lfloat discWallLength(lint x, lint y, lfloat z0, lfloat drop, lfloat zLen, lfloat pixel, int sx, int sy) {
    float t = min(P.thickness, P.radius);
    lfloat along = drop * zLen;
    lbool edge = along > DISC_MIN_DROP_PIXELS * pixel;
    lfloat wall = min(along, lfloat(t));
    if (anyLane(edge)) {
        wall = min(wall, discWidthTexels(x, y, z0, drop, sx, sy) * (DISC_DEPTH_PER_WIDTH * pixel));
    }
    return select(edge, wall, lfloat(0.0f));
}

// The texel's side wall: where a neighbour lies farther than the texel's surface continued
// (a silhouette), the passes do not show what is behind the edge. As HBAO's thickness and
// rtao's extrusion do, take the visible surface to be a solid T deep: its side is a wall
// from the edge back along the view ray, T long or down to the farther surface. Walls of
// the four edges are one element: areas add per axis and in quadrature across axes (a
// diagonal silhouette's pixel stands for sqrt 2 pixels of edge), the normal lies across the
// ray towards the drops, signed into one half-space so walls facing apart still merge.
// The sides' w come from depthSide (L: left, R: right, U: up, D: down; 1 and 2 steps).
void discWall(lint x, lint y, lvec3 ray, lvec3 pos, lfloat w0, lbool surface, lfloat wL1, lbool okL1, lfloat wL2,
              lbool okL2, lfloat wR1, lbool okR1, lfloat wR2, lbool okR2, lfloat wU1, lbool okU1, lfloat wU2, lbool okU2,
              lfloat wD1, lbool okD1, lfloat wD2, lbool okD2, OUT(lvec3) wallPos, OUT(lvec3) wallN,
              OUT(lfloat) wallArea, OUT(lfloat) wallLen, OUT(lfloat) facing) {
    lfloat z0 = -pos.z;
    // Pixel size in the world; the ray's length per unit of z (ray.z = -1 under perspective).
    lfloat scale = lfloat(1.0f);
    lfloat zLen = lfloat(1.0f);
    lvec3 D = lvec3(lfloat(0.0f), lfloat(0.0f), lfloat(-1.0f));
    if (P.orthographic == 0) {
        scale = z0;
        zLen = sqrt(dot(ray, ray));
        D = viewVector(ray) * -1.0f;
    }
    lfloat px = scale * P.invFx;
    lfloat py = scale * P.invFy;
    lfloat dLeft = discDrop(x, y, z0, w0, -1, 0, wL1, okL1, wL2, okL2, wR1, okR1);
    lfloat dRight = discDrop(x, y, z0, w0, 1, 0, wR1, okR1, wR2, okR2, wL1, okL1);
    lfloat dUp = discDrop(x, y, z0, w0, 0, -1, wU1, okU1, wU2, okU2, wD1, okD1);
    lfloat dDown = discDrop(x, y, z0, w0, 0, 1, wD1, okD1, wD2, okD2, wU1, okU1);
    lfloat lLeft = discWallLength(x, y, z0, dLeft, zLen, px, -1, 0);
    lfloat lRight = discWallLength(x, y, z0, dRight, zLen, px, 1, 0);
    lfloat lUp = discWallLength(x, y, z0, dUp, zLen, py, 0, -1);
    lfloat lDown = discWallLength(x, y, z0, dDown, zLen, py, 0, 1);
    // Walls on the left and right run along the screen's y: a pixel's height wide.
    lfloat aLeft = lLeft * py;
    lfloat aRight = lRight * py;
    lfloat aUp = lUp * px;
    lfloat aDown = lDown * px;
    lfloat ax = aLeft + aRight;
    lfloat ay = aUp + aDown;
    lfloat sum = ax + ay;
    lfloat area = sqrt(ax * ax + ay * ay);
    wallLen = (aLeft * lLeft + aRight * lRight + aUp * lUp + aDown * lDown) / max(sum, lfloat(1e-30f));
    // The edge runs across the drops (towards them: g, in view x and y) at constant z, as a
    // pixel's side does; the wall is the parallelogram of the edge and the ray, and its
    // normal, signed into one half-space, is theirs.
    lvec3 g = lvec3(select(aRight < aLeft, ax * -1.0f, ax), select(aUp > aDown, ay, ay * -1.0f), lfloat(0.0f));
    lvec3 edge = lvec3(g.y * -1.0f, g.x, lfloat(0.0f)) * inversesqrt(max(dot(g, g), lfloat(1e-30f)));
    lvec3 m = cross(D, edge);
    lfloat slant = sqrt(dot(m, m));
    m = m * (1.0f / max(slant, lfloat(1e-30f)));
    // facing: +1 where the stored normal points towards the drops, out of the solid.
    lbool flip = m.x + 0.5f * m.y < 0.0f;
    wallN = select(flip, m * -1.0f, m);
    facing = select(flip, lfloat(-1.0f), lfloat(1.0f)) * select(dot(m, g) < 0.0f, lfloat(-1.0f), lfloat(1.0f));
    // Drops on both sides of an axis (a pole one pixel wide): walls on both, no one outside.
    lbool twoSided = (aLeft > 0.0f && aRight > 0.0f) || (aUp > 0.0f && aDown > 0.0f);
    facing = select(twoSided, lfloat(0.0f), facing);
    area = area * slant;
    lbool used = surface && area > 0.0f;
    // A wall shorter than 1e-4 of its distance would be lost in the rounding of its position,
    // and could rise above a plane's horizon (DISC_HORIZON) on either side.
    used = used && wallLen > 1e-4f * sqrt(dot(pos, pos));
    wallArea = select(used, area, lfloat(0.0f));
    wallPos = pos + D * (wallLen * 0.5f);
}

// The part of texel (x, y)'s screen block that lies past a crease towards side (sx, sy), on
// the neighbour's plane: there the texel's own element (on its own plane) stands for nothing,
// and the face across the crease would have a gap one part-pixel wide right along it, the
// nearest part of that face for receivers beside the crease. w is affine in the pixel
// coordinates on a plane: the own plane through w0 and wb (one step back), the neighbour's
// through w1 and w2; they meet s steps towards the side. Added to (stripPos, stripN) by
// area, its share of the block to `share`.
void discCreaseStrip(lint x, lint y, lfloat w0, int sx, int sy, lfloat w1, lbool ok1, lfloat w2, lbool ok2, lfloat wb,
                     lbool okB, INOUT(lvec3) stripPos, INOUT(lvec3) stripN, INOUT(lfloat) stripArea,
                     INOUT(lfloat) share) {
    lfloat own = w0 - wb;
    lfloat next = w2 - w1;
    lfloat bend = own - next;
    lfloat scale = max(max(abs(w0), abs(w1)), max(abs(w2), abs(wb)));
    // A silhouette (a drop, discDrop) is not a crease: past it the surfaces do not meet.
    lfloat z0 = discZ(w0);
    lfloat pixel = (P.orthographic != 0 ? 1.0f : z0) * (sx != 0 ? P.invFx : P.invFy);
    lfloat drop = discDrop(x, y, z0, w0, sx, sy, w1, ok1, w2, ok2, wb, okB);
    // Concave only: the neighbour nearer than the own plane continued to it (w grows towards
    // the eye under perspective). Past a convex crease the far face falls below the texel's
    // tangent plane, and a strip's square stand-in tilted off it would poke above.
    lfloat nearer = w1 - (w0 + own);
    if (P.orthographic != 0) {
        nearer = nearer * -1.0f;
    }
    lbool crease = ok1 && ok2 && okB && nearer > 1e-3f * scale && drop < DISC_MIN_DROP_PIXELS * pixel;
    lfloat s = (w1 - next - w0) / select(crease, bend, lfloat(1.0f));
    crease = crease && s > 0.0f && s < 0.5f;
    if (!anyLane(crease)) {
        return;
    }
    s = select(crease, s, lfloat(0.25f)); // keep every lane's point finite
    lfloat centre = 0.5f * (s + 0.5f);
    lfloat z = discZ(w1 + (centre - 1.0f) * next);
    crease = crease && z < 1e29f;
    z = select(crease, z, lfloat(1.0f));
    lvec3 ray = viewRay(lvec2(lfloat(x + P.originX) + 0.5f + centre * float(sx), lfloat(y + P.originY) + 0.5f + centre * float(sy)));
    lvec3 p = ray * z;
    if (P.orthographic != 0) {
        p = lvec3(ray.x, ray.y, z * -1.0f);
    }
    lvec3 m = viewNormal(gatherNormal(x + sx, y + sy, crease), viewVector(ray));
    lvec3 du;
    lvec3 dv;
    discAxes(ray, p, m, du, dv);
    lvec3 c = cross(du, dv);
    lfloat a = select(crease, (0.5f - s) * sqrt(dot(c, c)), lfloat(0.0f));
    stripPos += p * a;
    stripN += m * a;
    stripArea += a;
    share += select(crease, 0.5f - s, lfloat(0.0f));
}

// The level-0 element of buffer texel (x, y) and its wall; area 0 where it is not a surface.
// Its normal is the depth's own (kernels/depth_normal.glsl: the cross product of the steps to
// its neighbours on the sides that continue its plane) wherever those steps are no longer than three footprints of
// the shading normal: elements must lie in each other's tangent planes where the surface is
// smooth, and shading normals need not (a smooth-shaded cylinder averages its caps into its
// sides; a facet bends them). Elsewhere (edges, one-pixel features) the pass's normal stays.
void discBase(lint x, lint y, OUT(lvec3) pos, OUT(lvec3) n, OUT(lfloat) area, OUT(lvec3) wallPos, OUT(lvec3) wallN,
              OUT(lfloat) wallArea, OUT(lfloat) wallLen, OUT(lfloat) facing, OUT(lvec3) stripPos, OUT(lvec3) stripN,
              OUT(lfloat) stripArea) {
    lbool surface;
    lfloat depth = surfaceDepth(x, y, surface);
    lvec3 ray = viewRay(lvec2(lfloat(x + P.originX) + 0.5f, lfloat(y + P.originY) + 0.5f));
    lvec3 V = viewVector(ray);
    pos = positionOnRay(ray, depth);
    n = viewNormal(gatherNormal(x, y, surface), V);
    lvec3 du;
    lvec3 dv;
    discAxes(ray, pos, n, du, dv);
    lbool leftOk;
    lbool rightOk;
    lbool upOk;
    lbool downOk;
    lvec3 left = depthStep(x, y, ray, depth, -1, 0, leftOk);
    lvec3 right = depthStep(x, y, ray, depth, 1, 0, rightOk);
    lvec3 up = depthStep(x, y, ray, depth, 0, -1, upOk);
    lvec3 down = depthStep(x, y, ray, depth, 0, 1, downOk);
    lbool alongX;
    lbool alongY;
    lfloat w0 = depthW(x, y, depth);
    lfloat wL1;
    lfloat wL2;
    lfloat wR1;
    lfloat wR2;
    lfloat wU1;
    lfloat wU2;
    lfloat wD1;
    lfloat wD2;
    lbool okL1;
    lbool okL2;
    lbool okR1;
    lbool okR2;
    lbool okU1;
    lbool okU2;
    lbool okD1;
    lbool okD2;
    depthSide(x, y, -1, 0, wL1, okL1, wL2, okL2);
    depthSide(x, y, 1, 0, wR1, okR1, wR2, okR2);
    depthSide(x, y, 0, -1, wU1, okU1, wU2, okU2);
    depthSide(x, y, 0, 1, wD1, okD1, wD2, okD2);
    lvec3 sx = depthPlaneStep(left, leftOk, depthBend(w0, wL1, okL1, wL2, okL2), right, rightOk,
                             depthBend(w0, wR1, okR1, wR2, okR2), alongX);
    lvec3 sy = depthPlaneStep(up, upOk, depthBend(w0, wU1, okU1, wU2, okU2), down, downOk,
                             depthBend(w0, wD1, okD1, wD2, okD2), alongY);
    lbool usable;
    lvec3 g = depthNormalOfSteps(sx, sy, V, usable);
    lbool fromDepth = surface && alongX && alongY && usable && dot(sx, sx) < 9.0f * dot(du, du) &&
                    dot(sy, sy) < 9.0f * dot(dv, dv);
    n = select(fromDepth, g, n);
    discAxes(ray, pos, n, du, dv);
    lvec3 c = cross(du, dv);
    area = select(surface, sqrt(dot(c, c)), lfloat(0.0f));
    stripPos = lvec3(lfloat(0.0f), lfloat(0.0f), lfloat(0.0f));
    stripN = stripPos;
    stripArea = lfloat(0.0f);
    lfloat share = lfloat(0.0f);
    // A pixel's part past a concave crease: the second element; the first keeps the rest.
    discCreaseStrip(x, y, w0, -1, 0, wL1, okL1 && surface, wL2, okL2, wR1, okR1, stripPos, stripN, stripArea, share);
    discCreaseStrip(x, y, w0, 1, 0, wR1, okR1 && surface, wR2, okR2, wL1, okL1, stripPos, stripN, stripArea, share);
    discCreaseStrip(x, y, w0, 0, -1, wU1, okU1 && surface, wU2, okU2, wD1, okD1, stripPos, stripN, stripArea, share);
    discCreaseStrip(x, y, w0, 0, 1, wD1, okD1 && surface, wD2, okD2, wU1, okU1, stripPos, stripN, stripArea, share);
    lbool strip = stripArea > 0.0f;
    stripPos = stripPos * (1.0f / select(strip, stripArea, lfloat(1.0f)));
    lfloat nl = sqrt(dot(stripN, stripN));
    stripN = stripN * (1.0f / select(nl > 0.0f, nl, lfloat(1.0f)));
    area = area * max(1.0f - share, 0.25f);
    discWall(x, y, ray, pos, w0, surface, wL1, okL1, wL2, okL2, wR1, okR1, wR2, okR2, wU1, okU1, wU2, okU2, wD1, okD1,
             wD2, okD2, wallPos, wallN, wallArea, wallLen, facing);
}

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

// A disc closer than this many radii is replaced by its polygon: there the disc's form factor
// saturates towards cos(receiver) whatever part of the hemisphere the element really covers
// (a floor seen at a grazing angle, merged into nodes far larger in the world than on screen).
CONST_GLOBAL float DISC_NEAR_RADII = 3.0f;

// The side wall of pyramid texel `index` (discWall): a parallelogram `length` long along the
// view ray through its centre, its other sides at constant z in its plane. A disc as far as its half length is a poor
// stand-in for a long strip, so nearer than DISC_NEAR_RADII of that it is the parallelogram's
// exact form factor. The range ramp spans the half length.
void discWallContribution(lvec3 xr, lvec3 nr, lint index, lbool use, lfloat weight, INOUT(DiscBins) bins) {
    lvec3 c;
    lfloat area;
    lvec3 n;
    discGather(index, 8, use, c, area, n);
    lvec3 v = c - xr;
    lfloat d2 = dot(v, v);
    lfloat ff = discFormFactor(v, d2, nr, n, area, DISC_WALL_HORIZON);
    lfloat wallLength = gatherDisc(index, 15, use);
    lfloat halfLength = 0.5f * wallLength;
    lfloat reach2 = area * (1.0f / PI) + halfLength * halfLength;
    lbool near = use && d2 < (DISC_NEAR_RADII * DISC_NEAR_RADII) * reach2;
    if (anyLane(near)) {
        lvec3 D = lvec3(lfloat(0.0f), lfloat(0.0f), lfloat(-1.0f));
        if (P.orthographic == 0) {
            D = c * inversesqrt(max(dot(c, c), 1e-30f));
        }
        // The edge: in the wall's plane at constant z (discWall); the sides are slanted.
        lvec3 edge = lvec3(n.y, n.x * -1.0f, lfloat(0.0f));
        edge = edge * inversesqrt(max(dot(edge, edge), lfloat(1e-30f)));
        lvec3 m = cross(D, edge);
        lfloat slant = max(sqrt(dot(m, m)), lfloat(1e-3f));
        lvec3 across = edge * (0.5f * area / (max(wallLength, lfloat(1e-30f)) * slant));
        ff = select(near, discQuadFormFactor(nr, v, D * halfLength, across, DISC_WALL_HORIZON), ff);
    }
    ff = ff * discRangeWeight(sqrt(d2), PI * halfLength * halfLength);
    // A wall occludes only receivers on its outer side: from the inner side it lies behind
    // the surface whose edge it hangs from (the ceiling's front edge, seen from the room),
    // whose own elements already count. Walls facing apart (a pole's two sides) count whole.
    lfloat facing = gatherDisc(index, 16, use);
    lbool inner = abs(facing) > 0.5f && dot(n, xr - c) * facing < 0.0f;
    ff = select(inner || !(use && area > 0.0f), lfloat(0.0f), ff * weight);
    discAdd(bins, nr, v, d2, area * (1.0f / PI) + halfLength * halfLength, ff);
}

// The form factor of element (e, ne, area) of node (ex, ey) of `level`, v = e - xr away, within
// R: a disc, or nearer than DISC_NEAR_RADII (or with `polygon`) its exact footprint polygon.
lfloat discElementFormFactor(lvec3 xr, lvec3 nr, lvec3 e, lvec3 ne, lfloat area, lvec3 v, lfloat d2, lbool use,
                             bool polygon, lint ex, lint ey, int level) {
    lfloat ff = discFormFactor(v, d2, nr, ne, area, DISC_HORIZON);
    lbool near = use && d2 * PI < (DISC_NEAR_RADII * DISC_NEAR_RADII) * area;
    if (polygon) {
        near = use;
    }
    if (P.discPolygon != 0 && anyLane(near)) {
        ff = select(near, discPolygonFormFactor(xr, nr, e, ne, area, ex, ey, level), ff);
    }
    return select(use && area > 0.0f, ff * discRangeWeight(sqrt(d2), area), lfloat(0.0f));
}

// The node's second element (channels 17-23: the part of a pixel past a concave crease, on
// the far face; above level 0 the children lying far behind the others), if any.
void discSecondContribution(lvec3 xr, lvec3 nr, lint index, lbool use, lfloat weight, bool polygon, lint ex, lint ey,
                            int level, INOUT(DiscBins) bins) {
    lvec3 e;
    lfloat area;
    lvec3 ne;
    lbool two = use && gatherDisc(index, 20, use) > 0.0f;
    if (!anyLane(two)) {
        return;
    }
    discGather(index, 17, two, e, area, ne);
    lvec3 v = e - xr;
    lfloat d2 = dot(v, v);
    lfloat ff = discElementFormFactor(xr, nr, e, ne, area, v, d2, two, polygon, ex, ey, level);
    discAdd(bins, nr, v, d2, area * (1.0f / PI), ff * weight);
}

// The node's first element. Where no lane's element is both within R and near (its polygon)
// or above the receiver's horizon (a plane's own nodes, everything under a floor receiver's
// tangent plane), its form factor is 0 in every lane: the rest is skipped, from its normal on.
void discFirstContribution(lvec3 xr, lvec3 nr, lint index, lbool use, lfloat weight, bool polygon, lint ex, lint ey,
                           int level, lbool continued, INOUT(DiscBins) bins) {
    lvec3 e = gatherDisc3(index, 0, use);
    lfloat area = gatherDisc(index, 3, use);
    lvec3 v = e - xr;
    lfloat d2 = dot(v, v);
    if (!anyLane(continued && use) && !polygon) {
        lbool near = d2 * PI < (DISC_NEAR_RADII * DISC_NEAR_RADII) * area;
        // discFormFactor's cosR > 0, with a margin for rounding between the two.
        lbool above = dot(nr, v) * inversesqrt(max(d2, lfloat(1e-30f))) > DISC_HORIZON - 1e-6f;
        // discRangeWeight > 0: nearer than R plus the element's radius (with a margin).
        lfloat reach = P.radius + 1.01f * sqrt(area * (1.0f / PI));
        lbool inRange = d2 < reach * reach;
        if (!anyLane(use && area > 0.0f && inRange && (near || above))) {
            return;
        }
    }
    lvec3 ne = gatherDisc3(index, 4, use);
    if (anyLane(continued && use)) {
        discContinue(continued, ex, ey, level, e, ne, area, use);
        v = e - xr;
        d2 = dot(v, v);
    }
    lfloat ff = discElementFormFactor(xr, nr, e, ne, area, v, d2, use, polygon, ex, ey, level);
    discAdd(bins, nr, v, d2, area * (1.0f / PI), ff * weight);
}

// The element of pyramid texel `index` (node (ex, ey) of `level`) and its wall where `wall`:
// their occlusion of the receiver (xr, nr), `weight` included; `polygon`: always the exact
// footprint form factor.
void discContribution(lvec3 xr, lvec3 nr, lint index, lbool use, lbool wall, lfloat weight, bool polygon, lint ex,
                      lint ey, int level, lbool continued, INOUT(DiscBins) bins) {
    if (P.discVisibility != 0) {
        weight = weight * gatherDisc(index, 7, use);
    }
    discFirstContribution(xr, nr, index, use, weight, polygon, ex, ey, level, continued, bins);
    discSecondContribution(xr, nr, index, use && !continued, weight, polygon, ex, ey, level, bins);
    lbool walled = wall && !continued && gatherDisc(index, 11, wall) > 0.0f;
    if (anyLane(walled)) {
        discWallContribution(xr, nr, index, walled, weight, bins);
    }
}

// How far, in pixels, the sphere of radius R around a receiver at view position xr reaches on
// the screen: R f / sqrt(z^2 - R^2) on the axis, stretched by up to 1 + tan^2 of the ray's
// angle off it, with a quarter for the stretch across the sphere; capped by maxRadiusPixels.
// The base kernel takes its largest value over each tile, for the frame's top level (cpu/discs_cpu.cpp).
lfloat discReachPixels(lvec3 xr) {
    float cap = P.maxRadiusPixels + 2.0f;
    float f = max(P.fx, P.fy);
    if (P.orthographic != 0) {
        return lfloat(min(1.25f * P.radius * f + 2.0f, cap));
    }
    lfloat z = -xr.z;
    lfloat tan2 = (xr.x * xr.x + xr.y * xr.y) / max(z * z, 1e-30f);
    lfloat reach = (1.25f * P.radius * f) * (1.0f + tan2) * inversesqrt(max(z * z - P.radius * P.radius, 1e-30f)) + 2.0f;
    return select(z > 1.01f * P.radius, min(reach, lfloat(cap)), lfloat(cap));
}

// k at `level`: its nodes open within k of the receiver; a level's window is made by the
// level above's k. Growing upwards keeps every open node's parent open.
int discWindowAt(int level) { return P.discWindow + (level >= P.discWideFrom ? 1 : 0); }

// The receiver's top level: the coarsest whose window (2k nodes each way beyond the
// receiver's own, k of the level above) covers its reach, at most P.discTop.
lint discTopLevel(lvec3 xr) {
    lfloat reach = discReachPixels(xr);
    lint top = lint(0);
    for (int level = 1; level <= P.discTop; ++level) {
        top = top + select(float(2 * discWindowAt(level)) * float(1 << (level - 1)) < reach, lint(1), lint(0));
    }
    return top;
}

lfloat discsLanes(lint x, lint y) {
    lbool inside = insideBuffer(x, y);
    lint self = x + y * P.width;
    lfloat areaR = gatherDisc(self, 3, inside);
    lbool computing = inside && areaR > 0.0f;
    if (!anyLane(computing)) {
        return lfloat(1.0f);
    }
    lvec3 xr = gatherDisc3(self, 0, computing);
    // The receiver's hemisphere is about the pass's normal, as the AO definition's (a ray
    // tracer's AO pass) and HBAO's: elements keep the depth's own normals, which must lie in
    // each other's planes, but a smooth-shaded facet's receiver is shaded as its normal says
    // (Blender's columns: 20.9 -> 24.7 dB against Cycles).
    lvec3 nr = viewNormal(gatherNormal(x, y, computing), viewVector(viewRay(lvec2(lfloat(x + P.originX) + 0.5f,
                                                                                  lfloat(y + P.originY) + 0.5f))));
    lint topLevel = discTopLevel(xr);
    lfloat px = lfloat(x) + 0.5f;
    lfloat py = lfloat(y) + 0.5f;
    DiscBins bins;
    discStartBins(bins, nr);
    for (int level = P.discTop; level >= 0; --level) {
        // Lanes whose top is coarser go on; at its top a lane takes its nodes whole.
        lbool visiting = computing && !(topLevel < lint(level));
        if (!anyLane(visiting)) {
            continue;
        }
        lbool top = !(topLevel > lint(level));
        // This level's open radius, and the one above's, whose open nodes' children are this
        // level's window.
        int kHere = discWindowAt(level);
        int k = discWindowAt(level + 1);
        int span = 4 * k + 2;
        float size = float(1 << level);
        int levelW = discLevelWidth(level);
        int levelH = discLevelHeight(level);
        int levelOffset = discOffsetOf(level);
        // The window: the children of the (2k + 1)^2 nodes around the receiver's parent.
        lint bx = ((x >> (level + 1)) << 1) - 2 * k;
        lint by = ((y >> (level + 1)) << 1) - 2 * k;
        for (int j = 0; j < span; ++j) {
            lint ny = by + j;
            lfloat dy = abs((lfloat(ny) + 0.5f) * size - py);
            lfloat pdy = abs((lfloat(ny >> 1) + 0.5f) * (2.0f * size) - py);
            lfloat idy = abs(lfloat(ny - (y >> level)));
            lfloat pidy = abs(lfloat((ny >> 1) - (y >> (level + 1))));
            for (int i = 0; i < span; ++i) {
                lint nx = bx + i;
                lbool inside = nx >= 0 && ny >= 0 && nx < levelW && ny < levelH;
                lbool use = visiting && inside;
                if (P.hbaoBorder == HBAO_BORDER_TANGENT) {
                    use = visiting;
                }
                lfloat weight = lfloat(1.0f);
                if (level > 0) {
                    lfloat dist = max(abs((lfloat(nx) + 0.5f) * size - px), dy) * (1.0f / size);
                    lfloat idist = max(abs(lfloat(nx - (x >> level))), idy);
                    weight = 1.0f - discOpen(dist, idist, kHere);
                }
                lfloat pdist = max(abs((lfloat(nx >> 1) + 0.5f) * (2.0f * size) - px), pdy) * (0.5f / size);
                lfloat pidist = max(abs(lfloat((nx >> 1) - (x >> (level + 1)))), pidy);
                weight = weight * select(top, lfloat(1.0f), discOpen(pdist, pidist, k));
                if (level == 0 && P.discPolygon != 0) {
                    // The 3 x 3 pixels around the receiver are the polygon loop's below.
                    weight = select(max(abs(lfloat(nx - x)), idy) < 1.5f, lfloat(0.0f), weight);
                }
                use = use && weight > 0.0f;
                if (anyLane(use)) {
                    // A receiver's own wall is the solid behind it, under its horizon.
                    lbool wall = use;
                    if (level == 0) {
                        wall = use && (nx < x || nx > x || ny < y || ny > y);
                    }
                    lint index = levelOffset + clamp(nx, lint(0), lint(levelW - 1)) + clamp(ny, lint(0), lint(levelH - 1)) * levelW;
                    discContribution(xr, nr, index, use, wall, weight, false, nx, ny, level, !inside, bins);
                }
            }
        }
    }
    if (P.discPolygon != 0) {
        for (int j = -1; j <= 1; ++j) {
            for (int i = -1; i <= 1; ++i) {
                if (i != 0 || j != 0) {
                    lint ex = x + i;
                    lint ey = y + j;
                    lbool inside = insideBuffer(ex, ey);
                    lbool use = computing && inside;
                    if (P.hbaoBorder == HBAO_BORDER_TANGENT) {
                        use = computing;
                    }
                    lint index = clamp(ex, lint(0), lint(P.width - 1)) + clamp(ey, lint(0), lint(P.height - 1)) * P.width;
                    discContribution(xr, nr, index, use, use, lfloat(1.0f), true, ex, ey, 0, !inside, bins);
                } else {
                    // The receiver's own part past a crease: the nearest of the face across it.
                    discSecondContribution(xr, nr, self, computing, lfloat(1.0f), true, x, y, 0, bins);
                }
            }
        }
    }
    return select(computing, clamp(1.0f - discOcclusion(bins), 0.0f, 1.0f), 1.0f);
}
