// Screen-space directional occlusion and one indirect bounce (Ritschel, Grosch and
// Seidel, I3D 2009), written on lane types: one pixel per GPU thread, several pixels per
// CPU register (cpu/lanes.h). Per-pixel branches are masks; loops are uniform over the lanes.
//
// N points are placed in the normal-oriented hemisphere within r_max: N / SSDO_STEPS
// cosine-distributed directions, each with SSDO_STEPS - 1 points stratified along it. Each point
// is projected into the depth image: if the surface seen there lies in front of the point (and
// within r_max of the pixel), the point is blocked. A direction's share of open points weighs
// the environment's radiance along it (pi/n per direction: irradiance with a linear falloff, as
// AO's). With the bounce, a march of its own along each direction (geometric, from about a pixel
// to r_max) finds the first surface the direction enters: its outgoing radiance (the bounce
// source, times its albedo) arrives along it. With cosine-distributed directions the irradiance
// is pi times the mean radiance arriving, so each direction adds pi/n times its sender's
// radiance (docs/ssdo.md derives it). Past the buffer's edge the bounce meets the edge texels'
// surfaces continued; DO sees open sky there.
// Interleaved sampling: the pixels of an M x M block use disjoint subsets of one
// rotated direction set, and a geometry-aware blur of size M gathers them back.
//
// Requires the lane loads (0 where `use` is false, albedo 1): lfloat gatherDepth(lint x,
// lint y, lbool use), and lvec3 gatherNormal, gatherRadiance, gatherAlbedo, and gatherEnv
// (texel (x, y) of the prefiltered environment level) with the same arguments.

// N counts SSDO_STEPS points per direction (kernel_params.glsl). The bounce's march adds
// SSDO_MARCH_POINTS + 1 of its own (not counted in N).
// The geometric marches, the bounce's along each direction and a directional light's: this many
// points from about a pixel to r_max, then one at r_max, so that a surface near the receiver (a
// contact shadow, a small sender) is met as surely as a far one. 8: marchRatio takes its root by
// three square roots. A bounce point entered a surface when it lies behind the surface seen by
// less than SSDO_ENTER_THICKNESS times its distance from the previous point.
CONST_GLOBAL int SSDO_MARCH_POINTS = 8;
CONST_GLOBAL float SSDO_ENTER_THICKNESS = 3.0f;

// Radical inverse in base 2 (van der Corput): the second coordinate of a Hammersley set.
lfloat radicalInverse2(luint i) {
    i = (i << 16u) | (i >> 16u);
    i = ((i & 0x55555555u) << 1u) | ((i & 0xAAAAAAAAu) >> 1u);
    i = ((i & 0x33333333u) << 2u) | ((i & 0xCCCCCCCCu) >> 2u);
    i = ((i & 0x0F0F0F0Fu) << 4u) | ((i & 0xF0F0F0F0u) >> 4u);
    i = ((i & 0x00FF00FFu) << 8u) | ((i & 0xFF00FF00u) >> 8u);
    return lfloat(i >> 8u) * (1.0f / 16777216.0f);
}

// Bilinear lookup of the lat-long environment level (wraps in longitude, clamps at the poles),
// read where `use`.
lvec3 environmentRadiance(lvec3 dirView, lbool use) {
    if (P.envWidth <= 0) {
        return lvec3(vec3(P.skyRadiance) * P.envIntensity);
    }
    lvec3 d = mat3(P.viewToEnv) * dirView;
    lfloat u = 0.5f + atan(d.x, -d.z) * (1.0f / TWO_PI);
    lfloat v = acos(clamp(d.y, -1.0f, 1.0f)) * (1.0f / PI);
    lfloat tx = u * float(P.envWidth) - 0.5f;
    lfloat ty = v * float(P.envHeight) - 0.5f;
    lfloat fx = tx - floor(tx);
    lfloat fy = ty - floor(ty);
    // u is in [0, 1], so floor(tx) is in [-1, width - 1]: one wrap each way is the modulo.
    lint x0 = lint(floor(tx));
    x0 = select(x0 < 0, x0 + P.envWidth, select(x0 >= P.envWidth, x0 - P.envWidth, x0));
    lint x1 = select(x0 + 1 >= P.envWidth, 0, x0 + 1);
    lint y0 = clamp(lint(floor(ty)), 0, P.envHeight - 1);
    lint y1 = clamp(lint(floor(ty)) + 1, 0, P.envHeight - 1);
    lvec3 top = mix(gatherEnv(x0, y0, use), gatherEnv(x1, y0, use), fx);
    lvec3 bottom = mix(gatherEnv(x0, y1, use), gatherEnv(x1, y1, use), fx);
    return mix(top, bottom, fy) * P.envIntensity;
}

// Display position of a view-space point; clears `visible` where it cannot be seen (behind the eye).
void projectToDisplay(lvec3 p, INOUT(lbool) visible, OUT(lvec2) displayPos) {
    if (P.orthographic != 0) {
        displayPos = lvec2(P.cx + P.fx * p.x, P.cy - P.fy * p.y);
        return;
    }
    visible = visible && p.z < 0.0f;
    lfloat invDepth = 1.0f / select(visible, -p.z, 1.0f);
    displayPos = lvec2(P.cx + P.fx * p.x * invDepth, P.cy - P.fy * p.y * invDepth);
}

// Where the ray through display position `displayPos` meets the tangent plane of the buffer texel
// nearest it: the surface continued past the buffer's edge, as HBAO's tangent border does
// (hbao_border.glsl). `met` where that texel is a surface and its plane meets the ray in front of
// the eye at more than a grazing angle.
lvec3 continuedSurface(lvec2 displayPos, lint edgeX, lint edgeY, lbool use, OUT(lbool) met) {
    lfloat edgeDepth = gatherDepth(edgeX, edgeY, use) * P.depthScale;
    met = use && isSurfaceDepth(edgeDepth);
    lvec3 edgeRay = viewRay(lvec2(lfloat(edgeX + P.originX) + 0.5f, lfloat(edgeY + P.originY) + 0.5f));
    lvec3 m = viewNormal(gatherNormal(edgeX, edgeY, met), viewVector(edgeRay));
    lvec3 e = positionOnRay(edgeRay, select(met, edgeDepth, 1.0f));
    lvec3 sampleRay = viewRay(displayPos);
    // Beyond 89 degrees from the ray the plane's continuation is ill-conditioned (as discs').
    lvec3 along = P.orthographic != 0 ? lvec3(vec3(0.0f, 0.0f, 1.0f)) : sampleRay;
    met = met && abs(dot(m, along)) > 0.0175f * sqrt(dot(along, along));
    lvec3 q = rayMeetsPlane(sampleRay, m, e);
    met = met && q.z < 0.0f && isSurfaceDepth(-q.z);
    return select(met, q, e);
}

// Where `asking`: whether the surface seen where a view-space point projects lies in front of
// the point and above the receiver's tangent plane: texel (texelX, texelY) and `surface` say what
// is seen, `distance2` its squared distance from the receiver. The tangent-plane condition is
// geometry, not a bias: nothing below that plane can block a direction of the hemisphere, and
// without it the pixel grid makes a flat surface shadow itself at grazing sample directions.
// Past the buffer's edge, where `continuing`, the nearest edge texel's surface continues; elsewhere
// (and behind the eye) nothing is known, and light passes. DO does not continue: on the report it
// bought 1% of DO's error for 10-30% of its time (docs/notes/2026-11-28-ssdo-gi-error.md).
lbool behindSurface(lvec3 point, lvec3 receiver, lvec3 n, lvec2 centre, lbool asking, bool continuing,
                    OUT(lint) texelX, OUT(lint) texelY, OUT(lvec3) surface, OUT(lfloat) distance2) {
    lbool ok = asking;
    lvec2 displayPos;
    projectToDisplay(point, ok, displayPos);
    // Reads stop at maxRadiusPixels, as HBAO's do: a host that pins it gets tiles equal to the frame.
    lfloat reachX = displayPos.x - centre.x;
    lfloat reachY = displayPos.y - centre.y;
    ok = ok && !(reachX * reachX + reachY * reachY > P.maxRadiusPixels * P.maxRadiusPixels);
    // Lanes out of reach look at their own pixel, so the conversion to int stays in range.
    lfloat cornerX = floor(select(ok, displayPos.x, centre.x));
    lfloat cornerY = floor(select(ok, displayPos.y, centre.y));
    texelX = lint(cornerX) - P.originX;
    texelY = lint(cornerY) - P.originY;
    lbool inside = insideBuffer(texelX, texelY);
    lbool past = ok && !inside;
    ok = ok && inside;
    lfloat d = gatherDepth(texelX, texelY, ok) * P.depthScale;
    ok = ok && isSurfaceDepth(d);
    surface = viewPosition(lvec2(cornerX + 0.5f, cornerY + 0.5f), select(ok, d, 1.0f));
    if (continuing && anyLane(past)) {
        texelX = select(past, clamp(texelX, 0, P.width - 1), texelX);
        texelY = select(past, clamp(texelY, 0, P.height - 1), texelY);
        lbool met;
        lvec3 q = continuedSurface(lvec2(cornerX + 0.5f, cornerY + 0.5f), texelX, texelY, past, met);
        surface = select(met, q, surface);
        ok = ok || met;
    }
    lvec3 toSurface = surface - receiver;
    distance2 = dot(toSurface, toSurface);
    // 1e-4 of the distance: float noise in a reconstructed plane stays below it.
    lbool above = dot(n, toSurface) > 1e-4f * sqrt(distance2);
    return ok && -surface.z < -point.z && above;
}

// DO's test: the point lies behind the surface seen, and that surface within r_max of the receiver.
lbool blockedBySurface(lvec3 point, lvec3 receiver, lvec3 n, lvec2 centre, lbool asking) {
    lint tx;
    lint ty;
    lvec3 q;
    lfloat distance2;
    lbool behind = behindSurface(point, receiver, n, centre, asking, false, tx, ty, q, distance2);
    return behind && distance2 < P.radius * P.radius;
}

// The stratified points along one direction (receiver + dir t, t in (0, r_max)): how many are open.
lfloat openAlong(lvec3 receiver, lvec3 n, lvec2 centre, lvec3 dir, lfloat offset, lbool valid) {
    lfloat openPoints = lfloat(0.0f);
    for (int step = 0; step < SSDO_STEPS - 1; ++step) {
        lfloat along = (float(step) + offset) * (1.0f / float(SSDO_STEPS - 1));
        lvec3 point = receiver + dir * (P.radius * max(along, 1e-3f));
        lbool blocked = blockedBySurface(point, receiver, n, centre, valid);
        openPoints += select(valid && !blocked, lfloat(1.0f), lfloat(0.0f));
    }
    return openPoints;
}

// The ratio of a march's successive points, (r_max / nearest)^(1 / SSDO_MARCH_POINTS): one per
// pixel, shared by its directions and lights.
lfloat marchRatio(lfloat nearest) {
    return sqrt(sqrt(sqrt(max(P.radius / nearest, 1.0f))));
}

// Point j (1 .. SSDO_MARCH_POINTS + 1) of a march: `base` walks nearest, nearest ratio, ...; each
// point lies `offset` into its interval, the last at r_max.
lfloat marchPoint(int j, INOUT(lfloat) base, lfloat ratio, lfloat offset) {
    lfloat t = j > SSDO_MARCH_POINTS ? lfloat(P.radius) : base * (1.0f + (ratio - 1.0f) * offset);
    base = base * ratio;
    return min(t, P.radius);
}

// The bounce's march along one direction: the first point that entered a surface since the
// previous one (it lies behind the surface seen by less than SSDO_ENTER_THICKNESS steps) is the
// sender, seen at texel (senderX, senderY), view position `sender`. Points from `nearest` (about
// a pixel at the receiver, successive ones `ratio` apart) to r_max, each shifted by `offset` of its interval.
void findSender(lvec3 receiver, lvec3 n, lvec2 centre, lvec3 dir, lfloat offset, lfloat nearest, lfloat ratio,
                lbool valid, lint x, lint y, OUT(lbool) found, OUT(lint) senderX, OUT(lint) senderY, OUT(lvec3) sender) {
    found = valid && !valid;
    senderX = x;
    senderY = y;
    sender = receiver;
    lfloat previous = lfloat(0.0f);
    lfloat base = nearest;
    for (int j = 1; j <= SSDO_MARCH_POINTS + 1; ++j) {
        if (!anyLane(valid && !found)) {
            break;
        }
        lfloat t = marchPoint(j, base, ratio, offset);
        lvec3 point = receiver + dir * t;
        lint tx;
        lint ty;
        lvec3 q;
        lfloat distance2;
        lbool behind = behindSurface(point, receiver, n, centre, valid && !found, true, tx, ty, q, distance2);
        lbool first = behind && (-point.z) - (-q.z) < SSDO_ENTER_THICKNESS * (t - previous);
        senderX = select(first, tx, senderX);
        senderY = select(first, ty, senderY);
        sender = select(first, q, sender);
        found = found || first;
        previous = t;
    }
}

// Whether a surface within r_max blocks direction `l` (unit, view space) where `asking`: the
// march's points from `nearest` to r_max, `ratio` apart, each shifted by `offset` of its interval.
lbool lightBlocked(lvec3 receiver, lvec3 n, lvec2 centre, vec3 l, lfloat offset, lfloat nearest, lfloat ratio,
                   lbool asking) {
    lbool blocked = asking && !asking;
    lfloat base = nearest;
    for (int j = 1; j <= SSDO_MARCH_POINTS + 1; ++j) {
        lbool open = asking && !blocked;
        if (!anyLane(open)) {
            break;
        }
        lfloat t = marchPoint(j, base, ratio, offset);
        blocked = blocked || blockedBySurface(receiver + lvec3(l) * t, receiver, n, centre, open);
    }
    return blocked;
}

// The bounce source's radiance of the sender where `found`, 0 elsewhere.
lvec3 senderRadiance(lvec3 receiver, lvec3 sender, lbool found, lint senderX, lint senderY) {
    // The sender's outgoing radiance arrives along the direction; a sender that turns its back
    // to the receiver is the unlit side of what the direction meets, and sends nothing.
    lvec3 toSender = sender - receiver;
    lvec3 senderRay = viewRay(lvec2(lfloat(senderX + P.originX) + 0.5f, lfloat(senderY + P.originY) + 0.5f));
    lvec3 senderNormal = viewNormal(gatherNormal(senderX, senderY, found), viewVector(senderRay));
    lbool facing = found && dot(senderNormal, toSender) < 0.0f;
    lvec3 radiance = gatherRadiance(senderX, senderY, facing);
    if (P.senderAlbedo != 0) {
        radiance = radiance * gatherAlbedo(senderX, senderY, facing);
    }
    return select(facing, radiance, lvec3(vec3(0.0f)));
}

// Directional occlusion (irradiance from unblocked directions), one-bounce indirect
// irradiance, and the AO of the same points (cosine-weighted, linear falloff) of the
// buffer texels (x, y); texels outside the buffer, sky and holes get 0, 0 and 1. Longer than a
// function should be: one loop over the directions feeds all three sums, and cutting it up moves
// where GCC contracts multiply-adds (kernels.md).
void ssdoLanes(lint x, lint y, OUT(lvec3) directional, OUT(lvec3) indirect, OUT(lfloat) ao) {
    lvec3 zero = lvec3(vec3(0.0f));
    directional = zero;
    indirect = zero;
    ao = lfloat(1.0f);
    lbool computing = insideBuffer(x, y);
    lfloat depth = gatherDepth(x, y, computing) * P.depthScale;
    computing = computing && isSurfaceDepth(depth);
    if (!anyLane(computing)) {
        return;
    }
    depth = select(computing, depth, 1.0f); // lanes that sit out compute on a harmless depth
    lint displayX = x + P.originX;
    lint displayY = y + P.originY;
    lvec2 centre = lvec2(lfloat(displayX) + 0.5f, lfloat(displayY) + 0.5f);
    lvec3 ray = viewRay(centre);
    lvec3 receiver = positionOnRay(ray, depth);
    lvec3 n = viewNormal(gatherNormal(x, y, computing), viewVector(ray));
    lvec3 b1;
    lvec3 b2;
    tangentFrame(n, b1, b2);

    // Interleaving: this pixel's subset of the sample set, and a rotation shared by its block.
    int m = max(P.interleave, 1);
    lint cellX = ((displayX % m) + m) % m;
    lint cellY = ((displayY % m) + m) % m;
    lint subset = cellX + m * cellY;
    int stride = m * m;
    luint h = hashPixel((displayX - cellX) / m, (displayY - cellY) / m);
    lfloat rotationX = hashToUnit(h);
    lfloat rotationY = hashToUnit(hashU32(h));
    lfloat distanceJitter = hashToUnit(hashU32(h + 0x68e31da4u));

    // Sample i's azimuth is 2 pi (RI(i) + rotationY), RI the radical inverse. With a
    // power-of-two stride, RI(subset + k stride) = RI(subset) + RI(k) / stride: the pixel's
    // angle turned by one shared by every pixel for sample k, so a complex multiplication
    // per sample replaces a cosine and a sine.
    bool splits = (stride & (stride - 1)) == 0;
    lfloat pixelAngle = TWO_PI * fract(radicalInverse2(luint(subset)) + rotationY);
    lfloat cosPixel = cos(pixelAngle);
    lfloat sinPixel = sin(pixelAngle);

    // About a pixel at the receiver, the bounce's nearest point.
    lfloat nearest = min(1.5f * (P.orthographic != 0 ? P.invFx : -receiver.z * P.invFx), lfloat(P.radius));
    lfloat pointRatio = marchRatio(nearest);
    lfloat used = lfloat(0.0f);
    lfloat open = lfloat(0.0f);
    int directions = max(P.ssdoSamples / SSDO_STEPS, stride); // at least one per pixel of the block
    int perPixel = (directions + stride - 1) / stride;
    for (int k = 0; k < perPixel; ++k) {
        lint i = subset + k * stride;
        lbool valid = computing && i < directions;
        used += select(valid, lfloat(1.0f), lfloat(0.0f));
        // Hammersley point, rotated per block (Cranley-Patterson), mapped to a cosine-weighted direction.
        lfloat u1 = fract((lfloat(i) + 0.5f) / float(directions) + rotationX);
        lfloat cosPhi;
        lfloat sinPhi;
        if (splits) {
            float turn = TWO_PI * uniformValue(radicalInverse2(luint(uint(k)))) / float(stride);
            float cosTurn = cos(turn);
            float sinTurn = sin(turn);
            cosPhi = cosPixel * cosTurn - sinPixel * sinTurn;
            sinPhi = sinPixel * cosTurn + cosPixel * sinTurn;
        } else {
            lfloat phi = TWO_PI * fract(radicalInverse2(luint(i)) + rotationY);
            cosPhi = cos(phi);
            sinPhi = sin(phi);
        }
        lfloat r = sqrt(u1);
        lvec3 dir = (r * cosPhi) * b1 + (r * sinPhi) * b2 + sqrt(max(1.0f - u1, 0.0f)) * n;
        // Points stratified along the direction in (0, r_max]: a golden-ratio offset per direction,
        // decorrelated from it, shifts all of them, so each distance is as likely as any other.
        lfloat offset = fract(lfloat(i) * 0.618033988749895f + distanceJitter);
        lfloat openPoints = openAlong(receiver, n, centre, dir, offset, valid);
        lbool found = valid && !valid;
        lint senderX = x;
        lint senderY = y;
        lvec3 sender = receiver;
        if (P.bounce != 0) {
            // The march's own offset, half a period from the stratified points'.
            findSender(receiver, n, centre, dir, fract(offset + 0.5f), nearest, pointRatio, valid, x, y, found, senderX,
                       senderY, sender);
        }
        lfloat openShare = openPoints * (1.0f / float(SSDO_STEPS - 1));
        open += openShare;
        lbool opening = openPoints > 0.0f;
        if (anyLane(opening)) {
            directional += select(opening, environmentRadiance(dir, opening) * openShare, zero);
        }
        if (P.bounce == 0 || !anyLane(found)) {
            continue;
        }
        indirect += senderRadiance(receiver, sender, found, senderX, senderY);
    }
    lbool any = computing && used > 0.0f;
    lfloat count = max(used, 1.0f);
    // Cosine-weighted directions: irradiance = pi / n * sum of the radiance arriving along them.
    directional = select(any, directional * (PI / count), zero);
    indirect = select(any, indirect * (PI / count), zero);
    ao = select(any, open / count, 1.0f);

    // Directional lights: irradiance n.l, unless a surface within r_max blocks the way (lightBlocked).
    for (int k = 0; k < P.lightCount; ++k) {
        vec3 l = vec3(P.lightDirection[k]);
        lfloat cosL = dot(n, lvec3(l));
        lbool lit = any && cosL > 0.0f;
        if (!anyLane(lit)) {
            continue;
        }
        lit = lit && !lightBlocked(receiver, n, centre, l, distanceJitter, nearest, pointRatio, lit);
        directional += select(lit, lvec3(vec3(P.lightIrradiance[k])) * cosL, zero);
    }
}
