// render --detail-levels (see far_view_level.h).
#include "far_view_level.h"

#include "renderer/math/classifier.h"
#include "renderer/model/detail_levels.h"

#include <cstdio>

void drawFarViewFromLevel(renderer::SplatScene& scene, renderer::SplatSettings& settings,
                          const renderer::Volume& volume, const renderer::ImagePlane& plane, int maxLevel) {
    renderer::DetailLevel d = renderer::chooseDetailLevel(volume, scene, plane, settings, maxLevel);
    const double thresholdPx = renderer::adaptiveThresholds(scene.spacing, plane, settings).lowPassBelowPx;
    if (d.level < d.pixelLevel)
        std::fprintf(stderr, "note: level %d would change the optical mass by %.1f %% (more than %.0f %%: averaging "
                             "changed what the TF shows); ", d.level + 1, 100.0 * d.refusedMassChange,
                     100.0 * renderer::kMaxMassChange);
    else
        std::fprintf(stderr, "note: ");
    if (d.level == 0) {
        std::fprintf(stderr, "full resolution: kernels of %.2f px at the nearest voxel, level 1's would be %.2f "
                             "(low-pass below %.2f px)\n", d.kernelPx, 2.0 * d.kernelPx, thresholdPx);
        return;
    }
    std::fprintf(stderr, "level %d (%d x %d x %d voxels): kernels of %.2f px at the nearest voxel, under the "
                         "low-pass threshold %.2f px; optical mass changed %.2f %%\n",
                 d.level, d.scene->dims.x, d.scene->dims.y, d.scene->dims.z, d.kernelPx, thresholdPx,
                 100.0 * d.massChange);
    scene = std::move(*d.scene);
    settings.density *= d.densityScale;
}
