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

#include "discs_walls.glsl"        // hidden sides behind silhouettes, creases
#include "discs_form_factors.glsl" // open weights, form factors, azimuth bins, node reads

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

// The receiver's walk down the pyramid, level by level (docs/discs.md's steps, in order). Longer
// than a function should be: the walk's lane state (the bins, each level's open weights) lives
// across every level, and cutting it up moves where GCC contracts multiply-adds (kernels.md).
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
