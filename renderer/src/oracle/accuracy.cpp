// Per-region error and the grazing checkerboard (see accuracy.h).
#include "renderer/oracle/accuracy.h"

#include "renderer/math/classifier.h"
#include "renderer/errors.h"
#include "renderer/model/procedural.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace renderer {

namespace {

// The orbit camera (camera.h) that puts the eye at `eye` looking along (azimuth, pitch): distance and
// pan follow from the orbit centre, the same conventions as makeImagePlane with up = +z.
Camera cameraAt(glm::dvec3 eye, double azimuthDeg, double pitchDeg, double fovYDeg, glm::dvec3 centre,
                double radius, int height) {
    const double deg = std::numbers::pi / 180.0, az = azimuthDeg * deg, el = pitchDeg * deg;
    const glm::dvec3 up(0, 0, 1);
    const glm::dvec3 toEye = std::cos(el) * glm::dvec3(std::cos(az), std::sin(az), 0.0) + std::sin(el) * up;
    const glm::dvec3 right = glm::normalize(glm::cross(-toEye, up)), down = glm::cross(-toEye, right);
    const double fPx = 0.5 * height / std::tan(0.5 * fovYDeg * deg);
    const double distance = glm::dot(eye - centre, toEye);
    const glm::dvec3 pan = (centre + toEye * distance - eye) * (fPx / distance); // in pixels
    Camera c{azimuthDeg, pitchDeg, distance / radius, fovYDeg};
    c.panPx = {glm::dot(pan, right), glm::dot(pan, down)};
    return c;
}

} // namespace

ViewedVolume grazingCheckerboard(int board, int cell, int width, int height) {
    ViewedVolume v;
    v.name = "grazing-checkerboard-" + std::to_string(board);
    v.volume = makeCheckerboard({board, board, 3}, cell);
    // Both values opaque, as in 000 fig. 8 ("all voxels classified as non-transparent").
    v.tf = fromSharedPoints("black-white", {{0.0, {0.0, 0.0, 0.0}, 1.0},
                                            {0.49, {0.0, 0.0, 0.0}, 1.0},
                                            {0.51, {1, 1, 1}, 1.0},
                                            {1.0, {1, 1, 1}, 1.0}});
    // Eye above the middle of the near edge at board / 64 over the top face, looking along +x and
    // pitched 21 degrees down: the top row meets the board just short of its far edge.
    const double b = board;
    const glm::dvec3 eye(0.0, 0.5 * (b - 1), 2.0 + b / 64.0);
    v.camera = cameraAt(eye, 180.0, 21.0, 40.0, v.volume.centre(), v.volume.boundingRadius(), height);
    v.width = width;
    v.height = height;
    return v;
}

ImagePlane cropPlane(const ImagePlane& plane, int x0, int y0, int width, int height) {
    if (x0 < 0 || y0 < 0 || width < 1 || height < 1 || x0 + width > plane.width || y0 + height > plane.height)
        throw RenderError("cropPlane: window " + std::to_string(width) + "x" + std::to_string(height) +
                          " at (" + std::to_string(x0) + ", " + std::to_string(y0) + ") is not inside the " +
                          std::to_string(plane.width) + "x" + std::to_string(plane.height) + " image");
    ImagePlane crop = plane;
    crop.width = width;
    crop.height = height;
    crop.centrePx -= glm::dvec2(x0, y0);
    return crop;
}

const char* regionName(Region r) {
    switch (r) {
    case Region::Empty:
        return "empty";
    case Region::Magnified:
        return "magnified";
    case Region::Transition:
        return "transition";
    case Region::Minified:
        return "minified";
    }
    return "?";
}

std::vector<Region> classifyPixels(const SplatScene& scene, const ImagePlane& plane,
                                   const SplatSettings& settings) {
    const AdaptiveThresholds t = adaptiveThresholds(scene.spacing, plane, settings);
    const glm::dvec3 lo = scene.origin, hi = scene.origin + scene.spacing * glm::dvec3(scene.dims - 1);
    const glm::dmat3 objectFromView = glm::transpose(plane.viewFromObject);
    std::vector<Region> regions(size_t(plane.width) * size_t(plane.height), Region::Empty);
    for (int y = 0; y < plane.height; ++y)
        for (int x = 0; x < plane.width; ++x) {
            // The ray u(s) = origin + s (m, 1) in camera space, so its depth u2 is s itself (orthographic:
            // origin (m, 0), direction (0, 0, 1)).
            const glm::dvec2 m = (glm::dvec2(x + 0.5, y + 0.5) - plane.centrePx) / plane.fPx;
            const glm::dvec3 originCam = plane.orthographic ? glm::dvec3(m, 0.0) : glm::dvec3(0.0);
            const glm::dvec3 dirCam = plane.orthographic ? glm::dvec3(0, 0, 1) : glm::dvec3(m, 1.0);
            const glm::dvec3 o = objectFromView * (originCam - plane.translation),
                             d = objectFromView * dirCam;
            double s0 = plane.nearDepth, s1 = std::numeric_limits<double>::infinity();
            for (int a = 0; a < 3 && s0 <= s1; ++a) { // slab test; a flat box still counts as hit
                if (d[a] == 0.0) {
                    if (o[a] < lo[a] || o[a] > hi[a]) s0 = s1 + 1.0;
                    continue;
                }
                const double ta = (lo[a] - o[a]) / d[a], tb = (hi[a] - o[a]) / d[a];
                s0 = std::max(s0, std::min(ta, tb));
                s1 = std::min(s1, std::max(ta, tb));
            }
            if (!(s0 <= s1)) continue;
            const FilterMode in = classifyDepth(s0, plane, t), out = classifyDepth(s1, plane, t);
            Region r = Region::Transition;
            if (in == out && in == FilterMode::Reconstruction) r = Region::Magnified;
            if (in == out && in == FilterMode::LowPass) r = Region::Minified;
            regions[size_t(y) * size_t(plane.width) + size_t(x)] = r;
        }
    return regions;
}

RegionError regionError(const Image& image, const Image& reference, const std::vector<Region>& regions,
                        Region region) {
    if (image.width != reference.width || image.height != reference.height ||
        regions.size() != size_t(image.width) * size_t(image.height))
        throw RenderError("regionError: image " + std::to_string(image.width) + "x" +
                          std::to_string(image.height) + ", reference " + std::to_string(reference.width) +
                          "x" + std::to_string(reference.height) + " and " + std::to_string(regions.size()) +
                          " region labels must agree");
    RegionError e;
    double sum2 = 0.0, bias = 0.0;
    for (size_t i = 0; i < regions.size(); ++i) {
        if (regions[i] != region) continue;
        ++e.pixels;
        for (size_t c = 0; c < 4; ++c) {
            const double d = double(image.rgba[4 * i + c]) - double(reference.rgba[4 * i + c]);
            sum2 += d * d;
        }
        bias += double(image.rgba[4 * i + 3]) - double(reference.rgba[4 * i + 3]);
    }
    if (e.pixels == 0) return e;
    e.rmse = std::sqrt(sum2 / double(4 * e.pixels));
    e.psnrDb = e.rmse > 0.0 ? -20.0 * std::log10(e.rmse) : std::numeric_limits<double>::infinity();
    e.alphaBias = bias / double(e.pixels);
    return e;
}

} // namespace renderer
