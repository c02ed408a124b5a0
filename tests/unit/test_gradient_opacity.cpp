// Gradient opacity: the TF's factor on a voxel's opacity by its gradient magnitude, in the file format,
// the scene (per magnitude byte, hidden classes), the CPU oracle and the ground truth.
#include "renderer/errors.h"
#include "renderer/math/metrics.h"
#include "renderer/model/gradients.h"
#include "renderer/model/phantom.h"
#include "renderer/model/procedural.h"
#include "renderer/oracle/ground_truth.h"
#include "renderer/oracle/reference_renderer.h"

#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include <cstdio>

using namespace renderer;

namespace {

TransferFunction opaqueRamp() {
    return fromSharedPoints("ramp", {{0.0, {0.9, 0.8, 0.7}, 0.0},
                                     {0.4, {0.9, 0.8, 0.7}, 0.0},
                                     {0.6, {1.0, 0.9, 0.8}, 0.8},
                                     {1.0, {1.0, 1.0, 1.0}, 1.0}});
}

SplatScene sceneWithGradients(const Volume& volume, const TransferFunction& tf) {
    SplatScene scene = buildSplatScene(volume, tf);
    addGradients(scene, *computeGradients(volume));
    return scene;
}

// A 16^3 grid of 0 with a uniform 10^3 block of 1 in the middle.
Volume uniformBlock() {
    Volume v;
    v.name = "block";
    v.dims = glm::ivec3(16);
    v.values.floats().assign(v.voxelCount(), 0.0f);
    for (int z = 3; z < 13; ++z)
        for (int y = 3; y < 13; ++y)
            for (int x = 3; x < 13; ++x)
                v.values.floats()[v.index(x, y, z)] = 1.0f;
    v.range = {0.0f, 1.0f};
    return v;
}

} // namespace

TEST(GradientOpacity, IsPiecewiseLinearAndOneWithoutPoints) {
    TransferFunction tf;
    EXPECT_EQ(evaluateGradientOpacity(tf, 123.0), 1.0);
    tf.gradientOpacity = {{10.0, 0.0}, {30.0, 1.0}};
    EXPECT_EQ(evaluateGradientOpacity(tf, 0.0), 0.0);
    EXPECT_DOUBLE_EQ(evaluateGradientOpacity(tf, 20.0), 0.5);
    EXPECT_EQ(evaluateGradientOpacity(tf, 1e9), 1.0);
}

TEST(GradientOpacity, RoundTripsThroughTheFileAndOldFilesReadWithout) {
    TransferFunction tf = inDataUnits(opaqueRamp(), {-1000.0f, 2000.0f});
    const std::string oldText = transferFunctionText(tf);
    EXPECT_EQ(oldText.find("gradientOpacity"), std::string::npos)
        << "a TF without it writes what it always did";
    EXPECT_TRUE(
        transferFunctionFromJson(nlohmann::json::parse(oldText), "old.json", "x").gradientOpacity.empty());

    tf.gradientOpacity = {{0.0, 0.0}, {12.5, 0.25}, {80.0, 1.0}};
    const TransferFunction back = transferFunctionFromJson(toJson(tf), "new.json", "x");
    EXPECT_EQ(back, tf);
    // Unsorted points come back sorted; bad ones name the file and the field.
    nlohmann::json j = toJson(tf);
    std::swap(j["gradientOpacity"][0], j["gradientOpacity"][2]);
    EXPECT_EQ(transferFunctionFromJson(j, "f.json", "x").gradientOpacity, tf.gradientOpacity);
    j["gradientOpacity"][1]["magnitude"] = -3.0;
    try {
        transferFunctionFromJson(j, "f.json", "x");
        FAIL() << "a negative magnitude must be refused";
    } catch (const LoadError& e) {
        EXPECT_NE(std::string(e.what()).find("f.json"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("gradientOpacity[1].magnitude"), std::string::npos) << e.what();
    }
    j["gradientOpacity"] = nlohmann::json::array();
    EXPECT_THROW(transferFunctionFromJson(j, "f.json", "x"), LoadError);
}

TEST(GradientOpacity, AFactorOfOneEverywhereGivesTheOldImageExactly) {
    const Volume volume = makeMarschnerLobb(16);
    TransferFunction withOne = opaqueRamp();
    withOne.gradientOpacity = {{0.0, 1.0}};
    const SplatScene plain = sceneWithGradients(volume, opaqueRamp());
    const SplatScene one = sceneWithGradients(volume, withOne);
    ASSERT_EQ(one.gradientFactors.size(), size_t(kGradientBins));
    EXPECT_EQ(one.visibleCount(), plain.visibleCount());
    const ImagePlane plane = makeImagePlane(Camera{30, 20, 2.5, 30.0}, plain.centre, plain.radius, 32, 32);
    for (auto shading : {SplatSettings::Shading::None, SplatSettings::Shading::PerFragment}) {
        SplatSettings s;
        s.shading = shading;
        EXPECT_EQ(renderReference(one, plane, s).rgba, renderReference(plain, plane, s).rgba);
    }
}

TEST(GradientOpacity, WaitsForTheGradientsAndFollowsTfEdits) {
    const Volume volume = uniformBlock();
    TransferFunction tf = opaqueRamp();
    tf.gradientOpacity = {{0.0, 0.0}, {0.05, 1.0}};
    SplatScene scene = buildSplatScene(volume, tf);
    EXPECT_TRUE(scene.gradientFactors.empty()) << "no gradients yet: a factor of 1";
    const size_t block = 10 * 10 * 10;
    EXPECT_EQ(scene.visibleCount(), block);
    addGradients(scene, *computeGradients(volume)); // re-bakes the TF the scene holds
    EXPECT_EQ(scene.gradientFactors.size(), size_t(kGradientBins));
    EXPECT_EQ(scene.visibleCount(), block - 8 * 8 * 8) << "the block's shell only";
    setTransferFunction(scene, opaqueRamp()); // the edit that removes it: no re-read
    EXPECT_TRUE(scene.gradientFactors.empty());
    EXPECT_EQ(scene.visibleCount(), block);
}

TEST(GradientOpacity, AClassZeroAtEveryGradientIsHiddenAndOneVisibleAtSomeStays) {
    const Volume volume = uniformBlock();
    TransferFunction tf = opaqueRamp();
    tf.gradientOpacity = {{0.0, 0.0}};
    SplatScene scene = sceneWithGradients(volume, tf);
    EXPECT_EQ(scene.visibleCount(), 0u);
    for (bool active : activeBuckets(scene.lut))
        EXPECT_FALSE(active);
    EXPECT_EQ(visibleValueRange(scene).hi, 0.0f);

    tf.gradientOpacity = {{0.0, 0.0}, {0.05, 1.0}}; // the block's class: its shell is visible
    setTransferFunction(scene, tf);
    const uint16_t blockClass = scene.classes[volume.index(8, 8, 8)];
    EXPECT_GT(scene.lut[blockClass].a, 0.0f);
    EXPECT_TRUE(activeBuckets(scene.lut)[blockClass >> kBucketShift]);
}

TEST(GradientOpacity, ARampOnLowGradientsRemovesTheInteriorOfAUniformRegion) {
    // The head phantom without noise: brain, soft tissue and bone are uniform inside. A TF showing
    // everything above air, with a factor rising from 0 at zero gradient, keeps the voxels at tissue
    // edges and removes every voxel inside a tissue.
    const Volume volume = makePhantom({.dims = glm::ivec3(40), .noiseHu = 0.0});
    const GradientField field = *computeGradients(volume);
    TransferFunction tf;
    tf.colours = {{-1000.0, {1.0, 1.0, 1.0}}};
    tf.opacities = {{-500.0, 0.0}, {-400.0, 0.5}};
    tf.gradientOpacity = {{0.0, 0.0}, {2.0, 1.0}}; // HU/mm; the phantom's 6.4 mm voxels
    SplatScene scene = buildSplatScene(volume, tf, kPhantomSkinBoneWindow);
    addGradients(scene, field);
    size_t interior = 0, edges = 0;
    for (uint32_t i = 0; i < scene.classes.size(); ++i) {
        if (!(scene.lut[scene.classes[i]].a > 0.0f)) continue;
        const DecodedGradient g = decodeGradient(scene.gradients[i]);
        if (g.magnitude == 0.0) { // uniform neighbourhood: gone
            ++interior;
            EXPECT_EQ(scene.opacityOf(i), 0.0f) << "voxel " << i;
        } else if (g.magnitude * scene.gradientMax >= 2.5) { // an edge: its whole opacity
            ++edges;
            EXPECT_EQ(scene.opacityOf(i), scene.lut[scene.classes[i]].a) << "voxel " << i;
        }
    }
    EXPECT_GT(interior, 1000u) << "the phantom's tissues must have insides";
    EXPECT_GT(edges, 1000u);

    // In the image: the ray through the middle crosses a few edges, not centimetres of tissue.
    const ImagePlane plane = makeImagePlane(Camera{0, 0, 2.5, 30.0}, scene.centre, scene.radius, 16, 16);
    SplatSettings s;
    s.density = 0.05;
    const float faded = renderReference(scene, plane, s).pixel(8, 8)[3];
    TransferFunction without = tf;
    without.gradientOpacity.clear();
    setTransferFunction(scene, without);
    const float solid = renderReference(scene, plane, s).pixel(8, 8)[3];
    std::printf("[ gradient opacity ] centre alpha %.3f without, %.3f with; %zu interior voxels removed\n",
                solid, faded, interior);
    EXPECT_LT(faded, 0.8f * solid);
}

TEST(GradientOpacity, ChangesTheTruthAndTheSplatsFollowIt) {
    const Volume volume = makeMarschnerLobb(16);
    const GradientField field = *computeGradients(volume);
    const GradientStats stats = gradientMagnitudeStats(field);
    TransferFunction tf = opaqueRamp();
    SplatScene plain = buildSplatScene(volume, tf);
    addGradients(plain, field);
    tf.gradientOpacity = {{0.5 * stats.mean, 0.0}, {1.5 * stats.mean, 1.0}};
    SplatScene faded = buildSplatScene(volume, tf);
    addGradients(faded, field);
    const ImagePlane plane = makeImagePlane(Camera{30, 20, 2.5, 30.0}, plain.centre, plain.radius, 32, 32);
    const SplatSettings s;
    const GroundTruthOptions options{.tolerance = 1e-4};
    EXPECT_NE(groundTruthKey(faded, plane, s, options), groundTruthKey(plain, plane, s, options));
    const Image plainTruth = renderGroundTruth(plain, plane, s, options);
    const Image fadedTruth = renderGroundTruth(faded, plane, s, options);
    EXPECT_GT(compareImages(fadedTruth, plainTruth).rmse, 0.02) << "gradient opacity must show in the truth";
    for (FilterMode mode : {FilterMode::Ewa, FilterMode::Adaptive}) {
        SplatSettings m = s;
        m.filter = mode;
        const double plainDb = compareImages(renderReference(plain, plane, m), plainTruth).psnrDb;
        const Image fadedImage = renderReference(faded, plane, m);
        const double fadedDb = compareImages(fadedImage, fadedTruth).psnrDb;
        std::printf(
            "[ gradient opacity ] %s: PSNR %.2f dB against its truth (%.2f dB without gradient opacity; "
            "%.2f dB against the truth without)\n",
            filterModeName(mode), fadedDb, plainDb, compareImages(fadedImage, plainTruth).psnrDb);
        EXPECT_GT(fadedDb, plainDb - 3.0) << filterModeName(mode);
        EXPECT_GT(fadedDb, compareImages(fadedImage, plainTruth).psnrDb + 6.0) << filterModeName(mode);
    }
}
