// Camera, transfer function, pre-classification and the CPU oracle's own invariants.
#include "renderer/math/camera.h"
#include "renderer/errors.h"
#include "renderer/io/image.h"
#include "renderer/model/procedural.h"
#include "renderer/oracle/reference_renderer.h"
#include "renderer/model/splat_scene.h"
#include "file_size_limit.h"
#include "test_paths.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>


#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <numbers>
#include <numeric>
#include <random>

using namespace renderer;
using ::testing::HasSubstr;

namespace {

TransferFunction flat(double opacity) { return fromSharedPoints("flat", {{0.0, {1, 1, 1}, opacity}, {1.0, {1, 1, 1}, opacity}}); }

Volume oneVoxel(float value) {
    Volume v;
    v.name = "one";
    v.dims = {1, 1, 1};
    v.values = {value};
    v.range = {0.0f, 1.0f};
    return v;
}

} // namespace

TEST(Camera, WIsARotationAndTheCentreProjectsToThePrincipalPoint) {
    for (double az : {0.0, 37.0, 181.0})
        for (double el : {-60.0, 0.0, 45.0})
            for (auto up : {glm::dvec3(0, 0, 1), glm::dvec3(0, 0, -1), glm::dvec3(0, 1, 0)}) {
                const ImagePlane p = makeImagePlane({az, el, 3.0, 40.0, {0, 0}, up}, {5, -2, 7}, 10.0, 64, 48);
                const glm::dmat3 w = p.viewFromObject;
                EXPECT_NEAR(glm::determinant(w), 1.0, 1e-12);
                const glm::dmat3 i = w * glm::transpose(w);
                for (int r = 0; r < 3; ++r)
                    for (int c = 0; c < 3; ++c) EXPECT_NEAR(i[c][r], r == c ? 1.0 : 0.0, 1e-12);
                const glm::dvec3 u = p.toCamera({5, -2, 7});
                EXPECT_NEAR(u.x, 0.0, 1e-9);
                EXPECT_NEAR(u.y, 0.0, 1e-9);
                EXPECT_NEAR(u.z, 30.0, 1e-9);   // distance 3 radii of 10
                // `up` points up the image: a point above the centre has u1 < 0 (rows grow downwards).
                if (std::abs(el) < 50) {
                    EXPECT_LT(p.toCamera(glm::dvec3(5, -2, 7) + up).y, 0.0);
                }
            }
}

TEST(Camera, FocalLengthFollowsTheFieldOfView) {
    const ImagePlane p = makeImagePlane({0, 0, 2, 30, {0, 0}}, {0, 0, 0}, 1.0, 48, 48);
    EXPECT_NEAR(p.fPx, 89.569219, 1e-6);   // EWA_NOTES: 48 px, 30 degrees
}

TEST(Camera, UpAxisNamesParse) {
    EXPECT_EQ(axisFromName("-z"), glm::dvec3(0, 0, -1));
    EXPECT_EQ(axisFromName("+y"), glm::dvec3(0, 1, 0));
    EXPECT_THROW(axisFromName("w"), RenderError);
}

// Where frameView() put each point: the largest of |pixel - centre| / (half size), over the points and
// both image axes, and the nearest depth. Framed: at most 1 - margin, and beyond the near plane.
struct Framed {
    double extent = 0.0, nearest = std::numeric_limits<double>::infinity();
    glm::dvec2 lo{std::numeric_limits<double>::infinity()}, hi{-std::numeric_limits<double>::infinity()};
};
Framed placed(const Camera& c, glm::dvec3 centre, double radius, const std::vector<glm::dvec3>& points, int w, int h,
              const glm::dmat3& axes = glm::dmat3(1.0)) {
    const ImagePlane p = makeImagePlane(c, centre, radius, w, h, axes);
    Framed f;
    for (const glm::dvec3& q : points) {
        const glm::dvec3 u = p.toCamera(q);
        const glm::dvec2 at = (p.project(u) - p.centrePx) / (0.5 * glm::dvec2(w, h));
        f.extent = std::max({f.extent, std::abs(at.x), std::abs(at.y)});
        f.nearest = std::min(f.nearest, u.z);
        f.lo = glm::min(f.lo, at);
        f.hi = glm::max(f.hi, at);
    }
    return f;
}

TEST(Camera, FrameViewFitsEveryPointInsideTheMarginAtTheLeastDistance) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    const double margin = 0.05;
    for (int trial = 0; trial < 200; ++trial) {
        const glm::dvec3 centre(u01(rng) * 10, u01(rng) * 10, u01(rng) * 10);
        // An elongated, off-centre cloud: the pan has to centre it.
        const glm::dvec3 size(1 + u01(rng) * 9, 1 + u01(rng) * 3, 1 + u01(rng) * 20), shift(u01(rng) * 4 - 2, 1, 0);
        std::vector<glm::dvec3> points;
        for (int i = 0; i < 20; ++i)
            points.push_back(centre + shift + size * glm::dvec3(u01(rng) - 0.5, u01(rng) - 0.5, u01(rng) - 0.5));
        Camera c{u01(rng) * 360 - 180, u01(rng) * 170 - 85, 9.0, 10 + u01(rng) * 80, {13, -4},
                 trial % 3 == 0 ? glm::dvec3(0, 0, -1) : glm::dvec3(0, 1, 0), trial % 4 == 0};
        const int w = 64 + int(u01(rng) * 600), h = 64 + int(u01(rng) * 600);
        const double radius = glm::length(size);
        // Every other trial, an oblique volume's axes (a rotation by Rodrigues' formula) turn the points.
        glm::dmat3 axes(1.0);
        if (trial % 2) {
            const glm::dvec3 k = glm::normalize(glm::dvec3(u01(rng), u01(rng), u01(rng)) - 0.5);
            const double angle = u01(rng) * 2.0 * std::numbers::pi;
            const glm::dmat3 cross(glm::dvec3(0, k.z, -k.y), glm::dvec3(-k.z, 0, k.x), glm::dvec3(k.y, -k.x, 0));
            axes = glm::dmat3(1.0) + std::sin(angle) * cross + (1.0 - std::cos(angle)) * cross * cross;
        }
        const Camera framed = frameView(c, centre, radius, points, w, h, margin, 0.0, 1e9, axes);
        SCOPED_TRACE("trial " + std::to_string(trial));
        EXPECT_EQ(framed.azimuthDeg, c.azimuthDeg);
        EXPECT_EQ(framed.fovYDeg, c.fovYDeg);
        const Framed f = placed(framed, centre, radius, points, w, h, axes);
        const double nearDepth = makeImagePlane(framed, centre, radius, w, h, axes).nearDepth;
        EXPECT_GT(f.nearest, nearDepth);
        const bool nearBound = f.nearest <= 2.0 * nearDepth * (1 + 1e-9);
        // Inside, and touching: nearer would push a point out (unless the near plane set the distance).
        EXPECT_LE(f.extent, 1.0 - margin + 1e-9);
        if (!nearBound) {
            EXPECT_NEAR(f.extent, 1.0 - margin, 1e-9);
            // Centred along the axis that set the distance: its extremes touch both edges.
            const bool alongX = std::abs(std::max(-f.lo.x, f.hi.x) - (1.0 - margin)) < 1e-9;
            const int axis = alongX ? 0 : 1;
            EXPECT_NEAR(-f.lo[axis], f.hi[axis], 1e-8);
        }
    }
}

TEST(Camera, FrameViewKeepsTheDistanceWithinItsLimitsAndCentresWhatItFrames) {
    const glm::dvec3 centre(0.0);
    const std::vector<glm::dvec3> small{{0.1, 0.2, 0.3}, {0.2, 0.25, 0.35}};   // off-centre and tiny
    for (bool ortho : {false, true}) {
        const Camera c{30, 20, 2.5, 30, {0, 0}, {0, 0, 1}, ortho};
        const Camera near = frameView(c, centre, 1.0, small, 200, 100, 0.05, 1.05, 20.0);
        EXPECT_DOUBLE_EQ(near.distance, 1.05);
        Framed f = placed(near, centre, 1.0, small, 200, 100);
        EXPECT_LT(f.extent, 0.5);
        EXPECT_NEAR(f.lo.x + f.hi.x, 0.0, 1e-9);   // the pan centres them
        EXPECT_NEAR(f.lo.y + f.hi.y, 0.0, 1e-9);
        const std::vector<glm::dvec3> huge{{-500, 0, 0}, {500, 0, 0}};
        EXPECT_DOUBLE_EQ(frameView(c, centre, 1.0, huge, 200, 100, 0.05, 1.05, 20.0).distance, 20.0);
        EXPECT_EQ(frameView(c, centre, 1.0, {}, 200, 100, 0.05, 1.05, 20.0).distance, c.distance);
        EXPECT_EQ(frameView(c, centre, 1.0, huge, 0, 100, 0.05, 1.05, 20.0).distance, c.distance);
    }
}

TEST(SplatScene, VisibleOutlineHoldsTheVoxelsTheLutShowsAndOnlyTheirBuckets) {
    Volume v;
    v.name = "block";
    v.dims = {9, 10, 11};
    v.spacing = {0.5, 1.0, 2.0};
    v.origin = {1.0, -2.0, 3.0};
    v.range = {0.0f, 1.0f};
    v.values.floats().assign(size_t(9 * 10 * 11), 0.0f);
    for (int z = 4; z <= 6; ++z)
        for (int y = 2; y <= 7; ++y)
            for (int x = 3; x <= 5; ++x) v.values.floats()[size_t(x + 9 * (y + 10 * z))] = (x + y + z) % 2 ? 1.0f : 0.7f;
    v.values.floats()[size_t(8 + 9 * (9 + 10 * 10))] = 0.2f;   // a far corner, shown only by the second TF
    const TransferFunction above = fromSharedPoints("above", {{0.0, {1, 1, 1}, 0.0}, {0.5, {1, 1, 1}, 0.0}, {0.6, {1, 1, 1}, 1.0},
                                              {1.0, {1, 1, 1}, 1.0}});
    SplatScene scene = buildSplatScene(v, above);
    auto box = [](const std::vector<glm::dvec3>& points) {
        std::pair<glm::dvec3, glm::dvec3> b{glm::dvec3(1e30), glm::dvec3(-1e30)};
        for (const glm::dvec3& p : points) b = {glm::min(b.first, p), glm::max(b.second, p)};
        return b;
    };
    const auto shown = box(visibleOutline(scene));
    EXPECT_EQ(shown.first, v.origin + v.spacing * glm::dvec3(3, 2, 4));
    EXPECT_EQ(shown.second, v.origin + v.spacing * glm::dvec3(5, 7, 6));
    setTransferFunction(scene, flat(0.5));
    EXPECT_EQ(box(visibleOutline(scene)).second, v.origin + v.spacing * glm::dvec3(8, 9, 10));
    setTransferFunction(scene, flat(0.0));   // nothing visible: the whole grid
    const auto all = box(visibleOutline(scene));
    EXPECT_EQ(all.first, v.origin);
    EXPECT_EQ(all.second, v.origin + v.spacing * glm::dvec3(8, 9, 10));
}

TEST(TransferFunction, LutInterpolatesControlPoints) {
    const TransferFunction tf = fromSharedPoints("t", {{0.0, {0, 0, 0}, 0.0}, {0.5, {1, 0, 0}, 1.0}, {1.0, {0, 0, 1}, 0.5}});
    const Lut lut = bakeLut(tf, {0.0f, 1.0f});
    ASSERT_EQ(lut.size(), size_t(kLutSize));
    const auto at = [&](double v) { return lut[size_t(std::floor(v * kLutSize))]; };
    EXPECT_NEAR(at(0.25).a, 0.5, 1e-3);
    EXPECT_NEAR(at(0.25).r, 0.5, 1e-3);
    EXPECT_NEAR(at(0.75).a, 0.75, 1e-3);
    EXPECT_NEAR(at(0.75).b, 0.5, 1e-3);
    EXPECT_EQ(lut[0].a, lut[0].a);   // finite
    EXPECT_LT(lut[0].a, 1e-3);
}

TEST(TransferFunction, ClassOfClampsAndHandlesNaN) {
    EXPECT_EQ(classOf(-5.0f, 0.0f, 1.0f), 0);
    EXPECT_EQ(classOf(5.0f, 0.0f, 1.0f), kLutSize - 1);
    EXPECT_EQ(classOf(std::nanf(""), 0.0f, 1.0f), 0);
    EXPECT_EQ(classOf(0.5f, 1.0f, 1.0f), 0);   // empty window
    EXPECT_EQ(classOf(0.5f, 0.0f, 1.0f), kLutSize / 2);
}

TEST(TransferFunction, SavingReplacesTheFileWholeOrFailsNamingItAndLeavesNoTempFile) {
    const auto dir = testing_support::testOutputDir();
    const auto path = dir / "saved_tf.json";
    saveTransferFunction(builtinPreset("fire"), path);
    saveTransferFunction(builtinPreset("grey-ramp"), path);   // over an existing file
    EXPECT_EQ(loadTransferFunction(path), builtinPreset("grey-ramp"));
    EXPECT_FALSE(std::filesystem::exists(path.string() + ".tmp"));

    const auto missing = dir / "no_such_dir" / "tf.json";
    try {
        saveTransferFunction(builtinPreset("fire"), missing);
        ADD_FAILURE() << "saved into a folder that does not exist";
    } catch (const LoadError& e) {
        EXPECT_THAT(e.what(), HasSubstr(missing.string()));
        EXPECT_THAT(e.what(), HasSubstr("cannot write"));
    }
    // A folder where the file should be: the temp file is written, the rename fails, nothing is left.
    const auto folder = dir / "tf_is_a_folder.json";
    std::filesystem::create_directories(folder);
    EXPECT_THROW(saveTransferFunction(builtinPreset("fire"), folder), LoadError);
    EXPECT_FALSE(std::filesystem::exists(folder.string() + ".tmp"));
    EXPECT_TRUE(std::filesystem::is_directory(folder));
}

TEST(ImageFiles, WritingReplacesTheFileWholeOrFailsNamingItAndKeepsTheOldOne) {
    const auto dir = testing_support::testOutputDir();
    Image first(4, 3), second(4, 3);
    for (size_t i = 0; i < first.rgba.size(); ++i) first.rgba[i] = float(i % 4 == 3 ? 1.0 : 0.25), second.rgba[i] = 1.0f;
    for (const char* name : {"saved_view.exr", "saved_view.png"}) {
        const auto path = dir / name;
        std::filesystem::remove(path);
        writeImage(first, path);
        writeImage(second, path);   // over an existing file
        EXPECT_EQ(readImage(path).rgba, second.rgba) << name;
        EXPECT_FALSE(std::filesystem::exists(path.string() + ".tmp")) << name;

        // What a killed save of an earlier release left (the fixed name "<out>.tmp", here a folder) blocks nothing.
        writeImage(first, path);
        std::filesystem::create_directories(path.string() + ".tmp/blocked");
        writeImage(second, path);
        EXPECT_EQ(readImage(path).rgba, second.rgba) << name;
        EXPECT_TRUE(std::filesystem::is_directory(path.string() + ".tmp/blocked")) << name;
        std::filesystem::remove_all(path.string() + ".tmp");
    }
    EXPECT_THROW(writeImage(first, dir / "no_such_dir" / "view.png"), LoadError);
}

// A full disk, made by a file-size limit: PNG's writer does not report the refused write, so the file
// is read back before it replaces the old one.
TEST(ImageFiles, AWriteTheDiskRefusesFailsAndKeepsTheOldFile) {
    const auto dir = testing_support::testOutputDir();
    Image old(8, 8), noise(64, 64);
    std::fill(old.rgba.begin(), old.rgba.end(), 1.0f);
    std::mt19937 random(7);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    for (float& v : noise.rgba) v = unit(random);   // incompressible: far over the limit below
    for (const char* name : {"full_disk.png", "full_disk.exr"}) {
        const auto path = dir / name;
        writeImage(old, path);
        const Image before = readImage(path);
        std::string error;
        {
            const testing_support::FileSizeLimit fullDisk(2048);
            ASSERT_TRUE(fullDisk.active());
            try {
                writeImage(noise, path);
            } catch (const LoadError& e) {
                error = e.what();
            }
        }
        EXPECT_THAT(error, HasSubstr(path.string())) << name;
        EXPECT_EQ(readImage(path).rgba, before.rgba) << name;
        EXPECT_FALSE(std::filesystem::exists(path.string() + ".tmp")) << name;
    }
}

TEST(TransferFunction, EvaluateInterpolatesAndHoldsTheEndsOutsideThePoints) {
    const TransferFunction tf = fromSharedPoints("t", {{0.2, {1, 0, 0}, 0.1}, {0.6, {0, 1, 0}, 0.9}});
    EXPECT_EQ(evaluate(tf, 0.0), glm::dvec4(1, 0, 0, 0.1));   // before the first point: the first
    EXPECT_EQ(evaluate(tf, 1.0), glm::dvec4(0, 1, 0, 0.9));   // after the last: the last
    const glm::dvec4 mid = evaluate(tf, 0.5);
    EXPECT_NEAR(mid.r, 0.25, 1e-12);
    EXPECT_NEAR(mid.g, 0.75, 1e-12);
    EXPECT_NEAR(mid.a, 0.1 + 0.75 * 0.8, 1e-12);
    EXPECT_EQ(evaluate(TransferFunction{}, 0.5), glm::dvec4(0.0));
    // Two points at one value make a step: the later one holds from there on.
    const TransferFunction step = fromSharedPoints("s", {{0.0, {0, 0, 0}, 0.0}, {0.5, {0, 0, 0}, 0.0}, {0.5, {1, 1, 1}, 1.0}});
    EXPECT_EQ(evaluate(step, 0.49).a, 0.0);
    EXPECT_EQ(evaluate(step, 0.51).a, 1.0);
}

TEST(TransferFunction, EachBundledPresetFileIsAPresetByItsName) {
    // assets/presets/bonsai.json: `--tf bonsai`, the editor's Preset list and `splatlab tf` name it.
    const std::vector<std::string> names = builtinPresetNames();
    ASSERT_GE(names.size(), 6u);
    EXPECT_EQ(std::vector<std::string>(names.begin(), names.begin() + 5),
              (std::vector<std::string>{"ct-skin-bone", "ct-bone", "grey-ramp", "soft", "fire"}));
    EXPECT_NE(std::find(names.begin(), names.end(), "bonsai"), names.end());
    const TransferFunction file = loadTransferFunction(testing_support::assetDir() / "presets" / "bonsai.json");
    EXPECT_EQ(builtinPreset("bonsai"), file);
    EXPECT_EQ(transferFunctionFromSpec("bonsai"), file);
    EXPECT_EQ(file.name, "bonsai");
    try {
        builtinPreset("no-such-preset");
        ADD_FAILURE() << "an unknown name loaded";
    } catch (const RenderError& e) {
        EXPECT_THAT(e.what(), ::testing::HasSubstr("fire, bonsai"));   // the known names, the files' last
    }
}

TEST(SplatScene, ATfEditCountsTheVisibleVoxelsAsEveryVoxelWould) {
    // The count comes from the voxels per class, kept from the build; each TF must give what a pass
    // over every voxel gives.
    SplatScene s = buildSplatScene(makeSphereShells(12, 4.0, 1.5), builtinPreset("grey-ramp"));
    ASSERT_EQ(s.classVoxels.size(), size_t(kLutSize));
    for (const std::string& name : builtinPresetNames()) {
        setTransferFunction(s, builtinPreset(name));
        const auto visible = size_t(std::count_if(s.classes.begin(), s.classes.end(),
                                                  [&](uint16_t c) { return s.lut[c].a > 0.0f; }));
        EXPECT_EQ(s.visibleCount(), visible) << name;
    }
}

TEST(SplatScene, DrawOrderListsEachVoxelOfTheActiveBucketsOnceInSliceOrder) {
    Volume v = makeSphereShells(12, 4.0, 1.5);
    const TransferFunction tf = fromSharedPoints("t", {{0.0, {1, 1, 1}, 0.0}, {0.4, {1, 1, 1}, 0.0}, {0.6, {1, 1, 1}, 1.0}});
    const SplatScene s = buildSplatScene(v, tf);
    const auto active = activeBuckets(s.lut);
    size_t expected = 0, visible = 0;
    for (uint16_t c : s.classes) expected += active[c >> kBucketShift], visible += s.lut[c].a > 0.0f;
    ASSERT_GT(visible, 0u);
    ASSERT_LT(expected, s.classes.size());
    EXPECT_EQ(s.visibleCount(), visible);
    for (int axis = 0; axis < 3; ++axis)
        for (bool descending : {false, true}) {
            std::vector<uint32_t> starts;
            const auto order = drawOrder(s, {axis, descending}, false, false, &starts);
            ASSERT_EQ(order.size(), expected);
            ASSERT_EQ(starts.size(), size_t(s.dims[axis]) + 1);
            std::vector<int> seen(s.classes.size(), 0);
            for (size_t k = 0; k < starts.size() - 1; ++k)
                for (uint32_t i = starts[k]; i < starts[k + 1]; ++i) {
                    const int slice = glm::ivec3(glm::round(s.positionOf(order[i]) - s.origin))[axis];
                    ASSERT_EQ(slice, descending ? s.dims[axis] - 1 - int(k) : int(k));
                    ++seen[order[i]];
                }
            for (size_t i = 0; i < seen.size(); ++i) ASSERT_EQ(seen[i], active[s.classes[i] >> kBucketShift] ? 1 : 0);
            // Every voxel once when all buckets are drawn, and front-to-back is the slice order reversed.
            EXPECT_EQ(drawOrder(s, {axis, descending}, false, true).size(), s.classes.size());
            std::vector<uint32_t> reversedStarts;
            const auto reversed = drawOrder(s, {axis, descending}, true, false, &reversedStarts);
            ASSERT_EQ(reversed.size(), order.size());
            EXPECT_EQ(reversed[0], order[starts[starts.size() - 2]]);
        }
}

TEST(SplatScene, ListsStayCompactWhereOneValueDominatesATile) {
    // 40^3 of air with a 10^3 block: air is one dense run per slice (no entries), so the three axis
    // lists hold only the block's voxels: 2 bytes each, 3 axes.
    Volume v;
    v.dims = {40, 40, 40};
    v.values.floats().assign(v.voxelCount(), 0.0f);
    for (int z = 15; z < 25; ++z)
        for (int y = 15; y < 25; ++y)
            for (int x = 15; x < 25; ++x) v.values.floats()[(size_t(z) * 40 + y) * 40 + x] = 1.0f;
    v.range = {0.0f, 1.0f};
    const SplatScene s = buildSplatScene(v, builtinPreset("grey-ramp"));
    for (const auto& lists : s.lists) {
        EXPECT_EQ(lists.entries().size(), 1000u);
        size_t dense = 0;
        for (const auto& r : lists.runs) {
            dense += r.dense;
            // The block's runs know where in the slice their voxels lie (the sheet's scissor box).
            const glm::u16vec2 lo = r.dense ? glm::u16vec2(0) : glm::u16vec2(15);
            const glm::u16vec2 hi = r.dense ? glm::u16vec2(39) : glm::u16vec2(24);
            EXPECT_EQ(r.lo, lo);
            EXPECT_EQ(r.hi, hi);
        }
        EXPECT_EQ(dense, 40u);
    }
}

TEST(SplatScene, BucketsOverAnEighthOfATileAreWalkedNotListed) {
    // 16x16x4: stripes along x of 4, 4, 4 and 3 columns (a quarter or 3/16 of every z and y slice, one
    // value per x slice), and a last column whose value, one bucket per y, takes 1/16 of those slices.
    // Only that column is listed, 64 entries on each axis; the stripes are walked.
    Volume v;
    v.dims = {16, 16, 4};
    v.values.floats().resize(v.voxelCount());
    for (int z = 0; z < 4; ++z)
        for (int y = 0; y < 16; ++y)
            for (int x = 0; x < 16; ++x)
                v.values.floats()[(size_t(z) * 16 + y) * 16 + x] = x == 15 ? float(y + 1.5) / 64.0f : 0.3f * float(x / 4);
    v.range = {0.0f, 1.0f};
    const SplatScene s = buildSplatScene(v, builtinPreset("grey-ramp"));
    for (int axis = 0; axis < 3; ++axis) {
        const AxisLists& lists = s.lists[size_t(axis)];
        EXPECT_EQ(lists.entries().size(), 64u) << axis;
        const uint32_t tile = uint32_t(v.dims[(axis + 1) % 3] * v.dims[(axis + 2) % 3]);
        size_t walked = 0;
        for (const SliceRun& r : lists.runs) {
            EXPECT_EQ(r.dense, kDenseShare * r.voxels > tile) << axis;
            walked += r.dense;
        }
        EXPECT_EQ(walked, axis == 0 ? 15u : axis == 1 ? 64u : 16u) << axis;
        // Every voxel drawn once: each walk keeps its own bucket's.
        std::vector<uint32_t> order = drawOrder(s, Traversal{axis, false}, false, true);
        std::sort(order.begin(), order.end());
        std::vector<uint32_t> all(v.voxelCount());
        std::iota(all.begin(), all.end(), 0u);
        EXPECT_EQ(order, all) << axis;
    }
}

TEST(SplatScene, EveryRunHoldsItsTilesVoxelsOfItsBucketOnEveryAxisOfAnUnevenVolume) {
    // 20 x 300 x 230: slices across x hold 69,000 positions (two tiles of kTileVoxels), and no axis has
    // a number of slices that the scene's blocks of slices divide. Most voxels share one value (walked
    // runs), the rest are spread over the buckets (listed runs).
    Volume v;
    v.dims = {20, 300, 230};
    v.values.floats().resize(v.voxelCount());
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> any(0.0f, 1.0f);
    for (float& value : v.values.floats()) value = any(rng) < 0.8f ? 0.5f : any(rng);
    v.range = {0.0f, 1.0f};
    const SplatScene s = buildSplatScene(v, builtinPreset("grey-ramp"));
    struct Bucket {
        uint32_t voxels = 0;
        glm::u16vec2 lo{UINT16_MAX}, hi{0};
        std::vector<uint16_t> positions;
    };
    for (int axis = 0; axis < 3; ++axis) {
        const AxisLists& lists = s.lists[size_t(axis)];
        const uint32_t rowLength = uint32_t(v.dims[(axis + 1) % 3]);
        const uint32_t sliceSize = rowLength * uint32_t(v.dims[(axis + 2) % 3]);
        ASSERT_EQ(lists.sliceRuns.size(), size_t(v.dims[axis]) + 1);
        for (uint32_t slice = 0; slice < uint32_t(v.dims[axis]); ++slice) {
            uint32_t r = lists.sliceRuns[slice];
            for (uint32_t tileBase = 0; tileBase < sliceSize; tileBase += kTileVoxels) {
                // The tile's buckets counted again, voxel by voxel through voxelAt.
                const uint32_t tileSize = std::min(kTileVoxels, sliceSize - tileBase);
                std::map<uint16_t, Bucket> buckets;
                for (uint32_t p = 0; p < tileSize; ++p) {
                    Bucket& b = buckets[uint16_t(s.classes[s.voxelAt(axis, slice, tileBase + p)] >> kBucketShift)];
                    ++b.voxels;
                    const glm::u16vec2 ab((tileBase + p) % rowLength, (tileBase + p) / rowLength);
                    b.lo = glm::min(b.lo, ab), b.hi = glm::max(b.hi, ab);
                    b.positions.push_back(uint16_t(p));
                }
                for (const auto& [bucket, b] : buckets) {   // a run each, in bucket order
                    ASSERT_LT(r, lists.sliceRuns[slice + 1]) << axis << " " << slice;
                    const SliceRun& run = lists.runs[r++];
                    ASSERT_EQ(run.slice, slice);
                    ASSERT_EQ(run.tileBase, tileBase);
                    ASSERT_EQ(run.bucket, bucket);
                    ASSERT_EQ(run.voxels, b.voxels) << axis << " " << slice;
                    ASSERT_EQ(run.lo, b.lo) << axis << " " << slice;
                    ASSERT_EQ(run.hi, b.hi) << axis << " " << slice;
                    ASSERT_EQ(run.dense, kDenseShare * b.voxels > tileSize);
                    if (run.dense) {
                        ASSERT_EQ(run.count, tileSize);
                    } else {
                        ASSERT_EQ(run.count, b.voxels);
                        ASSERT_TRUE(std::equal(b.positions.begin(), b.positions.end(), lists.entries().begin() + run.first));
                    }
                }
            }
            ASSERT_EQ(r, lists.sliceRuns[slice + 1]) << axis << " " << slice;
        }
    }
}

TEST(SplatScene, TraversalFollowsTheMajorViewAxisBackToFront) {
    ImagePlane p;
    p.viewDirObject = {0.2, -0.9, 0.3};
    EXPECT_EQ(chooseTraversal(p).axis, 1);
    EXPECT_FALSE(chooseTraversal(p).descending);   // looking towards -y: far slices have low y
    p.viewDirObject = {0.1, 0.2, 0.97};
    EXPECT_EQ(chooseTraversal(p).axis, 2);
    EXPECT_TRUE(chooseTraversal(p).descending);
}

TEST(ReferenceRenderer, OneSplatDepositsItsOpticalDepth) {
    // X-ray of one voxel with a wide cutoff: sum over pixels of -log(1 - alpha) = g vol |J| (mass
    // inside 8 sigma is 1 - 1e-14; a footprint of sigma >= 2 px samples the Gaussian's integral to
    // 1e-12 on a unit grid).
    const Volume v = oneVoxel(1.0f);
    const SplatScene scene = buildSplatScene(v, flat(0.2));
    SplatSettings s;
    s.compositing = Compositing::XRay;
    s.cutoffSigmas = 8.0;
    s.kernelScale = 0.7;
    s.density = 1e-3;   // optical depth well below 1 everywhere, so the float image keeps its digits
    for (auto mode : {FilterMode::Reconstruction, FilterMode::LowPass, FilterMode::Ewa}) {
        s.filter = mode;
        // Sigma ~17 px at 30 units: the 8-sigma ellipse (139 px) fits in the 400 px image.
        const ImagePlane plane = makeImagePlane({0, 0, 20.0, 30.0}, {0.3, 0.2, 0.0}, 1.5, 400, 400);
        SplatCounters counters;
        const Image img = renderReference(scene, plane, s, &counters);
        ASSERT_EQ(counters.drawn, 1u);
        double depth = 0.0;
        for (size_t i = 3; i < img.rgba.size(); i += 4) depth += -std::log1p(-double(img.rgba[i]));
        const glm::dvec3 u = plane.toCamera({0, 0, 0});
        const double expected = voxelExtinction(scene, s, 0) * rayJacobianDet(u, plane.fPx);
        EXPECT_NEAR(depth / expected, 1.0, 2e-6) << filterModeName(mode);   // float image: 1e-7 per pixel
    }
}

TEST(ReferenceRenderer, NearPlaneAndHugeFootprintsAreCulledAndCounted) {
    const Volume v = makeCheckerboard({8, 8, 8}, 1);
    const SplatScene scene = buildSplatScene(v, flat(0.5));
    // Camera inside the volume: voxels behind the eye are culled by the near plane, never drawn.
    const ImagePlane plane = makeImagePlane({0, 0, 0.2, 90.0}, scene.centre, scene.radius, 64, 64);
    SplatSettings s;
    SplatCounters c;
    const Image img = renderReference(scene, plane, s, &c);
    EXPECT_GT(c.culledNear, 0u);
    EXPECT_EQ(c.visible, c.drawn + c.culledTransparent + c.culledNear + c.culledOffscreen + c.culledHuge + c.culledDegenerate);
    EXPECT_TRUE(imageStats(img).finite);
    EXPECT_EQ(c.culledHuge, 0u) << "no huge-footprint guard unless one is set";
    s.maxFootprintFraction = 0.01;   // every footprint is now "huge"
    renderReference(scene, plane, s, &c);
    EXPECT_EQ(c.drawn, 0u);
    EXPECT_GT(c.culledHuge, 0u);
}

TEST(ReferenceRenderer, ResultDoesNotDependOnTheThreadCount) {
    // Bands of rows are independent: rendering twice (different scheduling) gives identical bits.
    const SplatScene scene = buildSplatScene(makeMarschnerLobb(16), flat(0.3));
    const ImagePlane plane = makeImagePlane(Camera{}, scene.centre, scene.radius, 48, 40);
    const Image a = renderReference(scene, plane, SplatSettings{});
    const Image b = renderReference(scene, plane, SplatSettings{});
    EXPECT_EQ(a.rgba, b.rgba);
}

TEST(HalfResolution, AveragesBlocksAtTheirCentreAndKeepsAxesOfOneVoxel) {
    Volume v;
    v.name = "ramp";
    v.dims = {5, 4, 1};
    v.spacing = {0.5, 2.0, 3.0};
    v.origin = {1.0, -1.0, 7.0};
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 5; ++x) v.values.floats().push_back(float(10 * y + x));
    v.values.floats()[v.index(1, 0, 0)] = std::nanf("");   // skipped in its block's mean
    updateRange(v);
    const Volume h = halfResolution(v);
    EXPECT_EQ(h.dims, glm::ivec3(3, 2, 1));
    EXPECT_EQ(h.spacing, glm::dvec3(1.0, 4.0, 3.0));
    EXPECT_EQ(h.origin, glm::dvec3(1.25, 0.0, 7.0));   // the centre of the fine voxels 0 and 1 on x and y
    EXPECT_FLOAT_EQ(h.at(0, 0, 0), (0.0f + 10 + 11) / 3);
    EXPECT_FLOAT_EQ(h.at(1, 1, 0), (22.0f + 23 + 32 + 33) / 4);
    EXPECT_FLOAT_EQ(h.at(2, 1, 0), (24.0f + 34) / 2);   // the odd last column holds one fine column
    EXPECT_FLOAT_EQ(h.range.lo, h.at(0, 0, 0));
    EXPECT_FLOAT_EQ(h.range.hi, 29.0f);   // (24 + 34) / 2
    v.values.floats().assign(v.values.size(), std::nanf(""));
    EXPECT_TRUE(std::isnan(halfResolution(v).at(0, 0, 0)));
    EXPECT_EQ(halfResolution(Volume{}).voxelCount(), 0u);
}

TEST(HalfResolution, WithDensityForItRendersTheVolumesExtinction) {
    // A smooth blob seen in X-ray: each pixel is the extinction integrated along its ray, so the coarse
    // volume with densityFor() must give the fine image, up to the blur of its wider kernels.
    Volume v;
    v.name = "blob";
    v.dims = {32, 32, 32};
    v.spacing = {1.0, 1.0, 2.0};
    for (int z = 0; z < 32; ++z)
        for (int y = 0; y < 32; ++y)
            for (int x = 0; x < 32; ++x) {
                const glm::dvec3 d = (glm::dvec3(x, y, z) - 15.5) * v.spacing;
                v.values.floats().push_back(float(std::exp(-glm::dot(d, d) / (2.0 * 7.0 * 7.0))));
            }
    updateRange(v);
    const Volume h = halfResolution(v);
    const TransferFunction ramp = fromSharedPoints("ramp", {{0.0, {1, 1, 1}, 0.0}, {1.0, {1, 1, 1}, 1.0}});
    SplatSettings s;
    s.compositing = Compositing::XRay;
    s.density = 0.04;
    // The fine volume's window for both: the means span a narrower range of values.
    const SplatScene fine = buildSplatScene(v, ramp, v.range), coarse = buildSplatScene(h, ramp, v.range);
    // Both seen from the fine volume's camera, as the editor draws the preview.
    const ImagePlane plane = makeImagePlane(Camera{}, fine.centre, fine.radius, 64, 64);
    const Image a = renderReference(fine, plane, s);
    SplatSettings sc = s;
    sc.density = densityFor(h, v, s.density);
    EXPECT_DOUBLE_EQ(sc.density, 0.08);
    const Image b = renderReference(coarse, plane, sc);
    // X-ray shows 1 - exp(-optical depth); the depths add up to the extinction's integral over the image.
    double depthA = 0.0, depthB = 0.0, sq = 0.0, peak = 0.0;
    for (size_t i = 3; i < a.rgba.size(); i += 4) {
        depthA -= std::log1p(-double(a.rgba[i])), depthB -= std::log1p(-double(b.rgba[i]));
        peak = std::max(peak, double(a.rgba[i]));
        sq += (a.rgba[i] - b.rgba[i]) * (a.rgba[i] - b.rgba[i]);
    }
    ASSERT_GT(peak, 0.3);
    EXPECT_NEAR(depthB / depthA, 1.0, 0.005);   // measured 0.9997; without densityFor() 0.5
    EXPECT_LT(std::sqrt(sq / double(a.rgba.size() / 4)), 0.02 * peak);
}

TEST(HalfResolution, PickingOneFineValueKeepsASharpTfsThinFeatureWhereTheMeanLosesIt) {
    // A one-voxel sheet of value 1 (at z = 15) in a background of 0, and a TF that shows only values
    // from 0.9: the mean of each 2x2x2 block through the sheet is 0.5, outside the band, so the coarse
    // level loses the sheet. PickOne takes the sheet's value in about half of those blocks, so the
    // coarse level's extinction integral (X-ray optical depth over the image) stays the fine one's.
    Volume v;
    v.name = "sheet";
    v.dims = {32, 32, 32};
    for (int z = 0; z < 32; ++z)
        for (int i = 0; i < 32 * 32; ++i) v.values.floats().push_back(z == 15 ? 1.0f : 0.0f);
    updateRange(v);
    const TransferFunction band = fromSharedPoints("band", {{0.0, {1, 1, 1}, 0.0}, {0.89, {1, 1, 1}, 0.0}, {0.9, {1, 1, 1}, 1.0},
                                         {1.0, {1, 1, 1}, 1.0}});
    SplatSettings s;
    s.compositing = Compositing::XRay;
    s.density = 0.05;
    const SplatScene fine = buildSplatScene(v, band, v.range);
    const ImagePlane plane = makeImagePlane(Camera{.azimuthDeg = 20, .elevationDeg = 30}, fine.centre, fine.radius, 48, 48);
    auto depth = [&](const Image& img) {
        double sum = 0.0;
        for (size_t i = 3; i < img.rgba.size(); i += 4) sum -= std::log1p(-double(img.rgba[i]));
        return sum;
    };
    const double fineDepth = depth(renderReference(fine, plane, s));
    ASSERT_GT(fineDepth, 1.0);
    SplatSettings sc = s;
    for (Downsample how : {Downsample::Mean, Downsample::PickOne}) {
        const Volume h = halfResolution(v, how);
        sc.density = densityFor(h, v, s.density);
        const double ratio = depth(renderReference(buildSplatScene(h, band, v.range), plane, sc)) / fineDepth;
        std::printf("[ levels   ] %s: coarse / fine optical depth %.4f\n",
                    how == Downsample::Mean ? "mean" : "pick one", ratio);
        if (how == Downsample::Mean) EXPECT_LT(ratio, 0.01) << "the mean kept the sheet: the test proves nothing";
        else EXPECT_NEAR(ratio, 1.0, 0.1);
    }
}
