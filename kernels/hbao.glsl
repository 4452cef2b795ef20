// Horizon-based ambient occlusion (Bavoil, Sainz & Dimitrov 2008, "Image-space horizon-based
// ambient occlusion", the paper) with the thickness of the visibility bitmask (Therrien,
// Levesque & Gilet 2023, "Screen space indirect lighting with visibility bitmask", the bitmask
// paper), written on lane types: one pixel per GPU thread, several per CPU register
// (docs/kernels.md). Per-pixel branches are masks; loops are uniform over the lanes.
//
// This file is the algorithm. What a sample hides is the plan's model (core/hbao_plan.h), each
// in a file of its own, chosen at compile time on both devices (template arguments on the CPU,
// cpu/lane_tile_impl.h; defines on OpenGL, gpu/gl_kernels.cpp):
//   HBAO_MODEL  HBAO_HORIZON, HBAO_FIXED_THICKNESS, HBAO_MEASURED_THICKNESS or HBAO_DEEP
//   HBAO_RUNS   1: samples are applied per occluder, a run of them, when it ends
//   HBAO_GI     1: also the indirect light the march's samples send (hbao_gi.glsl); 0 if undefined
// The paper's AO (its Eq. 3) is 1 - 1/(2 pi) \int (sin h(phi) - sin t(phi)) W(phi) dphi over the
// azimuth phi, h the horizon's elevation and t the tangent's. Directions are slices around the
// view vector V (as in GTAO), so every slice is a plane through the eye and its samples lie on one
// image line; this makes the solid-angle measure exact under perspective. Within a slice the
// integrand is F, the occlusion from the tangent up to an angle (hbao_slice.glsl, which also
// gives the cosine-weighted form).

#ifndef HBAO_GI
#define HBAO_GI 0
#endif
#include "hbao_slice.glsl"   // the receiver, a slice's axes, F, the march
#include "hbao_horizon.glsl" // HBAO_HORIZON: the highest sample
#include "hbao_bitmask.glsl" // HBAO_FIXED_THICKNESS: each sample's interval, sectors above the horizon
#include "hbao_runs.glsl"    // HBAO_RUNS: a run of samples per occluder (HBAO_MEASURED_THICKNESS)
#include "hbao_deep.glsl"    // HBAO_DEEP: the renderer's layers, each texel's footprint
#include "hbao_border.glsl"  // past the buffer's edge: the continued surface
#include "hbao_gi.glsl"      // HBAO_GI: each newly covered angle's bounce light
#include "hbao_deep_step.glsl" // HBAO_DEEP's step: each layer for the AO and the light

// The slice's integral of F: at the horizon, plus the sectors set above it (none without a
// thickness); linear falloff has summed its weighted rises as it marched.
lfloat sliceIntegral(IN(HbaoSlice) sl, IN(HbaoOccluded) o) {
    lfloat occlusion = o.occlusion;
    if (P.linearFalloff == 0) {
        lfloat invLen = inversesqrt(o.horizonA * o.horizonA + o.horizonB * o.horizonB);
        occlusion = sliceOcclusionAt(o.horizonA * invLen, o.horizonB * invLen, sl.np);
        if (HBAO_MODEL != HBAO_HORIZON) {
            // Sectors wholly below the horizon add nothing: clear them, and skip the sum when none is left.
            lint horizonSector = min(lint(sectorPseudoAngle(o.horizonA, o.horizonB) * 16.0f), lint(31));
            luint sectors = o.sectors & ~bitsBelow(horizonSector);
            if (anyLane(lfloat(sectors) > 0.0f)) {
                occlusion += sectorOcclusion(sectors, occlusion, sl.np);
            }
        }
    }
    return occlusion;
}

// Ambient occlusion in [0,1] (1 = unoccluded) of the buffer texels (x, y); texels outside
// the buffer, sky and holes get 1.
lfloat hbaoLanes(lint x, lint y) {
    if (HBAO_GI != 0) {
        hbaoIrradiance = lvec3(lfloat(0.0f), lfloat(0.0f), lfloat(0.0f));
    }
    // 1. The receiver's point and normal, and R projected on the screen, which bounds the march
    //    (the paper's projected radius); nothing to do off surfaces or where R spans no whole pixel.
    HbaoReceiver r;
    r.depth = surfaceDepth(x, y, r.computing);
    if (!anyLane(r.computing)) {
        return lfloat(1.0f);
    }
    receiverFrame(x, y, r);
    if (!anyLane(r.computing)) {
        return lfloat(1.0f);
    }
    receiverSteps(x, y, r);
    // 2. The integral over phi: N_d slices, turned by a random angle per pixel (the paper's
    //    per-pixel rotation of the directions).
    HbaoAzimuth azimuth = firstAzimuth(r);
    lfloat occlusion = lfloat(0.0f);
    lvec3 irradiance = lvec3(lfloat(0.0f), lfloat(0.0f), lfloat(0.0f)); // HBAO_GI only
    for (int d = 0; d < P.directions; ++d) {
        HbaoSlice slice = nextSlice(r, azimuth);
        HbaoOccluded o = nothingOccluded();
        OccluderRun run = noRun();                         // HBAO_RUNS only
        FootprintPrevious previous = receiverFootprint(r); // HBAO_DEEP only
        HbaoGi lit = nothingLit(irradiance);                // HBAO_GI only
        // 3. The horizon h(phi): N_s steps along the slice's image line, from one pixel out to R,
        //    jittered per pixel and snapped to texel centres (the paper's ray marching).
        HbaoMarch march = startMarch(r, slice);
        for (int s = 0; s < P.steps; ++s) {
            HbaoSample smp;
            lfloat loaded;
            lbool inBuffer = advanceMarch(r, s, march, smp.corner, loaded);
            if (!march.interior) {
                // Off the interior, the steps each lane takes inside the buffer come first (the
                // line is straight, the buffer convex): the march ends when every lane has left.
                march.stepsInside += select(inBuffer, lfloat(1.0f), lfloat(0.0f));
                if (!anyLane(inBuffer)) {
                    break;
                }
            }
            sampleAt(r, slice, loaded, inBuffer, smp);
            // 4. Each sample per model: it raises the horizon (the paper; with linear falloff, its
            //    attenuated rise), sets its interval from its front to T behind it (the bitmask
            //    paper), first joins its occluder's run, or adds every layer the renderer saw.
            if (HBAO_RUNS != 0) {
                RunStep st = runStepAt(smp, r, slice, run);
                if (HBAO_GI != 0) {
                    lightEndingRun(st, slice, run, o, lit); // before the run's close raises the horizon
                }
                takeSampleInRuns(smp, r, slice, st, run, o);
                if (HBAO_GI != 0) {
                    lightRisingSample(smp, run);
                }
            } else if (HBAO_MODEL == HBAO_DEEP) {
                takeSampleDeep(smp, r, slice, previous, o, lit); // with HBAO_GI, its light too
            } else if (HBAO_MODEL == HBAO_FIXED_THICKNESS) {
                takeSampleFixed(smp, slice, o);
            } else {
                takeSampleHorizon(smp, r, slice, o);
            }
            if (HBAO_GI != 0 && HBAO_RUNS == 0 && HBAO_MODEL != HBAO_DEEP) {
                takeSampleGi(smp, slice, lit);
            }
        }
        if (HBAO_RUNS != 0) {
            if (HBAO_GI != 0) {
                lightUnfinishedRun(run, slice, o, lit);
            }
            closeUnfinishedRun(run, slice, o);
        }
        // 5. Where the march left the buffer: the surface continued past its edge.
        lbool left = r.computing && march.stepsInside < float(P.steps);
        if (P.hbaoBorder != HBAO_BORDER_OPEN && !march.interior && anyLane(left)) {
            HbaoOccluded before = o; // HBAO_GI with HBAO_RUNS: the AO's state before the border
            takeBorder(r, slice, march, left, o);
            if (HBAO_GI != 0 && HBAO_RUNS != 0) {
                lightBorderAsOccluded(r, slice, march, left, before, o, lit);
            } else if (HBAO_GI != 0) {
                takeBorderGi(r, slice, march, left, lit);
            }
        }
        // 6. The slice's integral (Eq. 3's integrand): F at the horizon, and the sectors above it.
        occlusion += sliceIntegral(slice, o);
        if (HBAO_GI != 0) {
            irradiance = lit.irradiance;
        }
    }
    // 7. AO = 1 - the sum normalised. Uniform: (1/2pi) * (2pi/N_d) * sum. Cosine: (1/pi) *
    //    (2pi/N_d) * sum.
    float norm = (P.cosineWeighting != 0 ? 2.0f : 1.0f) / float(P.directions);
    if (HBAO_GI != 0) {
        // E = (2 pi / N_d) * the slices' sums of L dF_cos.
        lvec3 none = lvec3(lfloat(0.0f), lfloat(0.0f), lfloat(0.0f));
        hbaoIrradiance = select(r.computing, irradiance * (TWO_PI / float(P.directions)), none);
    }
    return select(r.computing, clamp(1.0f - occlusion * norm, 0.0f, 1.0f), 1.0f);
}
