// Speed against error (speed_error.h): which settings are measured, the percentiles of the frame times,
// and the Pareto front on hand-made points, ties included.
#include "renderer/oracle/speed_error.h"

#include "renderer/errors.h"

#include <gtest/gtest.h>

#include <limits>

using namespace renderer;

namespace {

FilterMeasurement point(double ms, double db) {
    FilterMeasurement m;
    m.frameMs = ms;
    m.psnrDb = db;
    return m;
}

std::vector<bool> front(std::initializer_list<FilterMeasurement> points) {
    const std::vector<FilterMeasurement> v(points);
    return paretoFront(v);
}

} // namespace

TEST(SpeedError, EveryFilterTimesEveryCompositingModeKeepingTheOtherSettings) {
    SplatSettings base;
    base.density = 3.0;
    base.primitive = SplatSettings::Primitive::Tiles;
    const std::vector<SplatSettings> all = speedErrorSettings(base);
    ASSERT_EQ(all.size(), 16u);
    for (size_t i = 0; i < all.size(); ++i) {
        EXPECT_EQ(all[i].density, 3.0);
        for (size_t j = 0; j < i; ++j)
            EXPECT_FALSE(all[i].filter == all[j].filter && all[i].compositing == all[j].compositing)
                << i << " " << j;
        // Tiles composite sheets and X-ray only: splat-every-sample takes auto (the rasteriser).
        EXPECT_EQ(all[i].primitive, all[i].compositing == Compositing::SplatEverySample
                                        ? SplatSettings::Primitive::Auto
                                        : SplatSettings::Primitive::Tiles);
    }
    base.surfaceFlatten = 4.0;
    EXPECT_TRUE(speedErrorSettings(base).empty()) << "surface splats have no ground truth";
}

TEST(SpeedError, PercentilesInterpolateBetweenRanks) {
    EXPECT_DOUBLE_EQ(percentile({4, 1, 3, 2}, 0.5), 2.5);
    EXPECT_DOUBLE_EQ(percentile({10, 20, 30, 40, 50, 60, 70, 80, 90, 100, 110}, 0.1), 20.0);
    EXPECT_DOUBLE_EQ(percentile({10, 20, 30, 40, 50, 60, 70, 80, 90, 100, 110}, 0.9), 100.0);
    EXPECT_DOUBLE_EQ(percentile({1, 2}, 0.1), 1.1);
    EXPECT_DOUBLE_EQ(percentile({7}, 0.9), 7.0);
    EXPECT_THROW(percentile({}, 0.5), RenderError);
}

TEST(SpeedError, TheParetoFrontKeepsThePointsNoOtherIsBothFasterAndCloser) {
    // a fast and rough, b slower and closer, c dominated by b (slower and worse), d the closest.
    EXPECT_EQ(front({point(10, 20), point(20, 30), point(25, 28), point(40, 45)}),
              (std::vector<bool>{true, true, false, true}));
    // One point that is faster and closer than all the others: it alone.
    EXPECT_EQ(front({point(5, 50), point(10, 20), point(20, 30)}), (std::vector<bool>{true, false, false}));
    EXPECT_TRUE(paretoFront(std::vector<FilterMeasurement>{}).empty());
}

TEST(SpeedError, TiesStayOnTheFrontUnlessSomethingIsBetterInOneAndNoWorseInTheOther) {
    // Equal points do not push each other off.
    EXPECT_EQ(front({point(10, 30), point(10, 30)}), (std::vector<bool>{true, true}));
    // Same time, less error wins; same error, less time wins.
    EXPECT_EQ(front({point(10, 30), point(10, 31)}), (std::vector<bool>{false, true}));
    EXPECT_EQ(front({point(12, 30), point(10, 30)}), (std::vector<bool>{false, true}));
    // An identical image (+inf dB) is the closest there is.
    EXPECT_EQ(front({point(30, std::numeric_limits<double>::infinity()), point(40, 60), point(10, 20)}),
              (std::vector<bool>{true, false, true}));
}

TEST(SpeedError, XRayHasAFrontOfItsOwnSinceItsErrorIsAgainstAnotherImage) {
    FilterMeasurement xray = point(5, 50);
    xray.compositing = Compositing::XRay;
    // Faster and closer, but against X-ray's truth: it does not push the attenuating point off.
    EXPECT_EQ(front({point(10, 30), xray}), (std::vector<bool>{true, true}));
    FilterMeasurement slowXRay = point(20, 20);
    slowXRay.compositing = Compositing::XRay;
    EXPECT_EQ(front({point(10, 30), xray, slowXRay}), (std::vector<bool>{true, true, false}));
}

TEST(SpeedError, PostClassifiedSlabsHaveAFrontOfTheirOwnPreClassifiedSlabsCompeteWithTheSheets) {
    FilterMeasurement post = point(5, 50), pre = point(5, 50);
    post.slabThickness = pre.slabThickness = 0.5;
    post.postClassified = true;
    // Faster and closer, but against the post-classified truth: the sheets' point stays on its front.
    EXPECT_EQ(front({point(10, 30), post}), (std::vector<bool>{true, true}));
    // Pre-classified slabs share the sheets' truth: faster and closer, they push the sheets off.
    EXPECT_EQ(front({point(10, 30), pre}), (std::vector<bool>{false, true}));
    EXPECT_FALSE(sameGroundTruth(post, pre));
    EXPECT_TRUE(sameGroundTruth(pre, point(1, 1)));
}
