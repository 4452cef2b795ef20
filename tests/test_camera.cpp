// Camera maths: projection conventions, EXR/V-Ray header conversions, sidecars,
// and the camera fit from a world-position pass (synthetic and real renders).
#include "core/camera.h"
#include "core/camera_fit.h"
#include "base/error.h"
#include "io/camera_sources.h"
#include "support/scratch.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFloatAttribute.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfIntAttribute.h>
#include <OpenEXR/ImfMatrixAttribute.h>
#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <random>

using namespace obscura;

namespace {

constexpr double kPi = 3.14159265358979323846;

// A camera at `eye` looking at `target`, OpenGL convention.
glm::dmat4 lookAtCameraToWorld(glm::dvec3 eye, glm::dvec3 target, glm::dvec3 up = {0, 1, 0}) {
    return glm::inverse(glm::lookAt(eye, target, up));
}

void expectMatNear(const glm::dmat4& a, const glm::dmat4& b, double tol) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) EXPECT_NEAR(a[c][r], b[c][r], tol) << "row " << r << " col " << c;
}

ConstPlane cview(const Image& img) { return img.view(); }

template <class M>
M toImath(const glm::dmat4& g) {
    M m;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) m[i][j] = (typename M::BaseType)g[i][j];
    return m;
}

// ---------------------------------------------------------------- analytic scenes

// Nearest hit of a ray with: the ground y = 0 (|x|,|z| < 8), a box [-1,1]x[0,2]x[-1,1],
// and a back wall z = -5 (|x| < 8, 0 < y < 6). Infinity if nothing is hit.
double traceScene(glm::dvec3 o, glm::dvec3 d, bool groundOnly) {
    double best = INFINITY;
    auto consider = [&](double t, bool inside) {
        if (t > 1e-9 && t < best && inside) best = t;
    };
    if (d.y != 0) {
        const double t = -o.y / d.y;
        const glm::dvec3 p = o + t * d;
        consider(t, std::fabs(p.x) < 8 && std::fabs(p.z) < 8);
    }
    if (groundOnly) return best;
    if (d.z != 0) {
        const double t = (-5 - o.z) / d.z;
        const glm::dvec3 p = o + t * d;
        consider(t, std::fabs(p.x) < 8 && p.y > 0 && p.y < 6);
    }
    const glm::dvec3 lo(-1, 0, -1), hi(1, 2, 1);
    double tNear = -INFINITY, tFar = INFINITY;
    for (int k = 0; k < 3; ++k) {
        if (d[k] == 0) {
            if (o[k] < lo[k] || o[k] > hi[k]) return best;
            continue;
        }
        double t0 = (lo[k] - o[k]) / d[k], t1 = (hi[k] - o[k]) / d[k];
        if (t0 > t1) std::swap(t0, t1);
        tNear = std::max(tNear, t0);
        tFar = std::min(tFar, t1);
    }
    if (tNear <= tFar) consider(tNear, true);
    return best;
}

// World-position pass (float, like a render), sky = 0, through pixel centres.
Image renderPosition(const Camera& cam, int W, int H, bool groundOnly) {
    Image img(W, H, 3, 0.0f);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            glm::dvec3 o, d;
            if (cam.projection == Projection::Perspective) {
                o = glm::dvec3(cam.cameraToWorld[3]);
                d = glm::dvec3(cam.cameraToWorld * glm::dvec4(cam.unproject(x + 0.5, y + 0.5, 1.0, false), 1.0)) - o;
            } else {
                o = glm::dvec3(cam.cameraToWorld * glm::dvec4(cam.unproject(x + 0.5, y + 0.5, 0.0, false), 1.0));
                d = -glm::dvec3(cam.cameraToWorld[2]);
            }
            const double t = traceScene(o, d, groundOnly);
            if (!std::isfinite(t)) continue;
            const glm::dvec3 p = o + t * d;
            float* px = img.at(x, y);
            px[0] = (float)p.x, px[1] = (float)p.y, px[2] = (float)p.z;
        }
    return img;
}

// The camera's viewing ray direction and eye, which every fit must reproduce
// (an orthographic eye is only defined up to its distance along the view axis).
void expectSameCamera(const Camera& fit, const Camera& truth, int W, double tolAngle, double tolPos, double tolF) {
    EXPECT_EQ(fit.projection, truth.projection) << fit.source;
    EXPECT_NEAR(fit.fx / truth.fx, 1.0, tolF) << fit.source;
    EXPECT_NEAR(fit.fy / truth.fy, 1.0, tolF);
    EXPECT_NEAR(fit.cx, truth.cx, 1e-6 * W);
    EXPECT_NEAR(fit.cy, truth.cy, 1e-6 * W);
    for (int axis = 0; axis < 3; ++axis)
        EXPECT_NEAR(glm::dot(glm::dvec3(fit.cameraToWorld[axis]), glm::dvec3(truth.cameraToWorld[axis])), 1.0,
                    tolAngle * tolAngle) << "axis " << axis;
    const glm::dvec3 eyeFit(fit.cameraToWorld[3]), eyeTruth(truth.cameraToWorld[3]);
    if (truth.projection == Projection::Perspective) {
        EXPECT_NEAR(glm::distance(eyeFit, eyeTruth), 0.0, tolPos);
    } else {  // compare the eye's position across the view axis only
        const glm::dvec3 viewAxis(truth.cameraToWorld[2]);
        const glm::dvec3 d = eyeFit - eyeTruth;
        EXPECT_NEAR(glm::length(d - glm::dot(d, viewAxis) * viewAxis), 0.0, tolPos);
    }
}

// ---------------------------------------------------------------- real samples

struct Sample {
    Image position;
    Box2i dataWindow, display;
    double pixelAspect = 1;
    nlohmann::json sidecar;
};

Sample loadSample(const std::string& name) {
    const std::string dir = OBSCURA_TEST_DATA_DIR;
    Imf::InputFile file((dir + "/" + name + ".exr").c_str());
    const Imath::Box2i dw = file.header().dataWindow(), disp = file.header().displayWindow();
    Sample s;
    s.dataWindow = {dw.min.x - disp.min.x, dw.min.y - disp.min.y, dw.max.x - disp.min.x + 1, dw.max.y - disp.min.y + 1};
    s.display = {0, 0, disp.max.x - disp.min.x + 1, disp.max.y - disp.min.y + 1};
    s.pixelAspect = file.header().pixelAspectRatio();
    const int W = dw.max.x - dw.min.x + 1, H = dw.max.y - dw.min.y + 1;
    s.position = Image(W, H, 3);
    Imf::FrameBuffer fb;
    const char* channels[3] = {"ViewLayer.Position.X", "ViewLayer.Position.Y", "ViewLayer.Position.Z"};
    for (int c = 0; c < 3; ++c) {
        char* base = (char*)(s.position.pixels.data() + c) - (std::ptrdiff_t(dw.min.y) * W + dw.min.x) * 3 * sizeof(float);
        fb.insert(channels[c], Imf::Slice(Imf::FLOAT, base, 3 * sizeof(float), 3 * sizeof(float) * W));
    }
    file.setFrameBuffer(fb);
    file.readPixels(dw.min.y, dw.max.y);
    std::ifstream(dir + "/" + name + ".json") >> s.sidecar;
    return s;
}

void checkRealSample(const std::string& name) {
    const Sample s = loadSample(name);
    const Camera fit = fitCameraFromPosition(s.position.view(), s.dataWindow, s.display, s.pixelAspect);
    const Camera truth = cameraFromSidecar(std::string(OBSCURA_TEST_DATA_DIR) + "/" + name + ".json", s.display, s.pixelAspect);
    const double fovFit = fit.horizontalFovRad(s.display.width()), fovTruth = s.sidecar["horizontal_fov_rad"].get<double>();
    double worstRotation = 0, eyeError = glm::distance(glm::dvec3(fit.cameraToWorld[3]), glm::dvec3(truth.cameraToWorld[3]));
    for (int axis = 0; axis < 3; ++axis)
        worstRotation = std::max(worstRotation, std::asin(std::min(1.0, glm::length(glm::cross(
                                                    glm::dvec3(fit.cameraToWorld[axis]), glm::dvec3(truth.cameraToWorld[axis]))))));
    std::printf("[ sample   ] %s: %s\n             fov %.6f rad (truth %.6f, diff %.2e), axes within %.2e rad, eye off by %.2e\n",
                name.c_str(), fit.source.c_str(), fovFit, fovTruth, fovFit - fovTruth, worstRotation, eyeError);
    EXPECT_EQ(fit.projection, Projection::Perspective);
    // Measured: rms < 5e-4 px, fov within 2e-7 rad, axes within 3e-6 rad, eye within 6e-6 units.
    EXPECT_LT(fit.fitResidualPx, 0.01);
    EXPECT_NEAR(fovFit, fovTruth, 2e-6);
    EXPECT_LT(worstRotation, 3e-5);
    EXPECT_LT(eyeError, 1e-4);
    const double rmsTruth = reprojectionRmsPx(truth, s.position.view(), s.dataWindow);
    std::printf("             sidecar camera reprojects the position pass with rms %.3g px (best 90%%)\n", rmsTruth);
    EXPECT_LT(rmsTruth, 0.1);
}

} // namespace

// ---------------------------------------------------------------- conventions

TEST(CameraModel, FovAndFocalLength) {
    const Camera c = Camera::perspectiveFromFov(kPi / 2, 200, 100);
    EXPECT_DOUBLE_EQ(c.fx, 100.0);  // (W/2) / tan(45 deg)
    EXPECT_DOUBLE_EQ(c.fy, 100.0);
    EXPECT_DOUBLE_EQ(c.cx, 100.0);
    EXPECT_DOUBLE_EQ(c.cy, 50.0);
    EXPECT_NEAR(c.horizontalFovRad(200), kPi / 2, 1e-15);
    const Camera wide = Camera::perspectiveFromFov(1.0, 320, 240, 2.0);  // pixels twice as wide as tall
    EXPECT_DOUBLE_EQ(wide.fy, 2.0 * wide.fx);
    EXPECT_NEAR(wide.horizontalFovRad(320), 1.0, 1e-14);
    const Camera o = Camera::orthographic(4.0, 400, 300);
    EXPECT_DOUBLE_EQ(o.fx, 100.0);
    EXPECT_DOUBLE_EQ(o.orthoWidth(400), 4.0);
    EXPECT_EQ(o.horizontalFovRad(400), 0.0);
}

TEST(CameraModel, ProjectConventions) {
    const Camera c = Camera::perspectiveFromFov(kPi / 2, 200, 100);
    // A point up and to the right, in front (-Z), lands right of and above the centre (y down).
    const glm::dvec3 p = c.project({1, 1, -2});
    EXPECT_DOUBLE_EQ(p.x, 150.0);
    EXPECT_NEAR(p.y, 0.0, 1e-12);
    EXPECT_DOUBLE_EQ(p.z, 2.0);
    const Camera o = Camera::orthographic(2.0, 200, 100);
    const glm::dvec3 q = o.project({1, -0.5, -3});
    EXPECT_DOUBLE_EQ(q.x, 200.0);
    EXPECT_DOUBLE_EQ(q.y, 100.0);
    EXPECT_DOUBLE_EQ(q.z, 3.0);
}

TEST(CameraModel, UnprojectRoundTrip) {
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> px(0, 320), py(0, 240), depth(0.1, 100);
    const Camera cams[2] = {Camera::perspectiveFromFov(1.1, 320, 240, 1.3), Camera::orthographic(7.0, 320, 240, 0.8)};
    for (const Camera& c : cams)
        for (bool radial : {false, true})
            for (int i = 0; i < 200; ++i) {
                const double x = px(rng), y = py(rng), d = depth(rng);
                const glm::dvec3 p = c.unproject(x, y, d, radial);
                const glm::dvec3 back = c.project(p);
                EXPECT_NEAR(back.x, x, 1e-9);
                EXPECT_NEAR(back.y, y, 1e-9);
                const bool eye = c.projection == Projection::Perspective && radial;
                EXPECT_NEAR(eye ? glm::length(p) : back.z, d, 1e-9);
            }
}

// ---------------------------------------------------------------- header conventions

TEST(CameraHeader, OpenExrStandardWorldToCameraAndNdc) {
    const int W = 320, H = 200;
    const Box2i display{0, 0, W, H};
    Camera truth = Camera::perspectiveFromFov(0.9, W, H);
    truth.cameraToWorld = lookAtCameraToWorld({3, 2, 6}, {0, 0.5, 0});
    // The standard matrices: left-handed camera looking down +Z; NDC (0,0)-(1,1) over the display, y down.
    const glm::dmat4 exrWorldToCamera = glWorldToCameraToExr(truth.worldToCamera());
    glm::dmat4 cameraToNdc(0.0);  // column-vector: h = M (X, Y, Z, 1), ndc = h.xy / h.w
    cameraToNdc[0][0] = truth.fx / W;
    cameraToNdc[2][0] = truth.cx / W;
    cameraToNdc[1][1] = -truth.fy / H;
    cameraToNdc[2][1] = truth.cy / H;
    cameraToNdc[2][2] = 1;
    cameraToNdc[2][3] = 1;  // w = Z
    Imf::Header h(W, H);
    h.insert("worldToCamera", Imf::M44fAttribute(toImath<Imath::M44f>(exrWorldToCamera)));
    h.insert("worldToNDC", Imf::M44fAttribute(toImath<Imath::M44f>(cameraToNdc * exrWorldToCamera)));

    // Imath's p * M on the stored matrix must agree with glm's M * p on the copy.
    const Imath::V3f pw(0.3f, 0.7f, -0.2f);
    Imath::V3f pc;
    h.typedAttribute<Imf::M44fAttribute>("worldToCamera").value().multVecMatrix(pw, pc);
    const glm::dvec4 pg = exrWorldToCamera * glm::dvec4(0.3, 0.7, -0.2, 1);
    EXPECT_NEAR(pc.x, pg.x, 1e-5);
    EXPECT_NEAR(pc.z, pg.z, 1e-5);
    EXPECT_GT(pc.z, 0) << "a point the camera looks at has positive standard-camera Z";

    const auto cam = cameraFromHeader(h, display);
    ASSERT_TRUE(cam);
    EXPECT_EQ(cam->projection, Projection::Perspective);
    EXPECT_NEAR(cam->fx, truth.fx, 1e-3);
    EXPECT_NEAR(cam->fy, truth.fy, 1e-3);
    EXPECT_NEAR(cam->cx, truth.cx, 1e-3);
    EXPECT_NEAR(cam->cy, truth.cy, 1e-3);
    EXPECT_TRUE(cam->hasPose);
    expectMatNear(cam->cameraToWorld, truth.cameraToWorld, 1e-5);
    EXPECT_NE(cam->source.find("worldToNDC"), std::string::npos);
}

TEST(CameraHeader, MinusZCameraWithScreenMatrix) {
    // Houdini and Arnold write an OpenGL-style worldToCamera (-Z forward) and a screen-space
    // matrix (x in [-1, 1] across the width, y up); the projection reveals the direction.
    const int W = 300, H = 300;
    Camera truth = Camera::perspectiveFromFov(0.7, W, H);
    truth.cameraToWorld = lookAtCameraToWorld({-2, 5, 4}, {1, 0, -1});
    glm::dmat4 cameraToScreen(0.0);
    cameraToScreen[0][0] = truth.fx / (W / 2.0);
    cameraToScreen[1][1] = truth.fy / (W / 2.0);
    cameraToScreen[2][3] = -1;  // w = -Z
    Imf::Header h(W, H);
    h.insert("worldToCamera", Imf::M44fAttribute(toImath<Imath::M44f>(truth.worldToCamera())));
    h.insert("worldToScreen", Imf::M44fAttribute(toImath<Imath::M44f>(cameraToScreen * truth.worldToCamera())));
    const auto cam = cameraFromHeader(h, {0, 0, W, H});
    ASSERT_TRUE(cam);
    EXPECT_NEAR(cam->fx, truth.fx, 1e-3);
    EXPECT_NEAR(cam->cx, truth.cx, 1e-3);
    EXPECT_NEAR(cam->cy, truth.cy, 1e-3);
    expectMatNear(cam->cameraToWorld, truth.cameraToWorld, 1e-5);
}

TEST(CameraHeader, WorldToCameraAloneIsPoseOnly) {
    Camera truth;
    truth.cameraToWorld = lookAtCameraToWorld({1, 1, 1}, {0, 0, 0});
    Imf::Header h(64, 64);
    h.insert("worldToCamera", Imf::M44fAttribute(toImath<Imath::M44f>(glWorldToCameraToExr(truth.worldToCamera()))));
    const auto cam = cameraFromHeader(h, {0, 0, 64, 64});
    ASSERT_TRUE(cam);
    EXPECT_FALSE(cam->valid());
    EXPECT_TRUE(cam->hasPose);
    expectMatNear(cam->cameraToWorld, truth.cameraToWorld, 1e-6);
}

TEST(CameraHeader, VRayCameraTransform) {
    const int W = 400, H = 250;
    const glm::dmat4 cameraToWorld = lookAtCameraToWorld({10, -20, 5}, {0, 0, 1}, {0, 0, 1});  // Z-up world
    Imath::M44f m;  // as V-Ray writes it: translation in the last column
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) m[r][c] = (float)cameraToWorld[c][r];
    Imf::Header h(W, H);
    h.insert("cameraTransform", Imf::M44fAttribute(m));
    h.insert("cameraFov", Imf::FloatAttribute(60.0f));
    h.insert("cameraProjection", Imf::IntAttribute(0));
    const auto cam = cameraFromHeader(h, {0, 0, W, H});
    ASSERT_TRUE(cam);
    EXPECT_NEAR(cam->horizontalFovRad(W), 60.0 * kPi / 180, 1e-6);
    expectMatNear(cam->cameraToWorld, cameraToWorld, 1e-5);
    h.insert("cameraProjection", Imf::IntAttribute(1));  // spherical: not a pinhole
    EXPECT_FALSE(cameraFromHeader(h, {0, 0, W, H}));
}

// ---------------------------------------------------------------- fit, synthetic

TEST(CameraFit, RecoversPerspectiveCamera) {
    const int W = 320, H = 240;
    Camera truth = Camera::perspectiveFromFov(0.9, W, H);
    truth.cameraToWorld = lookAtCameraToWorld({4, 3, 7}, {0, 0.8, -1});
    const Image pos = renderPosition(truth, W, H, false);
    const Camera fit = fitCameraFromPosition(cview(pos), {0, 0, W, H}, {0, 0, W, H});
    expectSameCamera(fit, truth, W, 1e-6, 1e-5, 1e-6);
    EXPECT_LT(fit.fitResidualPx, 1e-3);
    EXPECT_TRUE(fit.hasPose);
    EXPECT_EQ(fit.source.rfind("fit:position (perspective", 0), 0u) << fit.source;
}

TEST(CameraFit, RecoversOrthographicCamera) {
    const int W = 256, H = 256;
    Camera truth = Camera::orthographic(9.0, W, H);
    truth.cameraToWorld = lookAtCameraToWorld({6, 5, 8}, {0, 1, 0});
    const Image pos = renderPosition(truth, W, H, false);
    const Camera fit = fitCameraFromPosition(cview(pos), {0, 0, W, H}, {0, 0, W, H});
    expectSameCamera(fit, truth, W, 1e-6, 1e-5, 1e-6);
    EXPECT_LT(fit.fitResidualPx, 1e-3);
    // The fitted eye sits in front of everything it sees.
    const glm::dmat4 w2c = fit.worldToCamera();
    for (int y = 0; y < H; y += 16)
        for (int x = 0; x < W; x += 16)
            if (const float* p = pos.at(x, y); p[0] != 0) {
                EXPECT_LT((w2c * glm::dvec4(p[0], p[1], p[2], 1)).z, 0);
            }
}

TEST(CameraFit, PlanarScenesWithCentredPrincipalPoint) {
    const int W = 300, H = 200;
    Camera persp = Camera::perspectiveFromFov(1.0, W, H);
    persp.cameraToWorld = lookAtCameraToWorld({1, 4, 6}, {0, 0, 0});
    const Camera fitP = fitCameraFromPosition(cview(renderPosition(persp, W, H, true)), {0, 0, W, H}, {0, 0, W, H});
    expectSameCamera(fitP, persp, W, 1e-5, 1e-4, 1e-5);

    Camera ortho = Camera::orthographic(6.0, W, H);
    ortho.cameraToWorld = lookAtCameraToWorld({2, 5, 3}, {0, 0, 0});
    const Camera fitO = fitCameraFromPosition(cview(renderPosition(ortho, W, H, true)), {0, 0, W, H}, {0, 0, W, H});
    // A plane seen orthographically has a mirror-twin view; both reproject exactly.
    EXPECT_EQ(fitO.projection, Projection::Orthographic);
    EXPECT_NEAR(fitO.fx, ortho.fx, 1e-4 * ortho.fx);
    EXPECT_LT(fitO.fitResidualPx, 1e-3);
}

TEST(CameraFit, IgnoresBlendedOutliersAndUsesDataWindow) {
    const int W = 320, H = 240;
    Camera truth = Camera::perspectiveFromFov(0.8, W, H);
    truth.cameraToWorld = lookAtCameraToWorld({-3, 2.5, 6}, {0.5, 0.5, -1});
    Image pos = renderPosition(truth, W, H, false);
    // 5% of pixels blended towards the origin, like sky-edge pixels of a filtered render.
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(0, 1);
    for (std::size_t i = 0; i < pos.pixels.size() / 3; ++i)
        if (u(rng) < 0.05)
            for (int c = 0; c < 3; ++c) pos.pixels[i * 3 + c] *= (float)u(rng);
    // Crop to a data window that does not start at the display origin.
    const Box2i crop{40, 30, 300, 220};
    ConstPlane view = cview(pos);
    view.data = pos.at(crop.x0, crop.y0);
    view.width = crop.width();
    view.height = crop.height();
    const Camera fit = fitCameraFromPosition(view, crop, {0, 0, W, H});
    expectSameCamera(fit, truth, W, 1e-5, 1e-4, 1e-5);
}

TEST(CameraFit, ShiftedLensAndNonSquarePixels) {
    const int W = 320, H = 240;
    Camera truth = Camera::perspectiveFromFov(0.9, W, H, 1.25);
    truth.cx += 24;  // a lens shift: the fit must free the principal point
    truth.cy -= 10;
    truth.cameraToWorld = lookAtCameraToWorld({4, 3, 7}, {0, 0.8, -1});
    const Camera fit = fitCameraFromPosition(cview(renderPosition(truth, W, H, false)), {0, 0, W, H}, {0, 0, W, H}, 1.25);
    EXPECT_NEAR(fit.cx, truth.cx, 1e-3);
    EXPECT_NEAR(fit.cy, truth.cy, 1e-3);
    EXPECT_NEAR(fit.fy / fit.fx, 1.25, 1e-12);
    EXPECT_NEAR(fit.fx, truth.fx, 1e-3);
    EXPECT_LT(fit.fitResidualPx, 1e-3);
    expectMatNear(fit.cameraToWorld, truth.cameraToWorld, 1e-5);
}

TEST(CameraFit, RefusesRandomPositions) {
    const int W = 200, H = 150;
    Image pos(W, H, 3);
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(-5, 5);
    for (float& v : pos.pixels) v = u(rng);
    try {
        fitCameraFromPosition(cview(pos), {0, 0, W, H}, {0, 0, W, H});
        FAIL() << "a random position pass must not give a camera";
    } catch (const Error& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find("rms"), std::string::npos) << msg;
        EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    }
}

TEST(CameraFit, RefusesTooFewPoints) {
    Image pos(64, 64, 3, 0.0f);  // all sky
    for (int i = 0; i < 10; ++i) pos.at(i, i)[0] = 1.0f + i;
    EXPECT_THROW(fitCameraFromPosition(cview(pos), {0, 0, 64, 64}, {0, 0, 64, 64}), Error);
}

// ---------------------------------------------------------------- fit, real renders

TEST(CameraFitReal, Room) { checkRealSample("room"); }
TEST(CameraFitReal, Columns) { checkRealSample("columns"); }

// ---------------------------------------------------------------- sources

TEST(CameraSources, SidecarAndFinding) {
    const std::string dir = OBSCURA_TEST_DATA_DIR;
    EXPECT_EQ(findSidecar(dir + "/room.exr"), dir + "/room.json");
    EXPECT_EQ(findSidecar(dir + "/nonexistent.exr"), "");
    const Camera c = cameraFromSidecar(dir + "/columns.json", {0, 0, 320, 240}, 1.0);
    EXPECT_NEAR(c.horizontalFovRad(320), 1.1426749229431152, 1e-12);
    EXPECT_DOUBLE_EQ(c.cameraToWorld[3][0], 4.5);  // translation column of the rows
    EXPECT_DOUBLE_EQ(c.cameraToWorld[3][1], -6.0);
    EXPECT_DOUBLE_EQ(c.cameraToWorld[0][1], 0.3060092329978943);  // row 1, column 0
    EXPECT_THROW(cameraFromSidecar(dir + "/columns.json", {0, 0, 320, 320}, 1.0), Error);  // wrong frame
    EXPECT_THROW(cameraFromSidecar(dir + "/missing.json", {0, 0, 320, 240}, 1.0), Error);
}

// A sidecar that gives only an ortho_width is orthographic without saying "projection"; one that
// gives both lenses and no projection stays perspective, as before.
TEST(CameraSources, ASidecarsLensSaysItsProjection) {
    const std::filesystem::path dir = obscura::test::testDir("sidecar_lens");
    const std::string rows = R"("camera_to_world": [[1,0,0,0],[0,1,0,0],[0,0,1,5],[0,0,0,1]])";
    const std::string ortho = (dir / "ortho.json").string(), both = (dir / "both.json").string();
    std::ofstream(ortho) << "{" << rows << R"(, "ortho_width": 8})";
    std::ofstream(both) << "{" << rows << R"(, "ortho_width": 8, "horizontal_fov_rad": 0.9})";
    const Camera o = cameraFromSidecar(ortho, {0, 0, 320, 240}, 1.0);
    EXPECT_EQ(o.projection, Projection::Orthographic);
    EXPECT_DOUBLE_EQ(o.orthoWidth(320), 8.0);
    EXPECT_DOUBLE_EQ(o.cameraToWorld[3][2], 5.0);
    const Camera p = cameraFromSidecar(both, {0, 0, 320, 240}, 1.0);
    EXPECT_EQ(p.projection, Projection::Perspective);
    EXPECT_NEAR(p.horizontalFovRad(320), 0.9, 1e-12);
}

// A report written as NAME.json beside NAME.exr (--report shot.json) sits where a sidecar would:
// the next run on NAME.exr does not take it for its camera.
TEST(CameraSources, AReportBesideTheInputIsNoSidecar) {
    const std::filesystem::path dir = obscura::test::testDir("sidecars");
    const std::string exr = (dir / "shot.exr").string(), json = (dir / "shot.json").string();
    std::ofstream(json) << R"({"obscura": "0.1.0", "settings": {}, "recipe": {}, "timings_s": {}, "camera": {}})";
    EXPECT_EQ(findSidecar(exr), "");
    std::ofstream(json) << std::ifstream(std::string(OBSCURA_TEST_DATA_DIR) + "/room.json").rdbuf();
    EXPECT_EQ(findSidecar(exr), json);
}

TEST(CameraSources, ResolveOrder) {
    const int W = 160, H = 120;
    const Box2i frame{0, 0, W, H};
    Camera truth = Camera::perspectiveFromFov(0.9, W, H);
    truth.cameraToWorld = lookAtCameraToWorld({4, 3, 7}, {0, 0.8, -1});
    const Image pos = renderPosition(truth, W, H, false);

    CameraRequest none;
    EXPECT_THROW(resolveCamera(none, nullptr, ConstPlane{}, frame, frame, 1.0), Error);
    try {
        resolveCamera(none, nullptr, ConstPlane{}, frame, frame, 1.0);
    } catch (const Error& e) {
        EXPECT_EQ(std::string(e.what()).rfind("no camera:", 0), 0u);
    }

    const Camera fit = resolveCamera(none, nullptr, cview(pos), frame, frame, 1.0);
    EXPECT_EQ(fit.source.rfind("fit:position", 0), 0u) << fit.source;

    CameraRequest fov;
    fov.fovDeg = 50;  // lens from the flag, pose from the fit
    const Camera combined = resolveCamera(fov, nullptr, cview(pos), frame, frame, 1.0);
    EXPECT_NEAR(combined.horizontalFovRad(W), 50 * kPi / 180, 1e-12);
    EXPECT_TRUE(combined.hasPose);
    expectMatNear(combined.cameraToWorld, truth.cameraToWorld, 1e-5);
    const Camera lensOnly = resolveCamera(fov, nullptr, ConstPlane{}, frame, frame, 1.0);
    EXPECT_FALSE(lensOnly.hasPose);

    CameraRequest full = fov;
    std::array<double, 16> rows{};
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) rows[r * 4 + c] = truth.cameraToWorld[c][r];
    full.cameraToWorld = rows;
    const Camera flags = resolveCamera(full, nullptr, cview(pos), frame, frame, 1.0);
    EXPECT_EQ(flags.source.rfind("flags", 0), 0u);
    expectMatNear(flags.cameraToWorld, truth.cameraToWorld, 1e-12);

    // A header camera that contradicts the position pass loses to the fit.
    Camera wrong = truth;
    wrong.cameraToWorld = lookAtCameraToWorld({5, 3, 7}, {0, 0.8, -1});
    Imf::Header h(W, H);
    h.insert("worldToCamera", Imf::M44fAttribute(toImath<Imath::M44f>(glWorldToCameraToExr(wrong.worldToCamera()))));
    h.insert("fieldOfViewHorizontal", Imf::FloatAttribute(float(0.9 * 180 / kPi)));
    const Camera fromHeader = resolveCamera(none, &h, ConstPlane{}, frame, frame, 1.0);
    EXPECT_EQ(fromHeader.source.rfind("header:", 0), 0u) << fromHeader.source;
    const Camera checked = resolveCamera(none, &h, cview(pos), frame, frame, 1.0);
    EXPECT_NE(checked.source.find("disagrees"), std::string::npos) << checked.source;
    expectMatNear(checked.cameraToWorld, truth.cameraToWorld, 1e-5);
}
