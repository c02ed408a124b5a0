// One voxel's footprint laid open (footprint_inspection.h).
#include "renderer/oracle/footprint_inspection.h"

#include <cmath>

namespace renderer {

Ellipse ellipseOf(const glm::dmat2& v, double sigmas) {
    // Eigenvalues of the symmetric [[a, b], [b, c]]: (a + c) / 2 +- sqrt(((a - c) / 2)^2 + b^2).
    const double a = v[0][0], b = v[1][0], c = v[1][1];
    const double mean = 0.5 * (a + c), spread = std::hypot(0.5 * (a - c), b);
    Ellipse e;
    e.semiAxesPx = sigmas * glm::sqrt(glm::max(glm::dvec2(mean + spread, mean - spread), 0.0));
    e.angleRad = 0.5 * std::atan2(2.0 * b, a - c);
    return e;
}

std::optional<FootprintInspection> inspectFootprint(const SplatScene& scene, const ImagePlane& plane,
                                                    const SplatSettings& settings, glm::ivec3 voxel) {
    const uint32_t index = uint32_t((size_t(voxel.z) * size_t(scene.dims.y) + size_t(voxel.y)) * size_t(scene.dims.x) +
                                    size_t(voxel.x));
    const glm::dvec3 u = plane.toCamera(scene.positionOf(index));
    const glm::dmat3 varCamera = kernelVarianceCamera(settings.kernelScale * scene.spacing, plane.viewFromObject);
    // As splatGeometry: no splat for a kernel whose cutoff ellipsoid reaches the near plane.
    if (!plane.orthographic && !(u.z - settings.cutoffSigmas * std::sqrt(varCamera[2][2]) > plane.nearDepth))
        return std::nullopt;
    FootprintInspection out;
    out.voxel = voxel;
    out.depth = u.z;
    out.cutoffSigmas = settings.cutoffSigmas;
    const Footprint reconstruction =
        projectKernel(u, varCamera, plane.fPx, FilterMode::Reconstruction, glm::dmat2(1.0), plane.orthographic);
    out.centrePx = plane.centrePx + reconstruction.offsetPx;
    out.jacobianDet = reconstruction.jacobianDet;
    out.reconstruction = reconstruction.variancePx;
    out.lowPass =
        projectKernel(u, varCamera, plane.fPx, FilterMode::LowPass, glm::dmat2(1.0), plane.orthographic).variancePx;
    out.ewa = projectKernel(u, varCamera, plane.fPx, FilterMode::Ewa, glm::dmat2(1.0), plane.orthographic).variancePx;
    out.thresholds = adaptiveThresholds(scene.spacing, plane, settings);
    const double pxPerUnit = plane.pxPerUnit(u.z);
    out.kernelPx = glm::dvec2(out.thresholds.sigmaMin, out.thresholds.sigmaMax) * pxPerUnit;
    out.filterDepths = filterDepths(out.thresholds, plane);
    out.patchFilter = settings.filter != FilterMode::Adaptive
                          ? settings.filter
                          : classifyPatch(scene, plane, out.thresholds, settings.patchSize,
                                          chooseTraversal(plane).axis, index);
    return out;
}

} // namespace renderer
