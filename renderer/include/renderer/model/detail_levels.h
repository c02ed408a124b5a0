// Levels of detail for far views (#38 item 5): the volume halved k times (halfResolution, each coarse
// voxel the mean of its 2x2x2 block) and drawn with kernels 2^k times as wide, chosen only where those
// kernels still take the low-pass filter everywhere in the view, so that the pixel's filter, not the
// kernel, shapes every footprint. A pixel-size test cannot see what averaging values before
// classification loses (a one-voxel skin under a sharp TF leaves the TF's band), so a level must also
// keep the scene's optical mass.
#pragma once
#include "renderer/math/camera.h"
#include "renderer/model/splat_scene.h"
#include "renderer/model/splat_settings.h"
#include "renderer/model/volume.h"

#include <optional>

namespace renderer {

// The largest kernel sigma of level `level` (kernelScale x spacing x 2^level), in pixels at the
// volume's nearest voxel (orthographic: anywhere). Infinity where the near plane cuts the volume.
double levelKernelPx(glm::ivec3 dims, glm::dvec3 origin, glm::dvec3 spacing, const ImagePlane& plane,
                     const SplatSettings& s, int level);

// The coarsest level in 0..maxLevel whose kernels stay under the low-pass threshold r_h / c_max
// (adaptiveThresholds) at the nearest voxel. Hysteresis, given last frame's level `previous`: a level
// coarser than it is entered only below threshold / (1 + h), and it and finer levels are kept up to
// threshold x (1 + h), so a view near a threshold does not switch level frame by frame.
int coarsestLowPassLevel(glm::ivec3 dims, glm::dvec3 origin, glm::dvec3 spacing, const ImagePlane& plane,
                         const SplatSettings& s, int maxLevel, int previous = 0, double hysteresis = 0.0);

// How far `coarse`'s optical mass departs from `fine`'s, both classified with the same TF: each voxel's
// opacity times its volume, summed (the mass), and that weighted by each colour channel (what it emits);
// the largest change of the four sums over fine's mass (0 where neither shows anything, 1 where only
// coarse does). The same density gives both the same extinction per unit length (densityFor), so equal
// sums mean the same total extinction and emission.
double opticalMassChange(const SplatScene& fine, const SplatScene& coarse);

// The most optical mass a level may lose or gain. Measured at level 1 (each coarse voxel the mean of 8,
// docs/performance.md, "Levels of detail far away"): bonsai 0.5 %, engine 2.1 %, the 256^3 phantom 2.0 %,
// and headsq, whose skin is one or two voxels thick under ct-skin-bone, 6.0 %.
constexpr double kMaxMassChange = 0.03;

struct DetailLevel {
    int level = 0;               // 0: the full volume; k: halved k times
    int pixelLevel = 0;          // what the pixel-size test allowed, before the optical mass test
    double kernelPx = 0.0;       // the drawn level's largest kernel sigma at the nearest voxel, px
    double massChange = 0.0;     // the drawn level's opticalMassChange (0 at level 0)
    double refusedMassChange = 0.0;   // the next coarser level's, where the mass test refused it (else 0)
    std::optional<SplatScene> scene;   // the level's scene, classified as the full one (none at level 0)
    double densityScale = 1.0;   // multiplies SplatSettings::density for the level (densityFor)
};

// The level a far view draws: coarsestLowPassLevel, then finer while a level changes the optical mass
// by more than kMaxMassChange. `full` is `volume`'s scene; the levels are classified with its TF and
// window and get gradients when it has them. Builds only the levels it tests.
DetailLevel chooseDetailLevel(const Volume& volume, const SplatScene& full, const ImagePlane& plane,
                              const SplatSettings& s, int maxLevel = 2, int previous = 0, double hysteresis = 0.0);

} // namespace renderer
