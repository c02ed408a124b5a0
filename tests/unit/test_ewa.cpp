// The footprint math against independent numbers: EWA_NOTES' test vectors, finite differences, and
// the exact line integral of the 3D Gaussian along the ray through its centre.
#include "renderer/math/ewa.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

using namespace renderer;

namespace {

constexpr double kFpx = 89.569219;   // 48x48 image, vertical fov 30 deg (EWA_NOTES test vectors)

glm::dmat3 diag(double a, double b, double c) {
    return glm::dmat3(glm::dvec3(a, 0, 0), glm::dvec3(0, b, 0), glm::dvec3(0, 0, c));
}

// Random rotation from a random unit quaternion.
glm::dmat3 randomRotation(std::mt19937_64& rng) {
    std::normal_distribution<double> n;
    glm::dvec4 q(n(rng), n(rng), n(rng), n(rng));
    q = glm::normalize(q);
    const double w = q.w, x = q.x, y = q.y, z = q.z;
    return glm::transpose(glm::dmat3(1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w),
                                     2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w),
                                     2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)));
}

// Exact line integral of the unit-mass 3D Gaussian (variance v, centre u) along the ray from the
// origin through u. Along the ray the integrand is a 1D Gaussian in s with width 1/sqrt(d^T V^-1 d);
// the trapezoidal rule on a Gaussian converges geometrically, so a step of a quarter width over
// +-14 widths is accurate to ~1e-16 relative.
double lineIntegralThroughCentre(glm::dvec3 u, const glm::dmat3& v) {
    const glm::dmat3 inv = glm::inverse(v);
    const glm::dvec3 d = glm::normalize(u);
    const double width = 1.0 / std::sqrt(glm::dot(d, inv * d));
    const double s0 = glm::length(u), h = 0.25 * width;
    const double norm = 1.0 / (std::pow(2.0 * std::numbers::pi, 1.5) * std::sqrt(glm::determinant(v)));
    double sum = 0.0;
    for (int i = -56 * 4; i <= 56 * 4; ++i) {
        const glm::dvec3 x = (s0 + i * h / 4.0) * d - u;
        sum += norm * std::exp(-0.5 * glm::dot(x, inv * x));
    }
    return sum * h / 4.0;
}

} // namespace

TEST(EwaFootprint, MatchesTestVectorIsotropic) {
    const glm::dvec3 u(-0.3, -0.2, 30);
    const glm::dmat3 v = diag(0.49, 0.49, 0.49);
    const Footprint ewa = projectKernel(u, v, kFpx, FilterMode::Ewa);
    EXPECT_NEAR(ewa.offsetPx.x, -0.895692, 1e-6);
    EXPECT_NEAR(ewa.offsetPx.y, -0.597128, 1e-6);
    EXPECT_NEAR(ewa.jacobianDet, 8.914694, 1e-6);
    EXPECT_NEAR(ewa.variancePx[0][0], 5.368321, 1e-6);
    EXPECT_NEAR(std::abs(ewa.variancePx[0][1]), 0.000291, 1e-6);
    EXPECT_NEAR(ewa.variancePx[1][1], 5.368079, 1e-6);
    EXPECT_NEAR(ewa.peak, 0.264300, 1e-6);
    EXPECT_NEAR(projectKernel(u, v, kFpx, FilterMode::Reconstruction).peak, 0.324806, 1e-6);
    EXPECT_NEAR(projectKernel(u, v, kFpx, FilterMode::LowPass).peak, 1.418818, 1e-6);
}

TEST(EwaFootprint, MatchesTestVectorAnisotropic) {
    const glm::dvec3 u(-5, 3, 40);
    const glm::dmat3 v = diag(0.49, 0.49, 4.41);
    const Footprint ewa = projectKernel(u, v, kFpx, FilterMode::Ewa);
    EXPECT_NEAR(ewa.jacobianDet, 5.067148, 1e-6);
    EXPECT_NEAR(ewa.variancePx[0][0], 3.802442, 1e-6);
    EXPECT_NEAR(std::abs(ewa.variancePx[0][1]), 0.207304, 1e-6);
    EXPECT_NEAR(ewa.variancePx[1][1], 3.581317, 1e-6);
    EXPECT_NEAR(ewa.peak, 0.218886, 1e-6);
    EXPECT_NEAR(projectKernel(u, v, kFpx, FilterMode::Reconstruction).peak, 0.300738, 1e-6);
    EXPECT_NEAR(projectKernel(u, v, kFpx, FilterMode::LowPass).peak, 0.806462, 1e-6);
}

TEST(EwaFootprint, CutoffSumMatchesTestVector) {
    // 48x48 image, principal point at the centre, 3-sigma cutoff: the sum is 8.8219 (EWA_NOTES).
    const Footprint f = projectKernel({-0.3, -0.2, 30}, diag(0.49, 0.49, 0.49), kFpx, FilterMode::Ewa);
    double sum = 0.0;
    for (int y = 0; y < 48; ++y)
        for (int x = 0; x < 48; ++x) {
            const glm::dvec2 d = glm::dvec2(x + 0.5 - 24.0, y + 0.5 - 24.0) - f.offsetPx;
            if (footprintRadius2(f, d) <= 9.0) sum += footprintAt(f, d);
        }
    EXPECT_NEAR(sum, 8.8219, 1e-4);
}

TEST(EwaJacobian, DeterminantIsClosedForm) {
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> xy(-20, 20), z(0.5, 80);
    for (int i = 0; i < 200; ++i) {
        const glm::dvec3 u(xy(rng), xy(rng), z(rng));
        const double det = glm::determinant(rayJacobianPx(u, kFpx));
        EXPECT_NEAR(det / rayJacobianDet(u, kFpx), 1.0, 1e-12) << "u = " << u.x << "," << u.y << "," << u.z;
    }
}

TEST(EwaJacobian, MatchesFiniteDifferences) {
    // The map camera -> (f u0/u2, f u1/u2, |u|) differentiated by central differences.
    auto map = [](glm::dvec3 u) { return glm::dvec3(kFpx * u.x / u.z, kFpx * u.y / u.z, glm::length(u)); };
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> xy(-10, 10), z(1, 50);
    for (int i = 0; i < 100; ++i) {
        const glm::dvec3 u(xy(rng), xy(rng), z(rng));
        const glm::dmat3 j = rayJacobianPx(u, kFpx);
        for (int col = 0; col < 3; ++col) {
            glm::dvec3 h(0.0);
            h[col] = 1e-5 * glm::length(u);
            const glm::dvec3 fd = (map(u + h) - map(u - h)) / (2.0 * h[col]);
            for (int row = 0; row < 3; ++row)
                EXPECT_NEAR(j[col][row], fd[row], 1e-6 * (1.0 + std::abs(fd[row])));
        }
    }
}

TEST(EwaFootprint, CentreRayEqualsExactLineIntegral) {
    // On the ray through the kernel's centre the affine approximation is exact: the closed-form
    // reconstruction footprint equals the line integral of the 3D Gaussian to rounding.
    std::mt19937_64 rng(2026);
    std::uniform_real_distribution<double> scale(0.1, 3.0), depth(4.0, 200.0), lateral(-0.6, 0.6);
    for (int i = 0; i < 300; ++i) {
        const glm::dmat3 r = randomRotation(rng);
        const glm::dmat3 v = r * diag(scale(rng), scale(rng), scale(rng)) * glm::transpose(r);
        const double z = depth(rng);
        const glm::dvec3 u(lateral(rng) * z, lateral(rng) * z, z);
        const Footprint f = projectKernel(u, v, kFpx, FilterMode::Reconstruction);
        const double exact = lineIntegralThroughCentre(u, v);
        EXPECT_NEAR(f.peak / exact, 1.0, 1e-9) << "sample " << i;
    }
}

TEST(EwaFootprint, IsotropicCentreValueIsInverseTwoPiSigmaSquared) {
    for (double sigma : {0.3, 0.7, 2.0}) {
        const Footprint f = projectKernel({0, 0, 25}, diag(sigma * sigma, sigma * sigma, sigma * sigma), kFpx,
                                          FilterMode::Reconstruction);
        EXPECT_NEAR(f.peak, 1.0 / (2.0 * std::numbers::pi * sigma * sigma), 1e-12);
    }
}

TEST(EwaFootprint, EveryModeIntegratesToJacobianDeterminant) {
    // The |J| normaliser in all three filters: each deposits the same total, so patches that switch
    // modes leave no seam in brightness. Integrate each footprint on a fine grid (0.05 px).
    const glm::dvec3 u(2.0, -1.0, 30.0);
    const glm::dmat3 v = diag(0.8, 0.3, 1.1);
    for (auto mode : {FilterMode::Reconstruction, FilterMode::LowPass, FilterMode::Ewa}) {
        const Footprint f = projectKernel(u, v, kFpx, mode);
        const double h = 0.05;
        double sum = 0.0;
        for (double y = -30; y <= 30; y += h)
            for (double x = -30; x <= 30; x += h) sum += footprintAt(f, {x, y});
        EXPECT_NEAR(sum * h * h / f.jacobianDet, 1.0, 1e-6) << filterModeName(mode);
    }
}
