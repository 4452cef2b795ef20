// Disc AO's hidden sides (kernels/discs.glsl): where a pixel's surface drops away behind a
// silhouette, the wall that closes the solid, and the part of a pixel past a concave crease.
// Included by discs.glsl at this point of the kernel; docs/discs.md derives them.

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
