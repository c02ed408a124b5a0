// The head phantom at small sizes: its tissues take the volumes the anatomy gives them, the noise has the
// asked sigma and depends on the seed only, the skull is closed, and a size over the memory budget is
// refused. And saveNrrd writes what loadNrrd reads back.
#include "renderer/errors.h"
#include "renderer/io/nrrd_writer.h"
#include "renderer/io/volume_io.h"
#include "renderer/model/phantom.h"
#include "scoped_env.h"
#include "test_paths.h"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <deque>
#include <filesystem>
#include <optional>
#include <string>

using namespace renderer;
namespace fs = std::filesystem;

namespace {

Volume phantom(glm::ivec3 dims, double noiseHu = 20.0, uint32_t seed = 1) {
    PhantomOptions o;
    o.dims = dims;
    o.noiseHu = noiseHu;
    o.seed = seed;
    return makePhantom(o);
}

std::string sizeName(glm::ivec3 d) {
    return std::to_string(d.x) + "x" + std::to_string(d.y) + "x" + std::to_string(d.z);
}

// Bone at or above this: halfway from soft tissue to the skull's mean (2 + 2 mm at 1400, 3 mm at 700:
// 1100 HU), so a partial voxel counts as bone when about half of it is.
constexpr float kBoneThresholdHu = 570.0f;

struct TissueFractions {
    double air = 0, skin = 0, soft = 0, bone = 0; // soft: soft tissue, CSF and brain
};

// Voxels by value, each class boundary halfway between the tissues on either side (air -1000 | skin -70 |
// soft tissue 40 | bone), so that a partial voxel goes to the tissue filling most of it and the counts
// approach the tissues' volumes.
TissueFractions fractionsByValue(const Volume& v) {
    TissueFractions f;
    for (size_t i = 0; i < v.values.size(); ++i) {
        const float hu = v.values[i];
        if (hu < -535.0f)
            ++f.air;
        else if (hu < -15.0f)
            ++f.skin;
        else if (hu < kBoneThresholdHu)
            ++f.soft;
        else
            ++f.bone;
    }
    const double n = double(v.voxelCount());
    return {f.air / n, f.skin / n, f.soft / n, f.bone / n};
}

// The voxel nearest a position in mm (the phantom's (0,0,0) is mid-cube).
glm::ivec3 voxelAt(const Volume& v, glm::dvec3 posMm) {
    return glm::clamp(glm::ivec3(glm::round((posMm - v.origin) / v.spacing)), glm::ivec3(0), v.dims - 1);
}

// The middle of the head (phantom.cpp: the head's centre is 18 mm above the cube's).
constexpr glm::dvec3 kHeadCentreMm{0.0, 0.0, 18.0};

} // namespace

// Volumes of the anatomy's shapes, by Monte Carlo over the 256 mm cube (400k points, +-0.1%): air 79.9%,
// skin 1.66% (2.5 mm), soft tissue with CSF and brain 15.2%, skull 3.24% (7 mm). At 4 to 8 mm voxels the
// skin is thinner than a voxel, so its thresholds also take voxels that mix air and soft tissue; the
// ranges allow for that and for the skull's partial voxels. Measured: 64^3 air 79.9%, skin 1.98%, soft
// 14.6%, bone 3.51%; 48x40x32 79.8%, 2.09%, 15.2%, 2.90%.
TEST(Phantom, TissueFractionsAreTheVolumesOfTheAnatomy) {
    for (glm::ivec3 dims : {glm::ivec3(64), glm::ivec3(48, 40, 32)}) {
        const TissueFractions f = fractionsByValue(phantom(dims));
        SCOPED_TRACE(sizeName(dims) + ": air " + std::to_string(f.air) + ", skin " + std::to_string(f.skin) +
                     ", soft " + std::to_string(f.soft) + ", bone " + std::to_string(f.bone));
        EXPECT_NEAR(f.air, 0.799, 0.01);
        EXPECT_NEAR(f.skin, 0.0166, 0.006);
        EXPECT_NEAR(f.soft, 0.152, 0.012);
        EXPECT_NEAR(f.bone, 0.0324, 0.006);
    }
}

// The noise-free phantom is the known signal: the noisy one minus it is the noise alone. Over brain
// voxels (noise-free value exactly 30 HU), the mean stays within 4 standard errors of 30, and the noise's
// measured sigma within 10% of the option, as it does in the air.
TEST(Phantom, BrainMeanAndNoiseSigmaMatchTheOptions) {
    const glm::ivec3 dims(64);
    const Volume clean = phantom(dims, 0.0);
    for (double sigma : {20.0, 50.0}) {
        const Volume noisy = phantom(dims, sigma);
        for (double tissue : {kPhantomBrainHu, kPhantomAirHu}) {
            double n = 0, sum = 0, sumSq = 0;
            for (size_t i = 0; i < clean.values.size(); ++i)
                if (clean.values[i] == float(tissue)) {
                    const double noise = double(noisy.values[i]) - tissue;
                    n += 1;
                    sum += noise;
                    sumSq += noise * noise;
                }
            SCOPED_TRACE("sigma " + std::to_string(sigma) + ", tissue " + std::to_string(tissue) + " HU, " +
                         std::to_string(int(n)) + " voxels");
            ASSERT_GT(n, 10000.0) << "the tissue fills a good part of a 64^3 head";
            const double mean = sum / n, measuredSigma = std::sqrt(sumSq / n - mean * mean);
            EXPECT_NEAR(mean, 0.0, 4.0 * sigma / std::sqrt(n)) << "mean " << tissue + mean << " HU";
            EXPECT_NEAR(measuredSigma, sigma, 0.1 * sigma);
        }
    }
    // Noise-free, the brain's middle is the brain's value and every tissue is whole HU within its range.
    EXPECT_EQ(clean.at(32, 32, 32), float(kPhantomBrainHu));
    EXPECT_EQ(clean.range.lo, float(kPhantomAirHu));
    // At 4 mm no voxel is all cortical bone (its tables are 2 mm): the skull's voxels mix it with diploe.
    EXPECT_LT(clean.range.hi, float(kPhantomCorticalBoneHu));
    EXPECT_GT(clean.range.hi, float(kPhantomDiploeHu));
}

TEST(Phantom, TheSameSeedGivesTheSameVoxelsOnAnyThreadCount) {
    const glm::ivec3 dims(48, 40, 32);
    const Volume a = phantom(dims, 20.0, 7);
    Volume oneThread;
    tbb::task_arena(1).execute([&] { oneThread = phantom(dims, 20.0, 7); });
    EXPECT_TRUE(a.values == oneThread.values)
        << "the noise of a voxel must not depend on which thread made it";
    EXPECT_EQ(a.type, VoxelType::I16);
    EXPECT_EQ(a.dims, dims);
    EXPECT_EQ(a.spacing, glm::dvec3(256.0 / 48, 256.0 / 40, 256.0 / 32));

    // Another seed: other noise on the same anatomy. Two draws of N(0, 20) rounded to whole HU agree
    // about 1.4% of the time.
    const Volume b = phantom(dims, 20.0, 8);
    size_t same = 0;
    double meanDifference = 0;
    for (size_t i = 0; i < a.values.size(); ++i) {
        same += a.values[i] == b.values[i];
        meanDifference += double(a.values[i]) - double(b.values[i]);
    }
    EXPECT_LT(double(same) / double(a.voxelCount()), 0.05);
    EXPECT_NEAR(meanDifference / double(a.voxelCount()), 0.0, 0.5) << "the same anatomy under both";
}

// Each ray from the middle of the head to the cube's faces along the six axis directions meets the skull,
// and a flood fill of the voxels below it from there (6-connected) never reaches a face: no hole at all.
// The skull is 7 mm thick (mean 1100 HU); an 8 mm voxel of the 48x40x32 phantom can hold half of it at
// worst, about 500 HU, so the threshold is 250 HU: over soft tissue and the noise by 10 sigma.
TEST(Phantom, TheSkullIsAClosedShell) {
    constexpr float kSkullHu = 250.0f;
    for (glm::ivec3 dims : {glm::ivec3(64), glm::ivec3(48, 40, 32)}) {
        SCOPED_TRACE(sizeName(dims));
        const Volume v = phantom(dims);
        const glm::ivec3 start = voxelAt(v, kHeadCentreMm);
        ASSERT_LT(v.at(start.x, start.y, start.z), kSkullHu);
        for (int axis = 0; axis < 3; ++axis)
            for (int step : {-1, 1}) {
                bool skull = false;
                for (glm::ivec3 p = start; p[axis] >= 0 && p[axis] < dims[axis]; p[axis] += step)
                    skull = skull || v.at(p.x, p.y, p.z) >= kSkullHu;
                EXPECT_TRUE(skull) << "no skull from the head's middle along axis " << axis << ", step "
                                   << step;
            }

        std::vector<char> seen(v.voxelCount(), 0);
        std::deque<glm::ivec3> queue{start};
        seen[v.index(start.x, start.y, start.z)] = 1;
        size_t inside = 0;
        bool reachedAFace = false;
        while (!queue.empty()) {
            const glm::ivec3 p = queue.front();
            queue.pop_front();
            ++inside;
            for (int axis = 0; axis < 3; ++axis)
                for (int step : {-1, 1}) {
                    glm::ivec3 q = p;
                    q[axis] += step;
                    if (q[axis] < 0 || q[axis] >= dims[axis]) {
                        reachedAFace = true;
                        continue;
                    }
                    char& s = seen[v.index(q.x, q.y, q.z)];
                    if (s || v.at(q.x, q.y, q.z) >= kSkullHu) continue;
                    s = 1;
                    queue.push_back(q);
                }
        }
        EXPECT_FALSE(reachedAFace) << "the skull has a hole: the inside reached a face of the cube";
        // Within the skull: an ellipsoid of 61 x 79 x 87 mm semi-axes, 10.5% of the cube, less the partial
        // voxels over 250 HU at its inner surface (measured 9.65% at 64^3, 9.15% at 48x40x32).
        EXPECT_NEAR(double(inside) / double(v.voxelCount()), 0.105, 0.02);
    }
}

TEST(Phantom, ASizeOverTheMemoryBudgetIsRefusedBeforeAllocating) {
    std::optional<testing_support::ScopedEnv> budget(std::in_place, "SPLATLAB_MEMORY_BUDGET_MB", "1");
    EXPECT_EQ(phantom(glm::ivec3(64, 64, 128)).voxelCount(), size_t(1) << 19) << "64^2 x 128 int16 are 1 MiB: within it";
    const auto t0 = std::chrono::steady_clock::now();
    std::string error;
    try {
        phantom(glm::ivec3(4096, 4096, 16)); // 512 MiB of int16: would take seconds to fill
    } catch (const RenderError& e) {
        error = e.what();
    }
    budget.reset();
    EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::milliseconds(100));
    EXPECT_NE(error.find("size 4096 x 4096 x 16 voxels need 512 MiB as int16"), std::string::npos) << error;
    EXPECT_NE(error.find("memory budget of 1 MiB"), std::string::npos) << error;

    EXPECT_THROW(phantom(glm::ivec3(64, 0, 64)), RenderError);
    EXPECT_THROW(phantom(glm::ivec3(64), -1.0), RenderError);
}

// Every layout the writer has (detached or attached, raw or gzip) loads back as it was.
TEST(NrrdWriter, WritesWhatLoadNrrdReadsBack) {
    const Volume v = phantom(glm::ivec3(48, 40, 32));
    const fs::path dir = testing_support::testOutputDir("phantom");
    for (const char* name : {"detached.nhdr", "attached.nrrd"})
        for (bool gzip : {false, true}) {
            const fs::path path = dir / name;
            SCOPED_TRACE(path.string() + (gzip ? " gzip" : " raw"));
            const auto files = saveNrrd(v, path, {.gzip = gzip});
            ASSERT_EQ(files.size(), path.extension() == ".nhdr" ? 2u : 1u);
            if (files.size() == 2) {
                EXPECT_EQ(files[1].filename(), gzip ? "detached.raw.gz" : "detached.raw");
            }
            const Volume back = loadVolume(path);
            EXPECT_EQ(back.dims, v.dims);
            EXPECT_EQ(back.type, VoxelType::I16);
            EXPECT_EQ(back.spacing, v.spacing);
            EXPECT_EQ(back.origin, v.origin);
            EXPECT_EQ(back.directions, glm::dmat3(1.0));
            EXPECT_TRUE(back.values == v.values);
        }
}

TEST(NrrdWriter, AValueTheTypeCannotHoldIsRefusedAndNothingIsWritten) {
    Volume v = phantom(glm::ivec3(16), 0.0);
    v.values.floats()[v.index(3, 4, 5)] = 40000.0f;
    const fs::path path = testing_support::testOutputDir("phantom") / "too_large.nrrd";
    fs::remove(path);
    try {
        saveNrrd(v, path);
        ADD_FAILURE() << "40000 does not fit int16";
    } catch (const RenderError& e) {
        EXPECT_NE(std::string(e.what()).find("voxel (3, 4, 5) is 40000"), std::string::npos) << e.what();
    }
    EXPECT_FALSE(fs::exists(path));
}
