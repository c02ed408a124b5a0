// Orbit camera -> image plane (see camera.h for the conventions).
#include "renderer/camera.h"

#include "renderer/errors.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace renderer {

ImagePlane makeImagePlane(const Camera& camera, glm::dvec3 centre, double radius, int width, int height) {
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
    return p;
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
