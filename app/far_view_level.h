// `splatlab render --detail-levels N`: a far view drawn from a coarser level of the volume where the
// level's kernels still take the low-pass filter and it keeps the scene's optical mass
// (renderer/model/detail_levels.h). What was chosen, and why a coarser level was not, goes to stderr.
#pragma once
#include "renderer/math/camera.h"
#include "renderer/model/splat_scene.h"
#include "renderer/model/splat_settings.h"
#include "renderer/model/volume.h"

// Replaces `scene` (volume's, classified) by the level chooseDetailLevel picks from at most maxLevel
// halvings, and scales settings.density for it; `plane` stays the full scene's view.
void drawFarViewFromLevel(renderer::SplatScene& scene, renderer::SplatSettings& settings,
                          const renderer::Volume& volume, const renderer::ImagePlane& plane, int maxLevel);
