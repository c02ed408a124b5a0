// Analytic test volumes: each is a known signal, so tests and the hard-case suite can reason about
// what the image must show.
#pragma once
#include "renderer/model/volume.h"

namespace renderer {

// Values 0 and 1 alternating in cubes of `cell` voxels; the papers' grazing-view scene is
// makeCheckerboard({512, 512, 3}, 8) (000 fig. 8).
Volume makeCheckerboard(glm::ivec3 dims, int cell);
// Concentric shells around the centre: value 1 where the distance to the centre (in voxels) is
// within `thickness`/2 of a multiple of `period`, 0 elsewhere, smoothly ramped over one voxel.
Volume makeSphereShells(int n, double period, double thickness);
// Marschner & Lobb's test signal on [-1,1]^3 (f_M = 6, alpha = 0.25), sampled n^3; values in [0,1].
Volume makeMarschnerLobb(int n);

} // namespace renderer
