// Alignment of a scan's axes to the world's: reordered and mirrored voxels, rounded direction cosines,
// sheared axes resampled, and the rotation left for the image plane.
#include "renderer/errors.h"
#include "renderer/io/image.h"
#include "renderer/model/procedural.h"
#include "renderer/model/splat_scene.h"
#include "renderer/oracle/reference_renderer.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>

using namespace renderer;
using ::testing::HasSubstr;

// Alignment reorders voxels so that mirrored and swapped axes (as scanners store them) become x, y, z,
// and oblique mirrored ones a rotation: every value stays where the file's axes put it in its world.
TEST(AlignedToWorldAxes, KeepsEveryVoxelWhereTheFilesAxesPutItInTheWorld) {
    const glm::dvec3 x{1, 0, 0}, y{0, 1, 0}, z{0, 0, 1};
    const double c = std::cos(std::numbers::pi / 6), s = std::sin(std::numbers::pi / 6);
    const glm::dmat3 rz30(glm::dvec3(c, s, 0), glm::dvec3(-s, c, 0), z);
    struct Case {
        glm::dmat3 axes;
        glm::dmat3 left;   // what alignment leaves for the image plane
    };
    const std::vector<Case> cases = {
        {glm::dmat3(-x, y, z), glm::dmat3(1.0)},                       // x mirrored (RAS against LPS)
        {glm::dmat3(-x, -y, -z), glm::dmat3(1.0)},                     // every axis mirrored
        {glm::dmat3(-y, z, -x), glm::dmat3(1.0)},                      // swapped and mirrored
        {glm::dmat3(y + 1e-9 * z, x, z - 1e-9 * x), glm::dmat3(1.0)},  // swapped, with a header's rounding
        {rz30, rz30},                                                  // oblique: the image plane turns it
        {glm::dmat3(-rz30[0], rz30[1], rz30[2]), rz30},                // oblique and mirrored: x reversed
    };
    for (const Case& k : cases) {
        Volume v;
        v.dims = {3, 4, 5};
        v.spacing = {0.5, 2.0, 1.25};
        v.origin = {10.0, -3.0, 7.0};
        v.directions = k.axes;
        v.values.floats().resize(v.voxelCount());
        std::iota(v.values.floats().begin(), v.values.floats().end(), 0.0f);   // every voxel its own value
        updateRange(v);
        const Volume a = alignedToWorldAxes(v);
        EXPECT_LT(glm::length(a.directions[0] - k.left[0]) + glm::length(a.directions[1] - k.left[1]) +
                      glm::length(a.directions[2] - k.left[2]), 1e-6);
        EXPECT_FALSE(a.axesNotDrawn());
        ASSERT_EQ(a.voxelCount(), v.voxelCount());
        for (int kz = 0; kz < v.dims.z; ++kz)
            for (int ky = 0; ky < v.dims.y; ++ky)
                for (int kx = 0; kx < v.dims.x; ++kx) {
                    const glm::dvec3 world = v.origin + v.directions * (v.spacing * glm::dvec3(kx, ky, kz));
                    // Its index in `a`: a.directions is orthonormal, so its transpose inverts it.
                    const glm::dvec3 at = glm::transpose(a.directions) * (world - a.origin) / a.spacing;
                    const glm::ivec3 n = glm::ivec3(glm::round(at));
                    ASSERT_LT(glm::length(at - glm::dvec3(n)), 1e-6) << "not on a voxel: " << kx << ky << kz;
                    ASSERT_TRUE(glm::all(glm::greaterThanEqual(n, glm::ivec3(0))) &&
                                glm::all(glm::lessThan(n, a.dims)));
                    EXPECT_EQ(a.at(n.x, n.y, n.z), v.at(kx, ky, kz));
                }
    }
    // Sheared axes cannot be reordered: they are resampled (next test), and the volume says so.
    Volume sheared = makeCheckerboard({4, 4, 4}, 2);
    sheared.directions = glm::dmat3(x, glm::normalize(x + y), z);
    EXPECT_FALSE(axesAlignable(sheared.directions));
    EXPECT_TRUE(sheared.axesNotDrawn());
    const Volume resampled = alignedToWorldAxes(sheared);
    EXPECT_TRUE(resampled.resampled);
    EXPECT_FALSE(resampled.axesNotDrawn());
    EXPECT_EQ(resampled.directions, glm::dmat3(1.0));
    EXPECT_FALSE(axesAlignable(glm::dmat3(x, x, z))) << "two axes along one";
    EXPECT_FALSE(axesAlignable(glm::dmat3(2.0 * x, y, z))) << "not a unit vector";
    EXPECT_FALSE(axesAlignable(glm::dmat3(glm::dvec3(std::nan(""), 1, 0), y, z)));
    EXPECT_FALSE(isRotation(glm::dmat3(glm::dvec3(std::nan(""), 1, 0), y, z)));
    EXPECT_FALSE(isRotation(glm::dmat3(-x, y, z))) << "a mirror is not a rotation";
}

// Direction cosines rounded by a header (to three or four digits) leave axes that are not quite
// orthonormal; alignment takes them as the orthonormal axes nearest them, so they are drawn, and keeps
// refusing axes sheared by more than that.
TEST(AlignedToWorldAxes, TakesAHeadersRoundedCosinesAsTheNearestOrthonormalAxes) {
    const glm::dvec3 x{1, 0, 0}, y{0, 1, 0}, z{0, 0, 1};
    const glm::dmat3 rz30 = glm::dmat3(glm::rotate(glm::dmat4(1.0), glm::radians(30.0), z));
    // About an oblique axis, so that every cosine is rounded.
    const glm::dmat3 oblique =
        glm::dmat3(glm::rotate(glm::dmat4(1.0), glm::radians(40.0), glm::normalize(glm::dvec3(1, 2, 3))));
    const auto rounded = [](const glm::dmat3& m, double digits) {
        const double scale = std::pow(10.0, digits);
        glm::dmat3 r;
        for (int c = 0; c < 3; ++c)
            for (int row = 0; row < 3; ++row) r[c][row] = std::round(m[c][row] * scale) / scale;
        return r;
    };
    struct Case {
        glm::dmat3 axes;   // as the header gives them
        glm::dmat3 left;   // the rotation they are drawn as
    };
    const Case cases[] = {
        {rounded(rz30, 3), rz30},
        {rounded(rz30, 4), rz30},
        {rounded(oblique, 3), oblique},
        {rounded(glm::dmat3(-oblique[0], oblique[1], oblique[2]), 4), oblique},   // mirrored: x reversed
    };
    for (const Case& k : cases) {
        ASSERT_FALSE(isRotation(k.axes)) << "the rounding must leave axes a strict test refuses";
        Volume v = makeCheckerboard({4, 5, 6}, 2);
        v.directions = k.axes;
        const Volume a = alignedToWorldAxes(v);
        EXPECT_TRUE(isRotation(a.directions));
        EXPECT_FALSE(a.axesNotDrawn());
        // Within the rounding: three digits move an axis by under 2e-3.
        for (int c = 0; c < 3; ++c) EXPECT_LT(glm::length(a.directions[c] - k.left[c]), 2e-3) << "axis " << c;
    }
    // A shear of 0.01 (0.57 degrees) is not a header's rounding: resampled, not taken as a rotation.
    Volume sheared = makeCheckerboard({4, 4, 4}, 2);
    sheared.directions = glm::dmat3(x, glm::normalize(y + 0.01 * x), z);
    EXPECT_TRUE(alignedToWorldAxes(sheared).resampled);
}

// Sheared axes (a CT's gantry tilt, or any skew) are resampled onto a grid along the world axes. A field
// linear in the world is linear in the file's index space, where trilinear interpolation reproduces it:
// every grid point inside the scan must hold the field's value there, and every one outside the scan
// the data's minimum.
TEST(AlignedToWorldAxes, ResamplesShearedAxesOntoTheWorldGridExactlyForALinearField) {
    const glm::dvec3 x{1, 0, 0}, y{0, 1, 0}, z{0, 0, 1};
    const double tilt = glm::radians(20.0);
    const glm::dmat3 cases[] = {
        glm::dmat3(x, y, glm::dvec3(0, std::sin(tilt), std::cos(tilt))),   // gantry tilt about x
        glm::dmat3(x, glm::normalize(glm::dvec3(0.6, 0.8, 0)), glm::normalize(glm::dvec3(0.1, -0.2, 1))),
    };
    const glm::dvec3 gradient{0.7, -1.3, 2.1};
    for (const glm::dmat3& axes : cases) {
        Volume v;
        v.name = "sheared";
        v.dims = {7, 6, 5};
        v.spacing = {1.5, 2.0, 2.5};
        v.origin = {3.0, -2.0, 1.0};
        v.directions = axes;
        v.values.floats().resize(v.voxelCount());
        const glm::dmat3 toWorld = axes * glm::dmat3(glm::dvec3(1.5, 0, 0), glm::dvec3(0, 2.0, 0), glm::dvec3(0, 0, 2.5));
        for (int k = 0; k < v.dims.z; ++k)
            for (int j = 0; j < v.dims.y; ++j)
                for (int i = 0; i < v.dims.x; ++i)
                    v.values.floats()[v.index(i, j, k)] =
                        float(100.0 + glm::dot(gradient, v.origin + toWorld * glm::dvec3(i, j, k)));
        updateRange(v);
        const Volume a = alignedToWorldAxes(v);
        ASSERT_TRUE(a.resampled);
        EXPECT_EQ(a.directions, glm::dmat3(1.0));
        // Each world axis steps as far along it as the index axis most along it.
        for (int w = 0; w < 3; ++w) {
            double step = 0.0;
            for (int j = 0; j < 3; ++j) step = std::max(step, std::abs(toWorld[j][w]));
            EXPECT_NEAR(a.spacing[w], step, 1e-12) << "world axis " << w;
        }
        size_t inside = 0;
        for (int k = 0; k < a.dims.z; ++k)
            for (int j = 0; j < a.dims.y; ++j)
                for (int i = 0; i < a.dims.x; ++i) {
                    const glm::dvec3 p = a.positionOf(i, j, k);
                    const glm::dvec3 f = glm::inverse(toWorld) * (p - v.origin);
                    const bool in = glm::all(glm::greaterThanEqual(f, glm::dvec3(-1e-9))) &&
                                    glm::all(glm::lessThanEqual(f, glm::dvec3(v.dims - 1) + 1e-9));
                    const double expected = in ? 100.0 + glm::dot(gradient, p) : double(v.range.lo);
                    ASSERT_NEAR(a.at(i, j, k), expected, 1e-3) << i << " " << j << " " << k << (in ? " in" : " out");
                    inside += in;
                }
        EXPECT_GT(double(inside), 0.4 * double(a.voxelCount())) << "the grid must mostly hold the scan";
        // The grid holds every voxel centre of the file.
        for (int corner = 0; corner < 8; ++corner) {
            const glm::dvec3 p = v.origin + toWorld * (glm::dvec3(v.dims - 1) * glm::dvec3(corner & 1, corner >> 1 & 1, corner >> 2 & 1));
            EXPECT_TRUE(glm::all(glm::greaterThanEqual(p, a.origin - 1e-9)) &&
                        glm::all(glm::lessThanEqual(p, a.positionOf(a.dims.x - 1, a.dims.y - 1, a.dims.z - 1) + a.spacing)))
                << "corner " << corner;
        }
    }
    // Axes sheared so far that the grid would hold more than 8 times the voxels are refused, by name.
    Volume far = makeCheckerboard({64, 64, 64}, 2);
    far.name = "far";
    far.directions = glm::dmat3(glm::normalize(glm::dvec3(1, 0.9, 0.9)), glm::normalize(glm::dvec3(0.9, 1, 0.9)),
                                glm::normalize(glm::dvec3(0.9, 0.9, 1)));
    try {
        alignedToWorldAxes(far);
        ADD_FAILURE() << "resampled onto a grid many times the file's";
    } catch (const LoadError& e) {
        EXPECT_THAT(e.what(), HasSubstr("far: field 'directions': the axes are sheared so far"));
    }
}

// A rotation left in Volume::directions is drawn by the image plane (SplatScene::axes): turned 30 degrees
// about the up axis, a volume seen from azimuth 60 is the unturned one seen from azimuth 30. And a
// rotation that is also a permutation draws through the plane as its reordered voxels do.
TEST(AlignedToWorldAxes, TheImagePlaneTurnsTheVolumeByTheRotationLeft) {
    // Cells of colours that vary along x and z, so that a wrong slice order shows too.
    Volume v;
    v.dims = {6, 5, 4};
    v.spacing = {1.0, 1.5, 2.0};
    for (int z = 0; z < 4; ++z)
        for (int y = 0; y < 5; ++y)
            for (int x = 0; x < 6; ++x)
                v.values.floats().push_back((x / 2 + y / 2 + z / 2) % 2 ? float(0.2 + 0.12 * x + 0.05 * z) : 0.0f);
    updateRange(v);
    const TransferFunction tf = builtinPreset("fire");
    auto render = [&](const Volume& volume, const Camera& camera) {
        const SplatScene scene = buildSplatScene(volume, tf, volume.range);
        const ImagePlane plane = makeImagePlane(camera, scene.centre, scene.radius, 40, 40, scene.axes);
        return renderReference(scene, plane, SplatSettings{});
    };
    auto maxDiff = [](const Image& a, const Image& b) {
        double d = 0.0;
        for (size_t i = 0; i < a.rgba.size(); ++i) d = std::max(d, double(std::abs(a.rgba[i] - b.rgba[i])));
        return d;
    };
    const double c = std::cos(std::numbers::pi / 6), s = std::sin(std::numbers::pi / 6);
    Volume turned = v;
    turned.directions = glm::dmat3(glm::dvec3(c, s, 0), glm::dvec3(-s, c, 0), glm::dvec3(0, 0, 1));
    const Image seen = render(turned, Camera{.azimuthDeg = 60.0});
    EXPECT_LT(maxDiff(seen, render(v, Camera{.azimuthDeg = 30.0})), 1e-5);
    EXPECT_GT(maxDiff(seen, render(v, Camera{.azimuthDeg = 60.0})), 0.05) << "the turn must show";

    // 90 degrees about x: a rotation and a permutation, drawn by the plane and by reordering.
    Volume quarter = v;
    quarter.directions = glm::dmat3(glm::dvec3(1, 0, 0), glm::dvec3(0, 0, 1), glm::dvec3(0, -1, 0));
    const Camera oblique{.azimuthDeg = 40.0, .elevationDeg = 25.0};
    EXPECT_LT(maxDiff(render(quarter, oblique), render(alignedToWorldAxes(quarter), oblique)), 1e-5);
}
