// The kernels' parameter block, one definition for host (C++ via GLM) and shader
// (GLSL std140 uniform block). Members are mat4, vec4 (arrays) or groups of four
// 4-byte scalars, so the std140 and C++ layouts are byte-identical.
struct KernelParams {
    mat4 normalToView;     // rotates input normals into view space (upper 3x3; identity for camera-space normals)

    float fx, fy;          // perspective: focal length in pixels; orthographic: pixels per world unit
    float cx, cy;          // principal point, display-window pixel coordinates

    float invFx, invFy;    // 1/fx, 1/fy, so the inner loop multiplies instead of divides
    float radius;          // R, world units
    float skyDepth;        // depth at or beyond this is background

    float maxRadiusPixels; // cap on the projected radius, keeps huge R and tiny depth bounded
    float depthScale;      // multiplies loaded depth (1; lets hosts feed other units)
    float thickness;       // hbao: world-units thickness of depth-pass surfaces (+inf: none, a height field)
    int hbaoBorder;        // hbao: samples past the buffer's edge: HBAO_BORDER_OPEN, ... below

    int width, height;     // size of the buffers the loads address
    int originX, originY;  // display coordinates of buffer texel (0,0): noise and projection use display coords, so tiles agree

    int directions;        // N_d
    int steps;             // N_s
    int cosineWeighting;   // 0: uniform solid angle (HBAO paper), 1: projected solid angle (ray-traced AO)
    int linearFalloff;     // 0: binary visibility within R, 1: W(r) = 1 - r/R

    int orthographic;      // 0: pinhole, 1: orthographic
    int radialDepth;       // 0: depth is -z (planar), 1: depth is distance to the eye
    int ssaoSamples;       // ssao (kernels/ssao.glsl): points per pixel
    int ssaoHemisphere;    // ssao: 1: normal-oriented hemisphere, 0: the whole sphere (Crytek)

    // ---- SSDO (kernels/ssdo.glsl); `radius` above is its r_max ----
    mat4 viewToEnv;              // view-space direction -> environment space (y up), rotation included
    vec4 skyRadiance;            // constant sky radiance (rgb) when there is no environment map
    vec4 lightDirection[4];      // directional lights: view-space unit vector towards each light
    vec4 lightIrradiance[4];     // their irradiance at normal incidence (rgb)

    int ssdoSamples;             // N: the whole sample set; each pixel uses N / (M*M) of it
    int interleave;              // M: the pixels of an M x M block take disjoint subsets
    int lightCount;              // directional lights in use, at most 4
    int bounce;                  // 1: compute the one-bounce indirect light (GI)

    int envWidth, envHeight;     // the prefiltered lat-long level uploaded; 0 x 0: no map, use skyRadiance
    int senderAlbedo;            // 1: a sender's radiance is the bounce source times its albedo
    int hbaoModel;               // hbao: HBAO_HORIZON, ... below (core/hbao_plan.h, HbaoModel)

    float envIntensity;          // multiplies the environment (map or sky)
    float blurReach;             // blur: world-units reach of its spatial weight (0: pixels alone); BLUR_REACH below
    float runDepthPerWidth;      // hbao, HBAO_MEASURED_THICKNESS: a run's thickness per unit of its width
    float runJump;               // hbao, runs and deep footprints: the largest depth change (world units) within one occluder

    // ---- HBAO's visibility bitmask (kernels/hbao.glsl) ----
    // Per bound k = 0..32 of the 32 sectors (pseudo-angle k/16, angle theta_k above the tangent),
    // the terms of F that multiply cos b and sin b: uniform (1 - cos, sin), cosine (theta - sin cos, sin^2).
    vec4 sectorTerms[33];

    // ---- discs (kernels/discs.glsl, docs/discs.md); the pyramid is built by the host ----
    ivec4 discLevelOffset[4];    // texel offset of level L in each channel's plane, at [L / 4][L % 4]
    int discTop;                 // T: the coarsest level stored (any pixel's top level at most)
    int discWindow;              // k: windows of (4k + 2)^2 nodes per level
    int deepLayers;              // hbao: (front, back) layers per texel of the deep input, 0: none
    int discPolygon;             // 1: exact polygon form factor for the 8 pixels around the receiver

    int discBlend;               // 1: smooth open weights between levels; 0: hard windows
    int discVisibility;          // 1: weight each element by channel 7, its first-pass AO
    int discUnion;               // 1: occlusion as a union over hemisphere bins; 0: the plain sum
    int discStride;              // floats between one channel's plane of the pyramid and the next

    int discWideFrom;            // from this level up nodes open within k + 1 (discWindowAt)
    int hbaoRuns;                // hbao: 1: samples applied per occluder run (core/hbao_plan.h)
    int pad10;
    int pad11;
};

// KernelParams::hbaoModel: what a sample hides (core/hbao_plan.h, HbaoModel, says what each is).
CONST_GLOBAL int HBAO_HORIZON = 0;
CONST_GLOBAL int HBAO_FIXED_THICKNESS = 1;
CONST_GLOBAL int HBAO_MEASURED_THICKNESS = 2;
CONST_GLOBAL int HBAO_DEEP = 3;
// A blur's weights also fall within BLUR_REACH r_max across the surface (KernelParams::blurReach),
// so that where R spans a few pixels (distant geometry) a blur of a few pixels does not average
// over most of R: the methods whose table entry says so (MethodInfo::blurWithinReach: HBAO,
// SSDO). SSAO's, discs' and rtao's blur keeps pixels alone: their noise is what it removes
// (docs/notes/2026-11-29-blur-reach.md).
CONST_GLOBAL float BLUR_REACH = 0.25f;
// SSDO's GI is blurred SSDO_GI_BLUR_SCALE times as wide as its DO and AO.
CONST_GLOBAL int SSDO_GI_BLUR_SCALE = 3;
// SSDO's N samples are N / SSDO_STEPS directions of SSDO_STEPS points: SSDO_STEPS - 1 stratified
// ones give DO its linear falloff (a point at a uniform distance finds a surface at distance t
// with probability 1 - t / r_max). Each pixel of the M x M interleave block takes one direction
// at least, so N runs as max(N / SSDO_STEPS, M^2) directions (the host says when that differs).
CONST_GLOBAL int SSDO_STEPS = 4;

// KernelParams::hbaoBorder: past the buffer's edge open sky, the edge texel's depth, or its
// tangent plane continued (core/hbao_plan.h, HbaoBorder).
CONST_GLOBAL int HBAO_BORDER_OPEN = 0;
CONST_GLOBAL int HBAO_BORDER_CLAMP = 1;
CONST_GLOBAL int HBAO_BORDER_TANGENT = 2;
