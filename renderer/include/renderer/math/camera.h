// The orbit camera and the image plane it defines. Conventions (EWA_NOTES "Spaces"): object t ->
// camera u = W t + d, looking down +u2; pixels p = f_px (u0/u2, u1/u2) + centre, x right, y down,
// pixel (i, j) has its centre at (i + 0.5, j + 0.5).
#pragma once
#include "renderer/math/glm_config.h"

#include <algorithm>
#include <array>
#include <limits>
#include <span>
#include <string>

namespace renderer {

// The camera distances a session or the command line accepts, in bounding-sphere radii.
constexpr double kMinCameraDistance = 1e-3, kMaxCameraDistance = 1e3;

struct Camera {
    double azimuthDeg = 30.0;      // rotation about `up`
    double elevationDeg = 20.0;    // above the plane normal to `up`
    double distance = 2.5;         // from the volume centre, in bounding-sphere radii (kMinCameraDistance..kMaxCameraDistance)
    double fovYDeg = 30.0;         // vertical field of view
    glm::dvec2 panPx{0.0};         // image-plane shift of the orbit centre, pixels at the centre depth
    glm::dvec3 up{0.0, 0.0, 1.0};  // object-space axis shown upwards (CT stacks often need -z)
    bool orthographic = false;     // parallel rays; frames the centre like the perspective view does
};

// "x", "-y", "+z", ...: the object axis a user names for Camera::up. Throws RenderError otherwise.
glm::dvec3 axisFromName(const std::string& name);

// Everything a splat needs to reach pixels, in double precision.
struct ImagePlane {
    int width = 0, height = 0;
    glm::dmat3 viewFromObject{1.0};   // W: rotation, object -> camera axes
    glm::dvec3 translation{0.0};      // d: u = W t + d
    double fPx = 1.0;                 // focal length in pixels: (H/2) / tan(fov/2); orthographic: pixels
                                      // per object unit
    bool orthographic = false;
    double tanHalfFovY = 0.0;         // the perspective spread the adaptive thresholds account for
    glm::dvec2 centrePx{0.0};         // principal point
    double nearDepth = 0.0;           // splats with u2 below this are culled
    glm::dvec3 viewDirObject{0.0};    // unit viewing direction (towards the scene) in object space

    glm::dvec3 toCamera(glm::dvec3 t) const { return viewFromObject * t + translation; }
    // Pixels an object unit spans at camera depth u2, across the view (the adaptive classifier's scale).
    double pxPerUnit(double u2) const { return orthographic ? fPx : fPx / u2; }
    // Camera-space positions of the corner voxel centres of a dims-sized grid at origin/spacing. Every
    // voxel centre lies in their box, so depth (linear) and any convex function of u take their
    // extremes over the voxels among these eight.
    std::array<glm::dvec3, 8> gridCorners(glm::ivec3 dims, glm::dvec3 origin, glm::dvec3 spacing) const {
        std::array<glm::dvec3, 8> u;
        for (int c = 0; c < 8; ++c)
            u[size_t(c)] = toCamera(origin + spacing * glm::dvec3((c & 1) ? dims.x - 1 : 0, (c & 2) ? dims.y - 1 : 0,
                                                                  (c & 4) ? dims.z - 1 : 0));
        return u;
    }
    // The nearest and farthest camera depth of any voxel centre of such a grid (from its corners).
    glm::dvec2 depthRange(glm::ivec3 dims, glm::dvec3 origin, glm::dvec3 spacing) const {
        glm::dvec2 range(std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity());
        for (const glm::dvec3& u : gridCorners(dims, origin, spacing)) range = {std::min(range.x, u.z), std::max(range.y, u.z)};
        return range;
    }
    // Pixel position of a camera-space point (x right, y down).
    glm::dvec2 project(glm::dvec3 u) const {
        return centrePx + (orthographic ? fPx * glm::dvec2(u.x, u.y) : fPx * glm::dvec2(u.x / u.z, u.y / u.z));
    }
};

// `centre` is the orbit centre and `radius` the bounding radius, both in object units. `axes`: the
// object's axes in the world the camera orbits (a rotation, columns x, y, z; SplatScene::axes), turned
// about `centre`, so the plane maps object space through them.
ImagePlane makeImagePlane(const Camera& camera, glm::dvec3 centre, double radius, int width, int height,
                          const glm::dmat3& axes = glm::dmat3(1.0));

// `camera` moved so that every point of `points` (object space) lies inside the image less `margin` of
// each half size, and beyond the near plane: its direction, field of view, up and projection stay; its
// distance (within minDistance .. maxDistance radii) becomes the least that allows it, and its pan centres
// the points' extent. An empty `points` or image changes nothing.
Camera frameView(Camera camera, glm::dvec3 centre, double radius, std::span<const glm::dvec3> points, int width,
                 int height, double margin, double minDistance, double maxDistance,
                 const glm::dmat3& axes = glm::dmat3(1.0));

} // namespace renderer
