// The HBAO parameter block, one definition for host (C++ via GLM) and shader
// (GLSL std140 uniform block). Members are mat4 or groups of four 4-byte
// scalars, so the std140 and C++ layouts are byte-identical.
struct HbaoParams {
    mat4 normalToView;     // rotates input normals into view space (upper 3x3; identity for camera-space normals)

    float fx, fy;          // perspective: focal length in pixels; orthographic: pixels per world unit
    float cx, cy;          // principal point, display-window pixel coordinates

    float invFx, invFy;    // 1/fx, 1/fy, so the inner loop multiplies instead of divides
    float radius;          // R, world units
    float skyDepth;        // depth at or beyond this is background

    float maxRadiusPixels; // cap on the projected radius, keeps huge R and tiny depth bounded
    float depthScale;      // multiplies loaded depth (1; lets hosts feed other units)
    float pad0, pad1;

    int width, height;     // size of the buffers the loads address
    int originX, originY;  // display coordinates of buffer texel (0,0): noise and projection use display coords, so tiles agree

    int directions;        // N_d
    int steps;             // N_s
    int cosineWeighting;   // 0: uniform solid angle (HBAO paper), 1: projected solid angle (ray-traced AO)
    int linearFalloff;     // 0: binary visibility within R, 1: W(r) = 1 - r/R

    int orthographic;      // 0: pinhole, 1: orthographic
    int radialDepth;       // 0: depth is -z (planar), 1: depth is distance to the eye
    int pad2, pad3;
};
