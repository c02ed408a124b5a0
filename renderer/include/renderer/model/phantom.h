// A CT-like head phantom in Hounsfield units, as real-size test data for benchmarks and tests: air, skin,
// soft tissue, a closed skull, brain with ventricles and two small inclusions, and Gaussian noise. It only
// builds the Volume; saveNrrd (io/nrrd_writer.h) writes it.
#pragma once
#include "renderer/model/volume.h"

#include <cstdint>

namespace renderer {

// The noise-free value of each tissue, HU. Layer thicknesses are in mm (phantom.cpp), so every size shows
// the same head, sampled more or less finely.
constexpr double kPhantomAirHu = -1000.0;
constexpr double kPhantomSkinHu = -70.0;          // skin and the fat under it, as one thin layer
constexpr double kPhantomSoftTissueHu = 40.0;     // scalp muscle, face and neck
constexpr double kPhantomCorticalBoneHu = 1400.0; // the skull's outer and inner tables
constexpr double kPhantomDiploeHu = 700.0;        // the spongy bone between the tables
constexpr double kPhantomCsfHu = 8.0;             // around the brain and in the ventricles
constexpr double kPhantomBrainHu = 30.0;
constexpr double kPhantomBleedHu = 70.0; // a small haemorrhage (denser than brain)
constexpr double kPhantomCalcificationHu = 200.0;

// The phantom fills a cube this wide on every axis, whatever its dims: spacing is kPhantomFieldMm / dims
// (0.5 mm at 512), so a 512x512x400 phantom has thicker slices, not a shorter head.
constexpr double kPhantomFieldMm = 256.0;

// With the ct-skin-bone preset (`--window -1140,2860`), the skin shows as a surface and the skull inside
// it: the preset's skin band falls on the air-skin edge (-660..-340 HU), its bone ramp on 300..620 HU.
constexpr ValueRange kPhantomSkinBoneWindow{-1140.0f, 2860.0f};

struct PhantomOptions {
    glm::ivec3 dims{512};  // voxels along x (left-right), y (front-back), z (up: the neck at the z = 0 face)
    uint32_t seed = 1;     // the noise's seed; a seed and dims give the same voxels on any thread count
    double noiseHu = 20.0; // standard deviation of the Gaussian noise added to every voxel, HU; 0: none
};

// The phantom as int16 HU (Volume::type I16; values are whole numbers within int16, stored as floats),
// origin at minus half the field so that (0,0,0) is the middle of the cube. Edges are partial-volume
// averages over each voxel's width, as a scanner's are. Runs on every core (oneTBB), a slice per task.
// Throws RenderError, before allocating, for dims under 1 or over kMaxVoxels, noise outside [0, 1000] HU,
// or voxels whose floats exceed volumeMemoryBudget() (naming the size and the budget).
Volume makePhantom(const PhantomOptions& options);

} // namespace renderer
