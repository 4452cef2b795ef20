// HBAO_DEEP's step (kernels/hbao.glsl, docs/deep.md): each layer of a sample's texel, found once
// (hbao_deep.glsl), is occupied by the AO and, with HBAO_GI, covered by the light (hbao_gi.glsl).

// The visible layer's span where the renderer saw the ray leave its solid, the texel's footprint
// on its tangent plane, then every hidden layer (inside the buffer: past it, the continued
// surface's samples, hbao_border.glsl). The light covers each layer's interval, the visible one
// with the bounce source, each hidden one with the colour the deep file holds for it (black
// without one). The footprint is left to the AO: it refines where a grazing plane hides, and the
// light takes the texel's point as flat input does, so a deep file of one surface per pixel gives
// the flat input's light.
void takeSampleDeep(IN(HbaoSample) smp, IN(HbaoReceiver) r, IN(HbaoSlice) sl, INOUT(FootprintPrevious) previous,
                    INOUT(HbaoOccluded) o, INOUT(HbaoGi) g) {
    DeepInterval visible = visibleLayerInterval(smp, r, sl);
    occupyInterval(visible.a, visible.b, visible.backA, visible.backB, visible.counts, o);
    if (HBAO_GI != 0 && anyLane(visible.counts)) {
        coverGi(visible.a, visible.b, visible.backA, visible.backB, visible.counts, smp.corner, 0, sl.np, g);
    }
    takeFootprint(smp, lvec3(r.ray.x + smp.w.x, r.ray.y + smp.w.y, r.ray.z), sl, r.radius2, previous, o);
    bool more = true; // some lane has layer k: layers come nearest first, so none has the next without it
    for (int k = 1; k < P.deepLayers && more; ++k) {
        DeepInterval hidden = hiddenLayerInterval(k, smp, r, sl, more);
        if (anyLane(hidden.counts)) {
            occupyInterval(hidden.a, hidden.b, hidden.backA, hidden.backB, hidden.counts, o);
            if (HBAO_GI != 0) {
                coverGi(hidden.a, hidden.b, hidden.backA, hidden.backB, hidden.counts, smp.corner, k, sl.np, g);
            }
        }
    }
}
