// The named hard cases of EWA_NOTES ("Hard cases for numerical stability"): scenes where projection,
// filtering or compositing is most likely to break. Tests render each in every filter mode and check
// it against the ground truth; `splatlab accuracy` renders them larger for docs/accuracy.md.
#pragma once
#include "renderer/math/camera.h"
#include "renderer/model/splat_settings.h"
#include "renderer/model/transfer_function.h"
#include "renderer/model/volume.h"

#include <string>
#include <vector>

namespace renderer {

struct HardCase {
    std::string name;          // short, file-name safe
    std::string what;          // one line: what it stresses
    Volume volume;
    TransferFunction tf;
    Camera camera;
    SplatSettings settings;    // filter and compositing are set by the caller
    int width = 48, height = 48;
};

// scale 1: test size (small volumes, 48x48 images); larger scales grow volumes and images for reports.
// `only` names one case to build (none if no case has that name); empty builds them all.
std::vector<HardCase> hardCases(int scale = 1, const std::string& only = {});

// The near-eye views of issue 33's audit, where the near layer (near_layer.h) carries the image: the
// camera on a voxel centre inside a volume ("voxel-centre", a 9^3 radial ramp, the eye 1e-3 bounding
// radii from its centre voxel), and inside an optically thin ball ("thin-ball", radius 4 voxels, opacity
// 0.15, the eye 2 voxels from its centre). 48x48 images, 60 degree field of view.
std::vector<HardCase> nearEyeCases();

} // namespace renderer
