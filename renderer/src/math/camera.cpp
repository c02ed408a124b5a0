// Orbit camera -> image plane (see camera.h for the conventions).
#include "renderer/math/camera.h"

#include "renderer/errors.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

namespace renderer {

ImagePlane makeImagePlane(const Camera& camera, glm::dvec3 centre, double radius, int width, int height,
                          const glm::dmat3& axes) {
    const double deg = std::numbers::pi / 180.0;
    const double az = camera.azimuthDeg * deg;
    const double el = std::clamp(camera.elevationDeg, -89.9, 89.9) * deg;
    const double r = std::max(radius, 1e-9);
    // Orbit frame (e1, e2, up); for up = +z it is (x, y, z).
    const glm::dvec3 up = glm::length(camera.up) > 0 ? glm::normalize(camera.up) : glm::dvec3(0, 0, 1);
    const glm::dvec3 ref = std::abs(up.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
    const glm::dvec3 e1 = glm::normalize(ref - up * glm::dot(ref, up));
    const glm::dvec3 e2 = glm::cross(up, e1);
    const glm::dvec3 toEye = std::cos(el) * (std::cos(az) * e1 + std::sin(az) * e2) + std::sin(el) * up;

    // Camera axes: u0 right, u1 down (image rows grow downwards), u2 forward.
    const glm::dvec3 forward = -toEye;
    const glm::dvec3 right = glm::normalize(glm::cross(forward, up));
    const glm::dvec3 down = glm::cross(forward, right);

    ImagePlane p;
    p.width = width;
    p.height = height;
    p.tanHalfFovY = std::tan(0.5 * camera.fovYDeg * deg);
    p.fPx = 0.5 * height / p.tanHalfFovY;
    p.centrePx = glm::dvec2(0.5 * width, 0.5 * height);
    // Rows of W are the camera axes in object space.
    p.viewFromObject = glm::transpose(glm::dmat3(right, down, forward));
    const double eyeDistance = camera.distance * r;
    p.orthographic = camera.orthographic;
    // Orthographic: the view height equals the perspective one at the orbit centre's depth.
    if (p.orthographic) p.fPx /= eyeDistance;
    // Panning moves eye and orbit centre together along the image plane, by pixels at the centre depth.
    const double objectPerPx = p.orthographic ? 1.0 / p.fPx : eyeDistance / p.fPx;
    const glm::dvec3 pan = (right * camera.panPx.x + down * camera.panPx.y) * objectPerPx;
    const glm::dvec3 eye = centre + toEye * eyeDistance - pan;
    p.translation = -(p.viewFromObject * eye);
    // Near plane: a fixed fraction of the volume's size, so the guard scales with the scene.
    p.nearDepth = 1e-2 * r;
    p.viewDirObject = forward;
    if (axes != glm::dmat3(1.0)) {   // world = centre + axes (object - centre)
        p.translation += p.viewFromObject * (centre - axes * centre);
        p.viewFromObject = p.viewFromObject * axes;
        p.viewDirObject = glm::transpose(axes) * forward;
    }
    return p;
}

Camera frameView(Camera camera, glm::dvec3 centre, double radius, std::span<const glm::dvec3> points, int width,
                 int height, double margin, double minDistance, double maxDistance, const glm::dmat3& axes) {
    if (points.empty() || width <= 0 || height <= 0) return camera;
    camera.distance = 1.0;
    camera.panPx = glm::dvec2(0.0);
    const ImagePlane p = makeImagePlane(camera, centre, radius, width, height, axes);   // W and the near plane
    const double r = std::max(radius, 1e-9), tanY = p.tanHalfFovY;
    const glm::dvec2 t = (1.0 - margin) * tanY * glm::dvec2(double(width) / height, 1.0);
    // Relative to the orbit centre a point is v = W (q - centre); at eye distance D, panned by s (object
    // units in the image plane), its camera position is (v.xy + s, v.z + D). It is inside when
    // |v.x + s.x| <= t.x (v.z + D) (orthographic, whose view is as wide as the perspective one at the
    // centre's depth: t.x D), and likewise for y. Some s satisfies every point's bounds once
    // max(v.x - t.x v.z) - min(v.x + t.x v.z) <= 2 t.x D: the least D.
    const auto depthTerm = [&](const glm::dvec3& v) { return camera.orthographic ? 0.0 : v.z; };
    std::vector<glm::dvec3> view;
    view.reserve(points.size());
    glm::dvec2 hiLo(-std::numeric_limits<double>::infinity()), loHi(std::numeric_limits<double>::infinity());
    double eye = minDistance * r;
    for (const glm::dvec3& q : points) {
        const glm::dvec3 v = view.emplace_back(p.viewFromObject * (q - centre));
        hiLo = glm::max(hiLo, glm::dvec2(v) - t * depthTerm(v));
        loHi = glm::min(loHi, glm::dvec2(v) + t * depthTerm(v));
        eye = std::max(eye, 2.0 * p.nearDepth - v.z);
    }
    eye = std::min(std::max({eye, (hiLo.x - loHi.x) / (2.0 * t.x), (hiLo.y - loHi.y) / (2.0 * t.y)}), maxDistance * r);
    // s centres the points' image: the sum of their extreme positions, (v + s) / depth, grows with s, from
    // <= 0 at s = -max v to >= 0 at s = -min v. Bisection finds its zero; that s also leaves the most room
    // on both sides, so it is inside the bounds above wherever any s is.
    glm::dvec2 shift(0.0);
    for (int a = 0; a < 2; ++a) {
        double lo = std::numeric_limits<double>::infinity(), hi = -lo;
        for (const glm::dvec3& v : view) lo = std::min(lo, -v[a]), hi = std::max(hi, -v[a]);
        for (int i = 0; i < 64; ++i) {
            const double mid = 0.5 * (lo + hi);
            double most = -std::numeric_limits<double>::infinity(), least = -most;
            for (const glm::dvec3& v : view) {
                const double at = (v[a] + mid) / (camera.orthographic ? 1.0 : v.z + eye);
                most = std::max(most, at), least = std::min(least, at);
            }
            (most + least > 0.0 ? hi : lo) = mid;
        }
        shift[a] = 0.5 * (lo + hi);
    }
    camera.distance = eye / r;
    // makeImagePlane pans by panPx pixels of (eye distance tan(fov/2)) / (height / 2) object units each.
    camera.panPx = eye > 0.0 ? shift * (0.5 * height) / (eye * tanY) : glm::dvec2(0.0);
    return camera;
}

glm::dvec3 axisFromName(const std::string& name) {
    const std::string n = (!name.empty() && name[0] == '+') ? name.substr(1) : name;
    const bool neg = !n.empty() && n[0] == '-';
    const std::string a = neg ? n.substr(1) : n;
    glm::dvec3 v(0.0);
    if (a == "x") v.x = 1;
    else if (a == "y") v.y = 1;
    else if (a == "z") v.z = 1;
    else throw RenderError("up axis '" + name + "': expected x, y, z, -x, -y or -z");
    return neg ? -v : v;
}

} // namespace renderer
