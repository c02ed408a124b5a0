// The footprint inspector's inset (ui/footprint_inspector.h): its ellipses are the footprint's at the
// cutoff times one magnification, whole when it magnifies, and the largest fits the inset.
#include "ui/footprint_inspector.h"

#include <gtest/gtest.h>

#include <cmath>

TEST(FootprintInspector, TheInsetDrawsTheFootprintsEllipsesAtOneMagnificationThatFits) {
    renderer::FootprintInspection f;
    f.cutoffSigmas = 3.0;
    f.reconstruction = glm::dmat2(4.0, 1.0, 1.0, 2.25);
    f.lowPass = glm::dmat2(1.0);
    f.ewa = f.reconstruction + f.lowPass;
    for (const float side : {224.0f, 20.0f}) {
        const ui::FootprintInset inset = ui::footprintInset(f, side);
        const double m = inset.magnification;
        if (m >= 1.0) {
            EXPECT_EQ(m, std::floor(m)) << "the pixel grid needs whole squares";
        }
        EXPECT_LE(inset.ellipses[2].semiAxesPx.x, 0.45 * side + 1e-9) << "EWA's ellipse leaves the inset";
        EXPECT_GT(inset.ellipses[2].semiAxesPx.x, 0.45 * side * (m >= 1.0 ? 0.5 : 0.999)) << "it could be larger";
        const std::array<const glm::dmat2*, 3> variances{&f.reconstruction, &f.lowPass, &f.ewa};
        for (size_t k = 0; k < 3; ++k) {
            const renderer::Ellipse e = renderer::ellipseOf(*variances[k], 3.0);
            EXPECT_NEAR(inset.ellipses[k].semiAxesPx.x, e.semiAxesPx.x * m, 1e-9);
            EXPECT_NEAR(inset.ellipses[k].semiAxesPx.y, e.semiAxesPx.y * m, 1e-9);
            EXPECT_EQ(inset.ellipses[k].angleRad, e.angleRad);
        }
    }
}
