#include "support/scenes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace obscura::test {

namespace {
Camera lookAt(glm::dvec3 eye, glm::dvec3 target) {
    Camera c;
    const glm::dvec3 back = glm::normalize(eye - target);               // camera +Z
    const glm::dvec3 right = glm::normalize(glm::cross(glm::dvec3(0, 1, 0), back));
    const glm::dvec3 up = glm::cross(back, right);
    c.cameraToWorld = glm::dmat4(glm::dvec4(right, 0), glm::dvec4(up, 0), glm::dvec4(back, 0), glm::dvec4(eye, 1));
    c.hasPose = true;
    return c;
}
} // namespace

Camera lookAtPerspective(glm::dvec3 eye, glm::dvec3 target, double hfovRad, int width, int height) {
    Camera c = lookAt(eye, target);
    c.projection = Projection::Perspective;
    c.fx = c.fy = 0.5 * width / std::tan(0.5 * hfovRad);
    c.cx = 0.5 * width;
    c.cy = 0.5 * height;
    c.source = "test";
    return c;
}

Camera lookAtOrthographic(glm::dvec3 eye, glm::dvec3 target, double orthoWidth, int width, int height) {
    Camera c = lookAt(eye, target);
    c.projection = Projection::Orthographic;
    c.fx = c.fy = width / orthoWidth;
    c.cx = 0.5 * width;
    c.cy = 0.5 * height;
    c.source = "test";
    return c;
}

void addBox(std::vector<Rect>& rects, glm::dvec3 lo, glm::dvec3 hi) {
    const glm::dvec3 d = hi - lo;
    const glm::dvec3 ex(d.x, 0, 0), ey(0, d.y, 0), ez(0, 0, d.z);
    rects.push_back({lo, ex, ey});
    rects.push_back({lo + ez, ex, ey});
    rects.push_back({lo, ey, ez});
    rects.push_back({lo + ex, ey, ez});
    rects.push_back({lo, ex, ez});
    rects.push_back({lo + ey, ex, ez});
}

std::vector<Rect> studioScene() {
    const double L = 6.0;
    std::vector<Rect> r = {Rect{glm::dvec3(-L, 0, -L), glm::dvec3(2 * L, 0, 0), glm::dvec3(0, 0, 2 * L)},  // floor
                           Rect{glm::dvec3(-L, 0, -L), glm::dvec3(2 * L, 0, 0), glm::dvec3(0, 3, 0)},      // back wall
                           Rect{glm::dvec3(-L, 0, -L), glm::dvec3(0, 3, 0), glm::dvec3(0, 0, 2 * L)}};     // left wall
    addBox(r, glm::dvec3(-3.0, 0, -3.0), glm::dvec3(-1.5, 1.2, -1.5));
    addBox(r, glm::dvec3(0.5, 0, -1.0), glm::dvec3(1.5, 0.6, 0.5));
    addBox(r, glm::dvec3(-1.0, 0, 1.0), glm::dvec3(-0.6, 2.0, 1.4));  // a thin pillar
    return r;
}

Camera studioCamera(int width, int height) {
    return lookAtPerspective(glm::dvec3(3.5, 3.0, 6.5), glm::dvec3(-1.0, 0.6, -1.0), 65.0 * M_PI / 180, width, height);
}

std::vector<Rect> benchRoomScene() {
    using glm::dvec3;
    std::vector<Rect> rects;
    rects.push_back({dvec3(-6, 0, -8), dvec3(14, 0, 0), dvec3(0, 0, 16)});  // floor, ends at x = 8
    rects.push_back({dvec3(-6, 0, -8), dvec3(14, 0, 0), dvec3(0, 3, 0)});   // back wall, 3 high
    rects.push_back({dvec3(-6, 0, -8), dvec3(0, 0, 16), dvec3(0, 4, 0)});   // left wall, 4 high
    addBox(rects, dvec3(-6, 0, -8), dvec3(-4.5, 2.2, -6.5));  // cupboard in the corner
    addBox(rects, dvec3(-2, 0, -3), dvec3(-0.8, 1.2, -1.8));
    addBox(rects, dvec3(-1.9, 1.2, -2.9), dvec3(-1.1, 1.8, -2.1)); // stacked
    addBox(rects, dvec3(0.5, 0, -5), dvec3(2.5, 0.6, -4));
    addBox(rects, dvec3(1.5, 0, -1), dvec3(1.9, 0.4, -0.6));
    addBox(rects, dvec3(-6, 0, -1), dvec3(-5.4, 0.9, 1));     // against the left wall
    addBox(rects, dvec3(3, 0, -7.9), dvec3(4, 2.5, -7));      // pillar at the back wall
    rects.push_back({dvec3(-3.5, 0, 0.5), dvec3(1.2, 0.6, 0), dvec3(0, 0, 1.0)}); // ramp
    return rects;
}

Camera benchRoomCamera(int width, int height) {
    return lookAtPerspective(glm::dvec3(1.5, 2.2, 5.5), glm::dvec3(-1, 0.6, -3), 75.0 * M_PI / 180, width, height);
}

std::vector<Rect> cornerScene() {
    const double L = 1e3;
    return {Rect{glm::dvec3(-L, 0, -L), glm::dvec3(L, 0, 0), glm::dvec3(0, 0, 2 * L)},
            Rect{glm::dvec3(0, 0, -L), glm::dvec3(0, L, 0), glm::dvec3(0, 0, 2 * L)}};
}

Rect planeRect(glm::dvec3 point, glm::dvec3 s, glm::dvec3 t, double half) {
    return Rect{point - half * s - half * t, 2 * half * s, 2 * half * t};
}

OperatorInputs SceneBuffers::inputs() const {
    OperatorInputs in;
    in.displayWindow = display;
    in.dataWindow = data;
    in.depth = depth.view();
    in.normal = normal.view();
    in.position = position.view();
    in.depthKind = depthKind;
    in.normalSpace = normalSpace;
    in.camera = camera;
    return in;
}

bool SceneBuffers::pixelOf(const glm::dvec3& world, int& x, int& y) const {
    const glm::dvec3 pc = glm::dvec3(glm::inverse(camera.cameraToWorld) * glm::dvec4(world, 1.0));
    double px, py;
    if (camera.projection == Projection::Orthographic) {
        px = camera.cx + camera.fx * pc.x;
        py = camera.cy - camera.fy * pc.y;
    } else {
        px = camera.cx + camera.fx * pc.x / -pc.z;
        py = camera.cy - camera.fy * pc.y / -pc.z;
    }
    x = (int)std::floor(px) - data.x0;
    y = (int)std::floor(py) - data.y0;
    return x >= 0 && y >= 0 && x < data.width() && y < data.height();
}

SceneBuffers renderScene(const std::vector<Rect>& rects, const Camera& cam, Box2i display, Box2i data,
                         DepthKind depthKind, float skyDepth) {
    SceneBuffers sb;
    sb.display = display;
    sb.data = data;
    sb.camera = cam;
    sb.depthKind = depthKind;
    const int w = data.width(), h = data.height();
    sb.depth = Image(w, h, 1, skyDepth);
    sb.normal = Image(w, h, 3, 0.0f);
    sb.position = Image(w, h, 3, 0.0f);
    const glm::dmat3 rot(cam.cameraToWorld);
    const glm::dvec3 eye(cam.cameraToWorld[3]);
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const double px = data.x0 + x + 0.5, py = data.y0 + y + 0.5;
            const glm::dvec3 xy((px - cam.cx) / cam.fx, (cam.cy - py) / cam.fy, 0.0);
            glm::dvec3 oCam(0.0), dCam(xy.x, xy.y, -1.0);
            if (cam.projection == Projection::Orthographic) {
                oCam = glm::dvec3(xy.x, xy.y, 0.0);
                dCam = glm::dvec3(0, 0, -1);
            }
            const glm::dvec3 o = eye + rot * oCam, d = rot * dCam;
            double best = std::numeric_limits<double>::infinity();
            glm::dvec3 bestN(0.0);
            for (const Rect& r : rects) {
                const glm::dvec3 n = glm::normalize(glm::cross(r.u, r.v));
                const double denom = glm::dot(n, d);
                if (std::abs(denom) < 1e-15) continue;
                const double t = glm::dot(n, r.origin - o) / denom;
                if (!(t > 1e-9 && t < best)) continue;
                const glm::dvec3 q = o + t * d - r.origin;
                const double a = glm::dot(q, r.u) / glm::dot(r.u, r.u);
                const double b = glm::dot(q, r.v) / glm::dot(r.v, r.v);
                if (a < 0 || a > 1 || b < 0 || b > 1) continue;
                best = t;
                bestN = denom < 0 ? n : -n;
            }
            if (!std::isfinite(best)) continue;
            const glm::dvec3 p = o + best * d;
            // dCam has z = -1, so t is the planar depth; radial depth is the distance to the eye.
            *sb.depth.at(x, y) = (float)(depthKind == DepthKind::Radial ? best * glm::length(dCam) : best);
            float* n = sb.normal.at(x, y);
            float* pos = sb.position.at(x, y);
            for (int c = 0; c < 3; ++c) {
                n[c] = (float)bestN[c];
                pos[c] = (float)p[c];
            }
        }
    }
    return sb;
}

SceneBuffers tiltedPlaneView(double tiltDeg, double dist, bool ortho, int width, int height) {
    const double t = tiltDeg * M_PI / 180;
    const glm::dvec3 eye(0, 0, dist), n(std::sin(t), 0.0, std::cos(t));
    const glm::dvec3 s = glm::normalize(glm::cross(n, glm::dvec3(0, 1, 0))), u = glm::cross(n, s);
    const Camera cam = ortho ? lookAtOrthographic(eye, glm::dvec3(0.0), dist, width, height)
                             : lookAtPerspective(eye, glm::dvec3(0.0), 70.0 * M_PI / 180, width, height);
    return renderScene({planeRect(glm::dvec3(0.0), s, u, 1e7)}, cam, width, height);
}

Camera cornerCamera(int width, int height) {
    return lookAtPerspective(glm::dvec3(-7, 6, 4), glm::dvec3(-0.6, 0, 0), 40.0 * M_PI / 180, width, height);
}

double meanOnCornerLine(const SceneBuffers& sb, const Image& ao, double d) {
    double sum = 0;
    int n = 0;
    for (double z = -1.0; z <= 1.0; z += 0.05) {
        int x, y;
        if (!sb.pixelOf(glm::dvec3(-d, 0, z), x, y)) {
            ADD_FAILURE() << "corner line point (" << -d << ", 0, " << z << ") is outside the frame";
            return std::nan("");
        }
        sum += *ao.at(x, y);
        ++n;
    }
    return sum / n;
}

Settings hbaoSettings(Weighting w, Falloff f, float radius, int dirs, int steps) {
    Settings s;
    s.radius = radius;
    s.directions = dirs;
    s.steps = steps;
    s.weighting = w;
    s.falloff = f;
    s.blur = 0;  // the kernel alone: closed forms and bounds hold per pixel, not for a blurred neighbourhood
    s.threads = 2;
    return s;
}

const CornerCrop& cornerCrop() {
    static const CornerCrop c = [] {
        const int W = 200, H = 150;
        const Camera cam = cornerCamera(W, H);
        const Box2i crop{30, 20, 170, 130};
        return CornerCrop{renderScene(cornerScene(), cam, W, H),
                          renderScene(cornerScene(), cam, Box2i{0, 0, W, H}, crop), crop};
    }();
    return c;
}

double meanEdgeBandError(const SceneBuffers& full, const Image& whole, const Box2i& crop, const Image& cropped, int band,
                         int* pixels) {
    double sum = 0;
    int n = 0;
    for (int y = crop.y0; y < crop.y1; ++y)
        for (int x = crop.x0; x < crop.x1; ++x) {
            const int edge = std::min(std::min(x - crop.x0, crop.x1 - 1 - x), std::min(y - crop.y0, crop.y1 - 1 - y));
            if (edge >= band || *full.depth.at(x, y) >= 1e9f) continue;
            sum += std::abs(*cropped.at(x - crop.x0, y - crop.y0) - *whole.at(x, y));
            ++n;
        }
    *pixels = n;
    return sum / std::max(n, 1);
}

double maxAbsDiff(const Image& a, const Image& b) {
    if (a.pixels.size() != b.pixels.size()) return std::numeric_limits<double>::infinity();
    double m = 0;
    for (size_t i = 0; i < a.pixels.size(); ++i) m = std::max(m, (double)std::abs(a.pixels[i] - b.pixels[i]));
    return m;
}

std::string diffSummary(const Image& a, const Image& b, double tol) {
    if (a.pixels.size() != b.pixels.size()) return "sizes differ";
    size_t over = 0, worst = 0;
    for (size_t i = 0; i < a.pixels.size(); ++i) {
        const double d = std::abs((double)a.pixels[i] - b.pixels[i]);
        over += d > tol;
        if (d > std::abs((double)a.pixels[worst] - b.pixels[worst])) worst = i;
    }
    if (over == 0) return "";
    const size_t texel = worst / (size_t)a.channels;
    std::ostringstream out;
    out << over << " of " << a.pixels.size() << " values over " << tol << "; worst at (" << texel % a.width << ", "
        << texel / a.width << ") channel " << worst % a.channels << ": " << a.pixels[worst] << " vs "
        << b.pixels[worst];
    return out.str();
}

Image deepLayersFromDepth(const Image& depth, const std::vector<std::pair<float, float>>& offsets) {
    Image deep(depth.width, depth.height, 2 * (int)offsets.size());
    for (int y = 0; y < depth.height; ++y)
        for (int x = 0; x < depth.width; ++x) {
            const float z = *depth.at(x, y);
            float* d = deep.at(x, y);
            for (const auto& [front, back] : offsets) {
                *d++ = z + front;
                *d++ = z + back;
            }
        }
    return deep;
}

std::vector<Rect> wellScene(double a, double h) {
    using glm::dvec3;
    const double L = 1e3;
    std::vector<Rect> r = {Rect{dvec3(-a, 0, -a), dvec3(2 * a, 0, 0), dvec3(0, 0, 2 * a)},
                           Rect{dvec3(-a, 0, -a), dvec3(0, h, 0), dvec3(0, 0, 2 * a)},
                           Rect{dvec3(a, 0, -a), dvec3(0, h, 0), dvec3(0, 0, 2 * a)},
                           Rect{dvec3(-a, 0, -a), dvec3(0, h, 0), dvec3(2 * a, 0, 0)},
                           Rect{dvec3(-a, 0, a), dvec3(0, h, 0), dvec3(2 * a, 0, 0)}};
    // The ground around the opening, in four strips.
    r.push_back(Rect{dvec3(-L, h, -L), dvec3(2 * L, 0, 0), dvec3(0, 0, L - a)});
    r.push_back(Rect{dvec3(-L, h, a), dvec3(2 * L, 0, 0), dvec3(0, 0, L - a)});
    r.push_back(Rect{dvec3(-L, h, -a), dvec3(L - a, 0, 0), dvec3(0, 0, 2 * a)});
    r.push_back(Rect{dvec3(a, h, -a), dvec3(L - a, 0, 0), dvec3(0, 0, 2 * a)});
    return r;
}

Image uniformRadiance(const SceneBuffers& sb, float value) {
    Image r(sb.depth.width, sb.depth.height, 3, 0.0f);
    for (size_t i = 0; i < sb.depth.pixels.size(); ++i)
        if (sb.depth.pixels[i] < 1e9f)
            for (int c = 0; c < 3; ++c) r.pixels[3 * i + c] = value;
    return r;
}

} // namespace obscura::test
