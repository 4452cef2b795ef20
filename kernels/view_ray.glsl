// The camera's rays: what common.glsl's reconstruction and the packing of HBAO's light's normals
// (cpu/pack_tile_impl.h) share. Requires a parameter block `P` with the camera's KernelParams.

// Direction through a display position, scaled so z = -1 (perspective); for an
// orthographic camera, the position on the image plane with z = 0.
lvec3 viewRay(lvec2 displayPos) {
    return lvec3((displayPos.x - P.cx) * P.invFx, (P.cy - displayPos.y) * P.invFy, P.orthographic != 0 ? 0.0f : -1.0f);
}

// Unit vector towards the eye. Taken from the pixel's ray, not its position, so
// it stays exact at any depth (tiny depths would underflow a normalisation).
lvec3 viewVector(lvec3 ray) {
    if (P.orthographic != 0) {
        return lvec3(0.0f, 0.0f, 1.0f);
    }
    return normalize(-ray);
}
