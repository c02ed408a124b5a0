// Shading math (shading.h) against independent numbers: quantisation bounds derived from the byte
// layout, GL's fixed-point conversion rule, Phong's closed form for a headlight, the eigenstructure
// of a flattened Gaussian, and Poisson summation for the footprint floor.
#include "renderer/math/shading.h"

#include "renderer/errors.h"
#include "renderer/math/ewa.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <random>

using namespace renderer;

namespace {

constexpr double kFpx = 89.569219; // 48x48 image, vertical fov 30 deg (EWA_NOTES test vectors)
constexpr double kPi = std::numbers::pi;
constexpr double kNormalStep = 0.5 / 127.0;   // worst rounding of one snorm8 octahedral coordinate
constexpr double kFloatUlp = 1.0 / (1 << 24); // relative rounding of the float32 the GPU returns

glm::dmat3 randomRotation(std::mt19937_64& rng) {
    std::normal_distribution<double> n;
    glm::dvec4 q = glm::normalize(glm::dvec4(n(rng), n(rng), n(rng), n(rng)));
    const double w = q.w, x = q.x, y = q.y, z = q.z;
    return glm::transpose(glm::dmat3(1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w),
                                     2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w),
                                     2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)));
}

glm::dvec3 randomUnit(std::mt19937_64& rng) {
    std::normal_distribution<double> n;
    return glm::normalize(glm::dvec3(n(rng), n(rng), n(rng)));
}

// Any unit vector perpendicular to a.
glm::dvec3 perpendicular(glm::dvec3 a) {
    const glm::dvec3 other = std::abs(a.x) < 0.6 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
    return glm::normalize(glm::cross(a, other));
}

// Eigenvalues (lo, hi) of a symmetric 2x2, computed independently of clampFootprintVariance.
glm::dvec2 eigenvalues(const glm::dmat2& v) {
    const double tr = v[0][0] + v[1][1], det = glm::determinant(v);
    const double disc = std::sqrt(std::max(tr * tr / 4 - det, 0.0));
    return {tr / 2 - disc, tr / 2 + disc};
}

bool finite(const glm::dmat2& m) {
    return std::isfinite(m[0][0]) && std::isfinite(m[0][1]) && std::isfinite(m[1][0]) &&
           std::isfinite(m[1][1]);
}
bool finite(const glm::dmat3& m) {
    for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r)
            if (!std::isfinite(m[c][r])) return false;
    return true;
}

// Total of |J| G_V by the trapezoidal rule in V's principal axes (steps of a quarter sigma over +-10
// sigma: for a Gaussian the rule's error is ~exp(-2 pi^2 16), far below double rounding).
double integrateFootprint(const Footprint& f) {
    const glm::dmat2& v = f.variancePx;
    const double b = v[0][1];
    const double theta = 0.5 * std::atan2(2 * b, v[0][0] - v[1][1]);
    const glm::dvec2 e0(std::cos(theta), std::sin(theta)), e1(-std::sin(theta), std::cos(theta));
    const double s0 = std::sqrt(glm::dot(e0, v * e0)), s1 = std::sqrt(glm::dot(e1, v * e1));
    double sum = 0;
    for (int i = -40; i <= 40; ++i)
        for (int j = -40; j <= 40; ++j)
            sum += footprintAt(f, i * s0 / 4 * e0 + j * s1 / 4 * e1);
    return sum * (s0 / 4) * (s1 / 4);
}

} // namespace

// == Packed gradients

TEST(ShadingPack, DecodeUnfoldsTheOctahedronAndNormalises) {
    // Magnitude: GL 4.5 eq. 2.1, unorm c -> c / 255 as float32, squared in float, for every byte; a
    // zero byte means no normal.
    for (int byte = 0; byte < 256; ++byte) {
        const float a = float(byte / 255.0);
        const DecodedGradient d = decodeGradient(uint32_t(byte) << 16);
        EXPECT_EQ(d.magnitude, double(a * a)) << "byte " << byte;
        EXPECT_EQ(d.normal, byte == 0 ? glm::dvec3(0.0) : glm::dvec3(0, 0, 1)) << "byte " << byte;
    }
    // The octahedron's corners and an edge, upper half and folded lower half (u, v as snorm8 bytes).
    const uint32_t w = 0xffu << 16;
    auto at = [&](int u, int v) { return decodeGradient(w | uint32_t(uint8_t(int8_t(u))) | uint32_t(uint8_t(int8_t(v))) << 8).normal; };
    EXPECT_EQ(at(127, 0), glm::dvec3(1, 0, 0));
    EXPECT_EQ(at(-127, 0), glm::dvec3(-1, 0, 0));
    EXPECT_EQ(at(0, 127), glm::dvec3(0, 1, 0));
    EXPECT_EQ(at(0, -128), glm::dvec3(0, -1, 0)); // -128 and -127 both decode to -1
    EXPECT_EQ(at(127, 127), glm::dvec3(0, 0, -1));
    EXPECT_EQ(at(-127, -127), glm::dvec3(0, 0, -1));
    const glm::dvec3 edge = at(0, 64); // v = 64/127: z = 63/127 > 0, not folded
    EXPECT_NEAR(edge.y / edge.z, 64.0 / 63.0, 1e-6);
    EXPECT_EQ(edge.x, 0.0);
    EXPECT_NEAR(glm::length(edge), 1.0, 4 * kFloatUlp);
}

TEST(ShadingPack, RoundTripStaysWithinTheQuantisationBounds) {
    std::mt19937_64 rng(7);
    std::uniform_int_distribution<int> component(-32767, 32767);
    GradientField field;
    field.dims = {17, 13, 11};
    field.scale = 123.4;
    const size_t count = size_t(field.dims.x) * field.dims.y * field.dims.z;
    for (size_t i = 0; i < 3 * count; ++i) {
        // Every third voxel is scaled down by up to 1e-4 so weak gradients are covered too.
        const size_t voxel = i / 3;
        const double shrink = voxel % 3 == 0 ? std::pow(10.0, -4.0 * double(voxel / 3 % 9) / 8.0) : 1.0;
        field.xyz.push_back(int16_t(std::lround(component(rng) * shrink)));
    }
    const PackedGradients packed = packGradients(field);
    ASSERT_EQ(packed.texels.size(), count);
    double maxMagnitude = 0;
    for (size_t i = 0; i < count; ++i)
        maxMagnitude = std::max(maxMagnitude, field.magnitude(i));
    EXPECT_EQ(packed.maxMagnitude, maxMagnitude);

    // Derived bounds. Normal: u and v each round by <= h = 0.5/127, which moves the point on the
    // octahedron by at most sqrt(h^2 + h^2 + (2h)^2) = sqrt(6) h (z = 1 - |u| - |v|; the fold keeps
    // this); the octahedron lies at least 1/sqrt(3) from the centre, so the direction turns by at most
    // asin(sqrt(18) h): 0.96 degrees; plus float rounding.
    const double maxAngle = std::asin(std::sqrt(18.0) * kNormalStep) + 1e-6;
    int weakButNonZero = 0;
    double worst = 0.0;
    for (size_t i = 0; i < count; ++i) {
        const glm::dvec3 g = field.at(i);
        const DecodedGradient d = decodeGradient(packed.texels[i]);
        const double len = glm::length(g);
        if (len == 0) {
            EXPECT_EQ(packed.texels[i], 0u);
            continue;
        }
        EXPECT_EQ(packed.texels[i] >> 24, 0u); // 24 bits
        // Magnitude: a = q/255 is within 0.5/255 of s = sqrt(r), so |a^2 - s^2| <= 0.5/255 (2 s + 0.5/255).
        const double r = len / maxMagnitude, s = std::sqrt(r);
        EXPECT_LE(std::abs(d.magnitude - r), 0.5 / 255 * (2 * s + 0.5 / 255) + 4 * kFloatUlp)
            << "voxel " << i;
        if (d.magnitude == 0) {
            EXPECT_EQ(d.normal, glm::dvec3(0.0));
            continue;
        }
        if (r < 1.0 / 510) ++weakButNonZero; // a linear byte would have zeroed these
        const glm::dvec3 n = g / len;
        const double angle = std::acos(std::min(glm::dot(d.normal, n) / glm::length(d.normal), 1.0));
        worst = std::max(worst, angle);
        EXPECT_LE(angle, maxAngle) << "voxel " << i;
        EXPECT_NEAR(glm::length(d.normal), 1.0, 4 * kFloatUlp);
    }
    std::printf("[ pack     ] worst normal error %.3f degrees (bound %.3f)\n", worst * 180 / kPi, maxAngle * 180 / kPi);
    EXPECT_GT(weakButNonZero, 10); // the sample does reach the range the sqrt encoding is for
    const auto strongest = std::max_element(packed.texels.begin(), packed.texels.end(),
                                            [](uint32_t a, uint32_t b) { return (a >> 16) < (b >> 16); });
    EXPECT_EQ(decodeGradient(*strongest).magnitude, 1.0);
}

TEST(ShadingPack, ZeroAndNonFiniteGradientsDecodeToZero) {
    const double inf = std::numeric_limits<double>::infinity(),
                 nan = std::numeric_limits<double>::quiet_NaN();
    for (glm::dvec3 g :
         {glm::dvec3(0.0), glm::dvec3(-0.0, 0.0, -0.0), glm::dvec3(nan, 1, 0), glm::dvec3(inf, 0, 0)}) {
        EXPECT_EQ(packGradient(g, 10.0), 0u);
        const DecodedGradient d = decodeGradient(packGradient(g, 10.0));
        EXPECT_EQ(d.normal, glm::dvec3(0.0));
        EXPECT_EQ(d.magnitude, 0.0);
    }
    GradientField flat;
    flat.dims = {2, 2, 2};
    flat.xyz.assign(24, 0); // scale 0: a constant volume
    const PackedGradients packed = packGradients(flat);
    EXPECT_EQ(packed.maxMagnitude, 0.0);
    for (uint32_t t : packed.texels)
        EXPECT_EQ(t, 0u);
}

TEST(ShadingPack, AnyTexelDecodesToBoundedFiniteValues) {
    std::mt19937_64 rng(11);
    for (int i = 0; i < 100000; ++i) {
        const DecodedGradient d = decodeGradient(uint32_t(rng()));
        for (int c = 0; c < 3; ++c) {
            ASSERT_TRUE(std::isfinite(d.normal[c]));
            ASSERT_LE(std::abs(d.normal[c]), 1.0 + 4 * kFloatUlp);
        }
        ASSERT_GE(d.magnitude, 0.0);
        ASSERT_LE(d.magnitude, 1.0);
        const glm::dvec3 c = shade(glm::dvec3(0.5), d.gradient(), randomUnit(rng), ShadingParams{});
        ASSERT_TRUE(std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z));
    }
}

// == Headlight Phong

TEST(ShadingPhong, MatchesTheClosedFormForAHeadlight) {
    // Angle t between normal and view: diffuse cos t, and R.V = cos 2t because L = V.
    const ShadingParams p;
    const glm::dvec3 colour(0.8, 0.5, 0.2), toEye(0, 0, -3); // any length
    for (double deg : {0.0, 10.0, 30.0, 44.0, 45.0, 60.0, 89.0, 90.0, 120.0, 180.0}) {
        const double t = deg * kPi / 180;
        const glm::dvec3 n(std::sin(t), 0, -std::cos(t));
        const double c = std::abs(std::cos(t));
        const double spec = std::pow(std::max(std::cos(2 * t), 0.0), p.shininess);
        const glm::dvec3 expected = colour * (p.ambient + p.diffuse * c) + p.specular * spec;
        const glm::dvec3 got = shade(colour, 5.0 * n, toEye, p); // length above flatGradient: fully shaded
        for (int k = 0; k < 3; ++k)
            EXPECT_NEAR(got[k], expected[k], 1e-14) << deg << " deg";
    }
    // Face-on: ambient + diffuse = 1 keeps the TF colour, plus the white highlight.
    const glm::dvec3 faceOn = shade(colour, glm::dvec3(0, 0, 1), toEye, p);
    for (int k = 0; k < 3; ++k)
        EXPECT_NEAR(faceOn[k], colour[k] + p.specular, 1e-15);
}

TEST(ShadingPhong, IsTwoSided) {
    std::mt19937_64 rng(3);
    for (int i = 0; i < 1000; ++i) {
        const glm::dvec3 n = randomUnit(rng), v = randomUnit(rng), colour(0.3, 0.6, 0.9);
        const glm::dvec3 a = shade(colour, n, v, ShadingParams{}), b = shade(colour, -n, v, ShadingParams{});
        for (int k = 0; k < 3; ++k)
            EXPECT_NEAR(a[k], b[k], 1e-15);
    }
}

TEST(ShadingPhong, FadesContinuouslyToUnshadedWithoutAGradient) {
    const ShadingParams p;
    const glm::dvec3 colour(0.2, 0.4, 0.6), toEye(0.1, -0.2, -1),
        n = glm::normalize(glm::dvec3(0.7, 0.1, 0.2));
    EXPECT_EQ(shade(colour, glm::dvec3(0.0), toEye, p), colour); // no normal: unshaded, exactly
    const glm::dvec3 full = shade(colour, n, toEye, p);
    const glm::dvec3 atThreshold = shade(colour, p.flatGradient * n, toEye, p);
    for (int k = 0; k < 3; ++k)
        EXPECT_NEAR(atThreshold[k], full[k], 1e-15);
    // Below flatGradient the result is linear in |g|: |shade - colour| = (|g| / flatGradient) |full -
    // colour|.
    for (double r : {1e-300, 1e-12, 1e-6, 0.25 * p.flatGradient, 0.999999 * p.flatGradient}) {
        const glm::dvec3 got = shade(colour, r * n, toEye, p);
        for (int k = 0; k < 3; ++k)
            EXPECT_NEAR(got[k] - colour[k], r / p.flatGradient * (full[k] - colour[k]), 1e-15) << r;
    }
}

TEST(ShadingPhong, DegenerateDirectionsStayFinite) {
    const ShadingParams p;
    const glm::dvec3 colour(1.0);
    for (glm::dvec3 g : {glm::dvec3(0.0), glm::dvec3(0, 0, 1), glm::dvec3(1e-300, 0, 0)})
        for (glm::dvec3 v : {glm::dvec3(0.0), glm::dvec3(0, 0, -1), glm::dvec3(0, 1e-300, 0)}) {
            const glm::dvec3 c = shade(colour, g, v, p);
            EXPECT_TRUE(std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z));
            EXPECT_GE(c.x, p.ambient - 1e-15); // never darker than ambient
        }
}

// == Surface splats

TEST(ShadingSurface, FlatteningScalesOnlyTheNormalVariance) {
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> unit(0.3, 2.0), flat(1.0, 10.0);
    for (int i = 0; i < 500; ++i) {
        const glm::dvec3 sigma(unit(rng), unit(rng), unit(rng));
        const glm::dmat3 w = randomRotation(rng);
        const glm::dvec3 n = randomUnit(rng), t = perpendicular(n);
        const double s = flat(rng);
        // Back to object space: W^T V W is the flattened object variance.
        const glm::dmat3 obj = glm::transpose(w) * surfaceVarianceCamera(sigma, w, 3.0 * n, s) * w;
        const glm::dmat3 orig(glm::dvec3(sigma.x * sigma.x, 0, 0), glm::dvec3(0, sigma.y * sigma.y, 0),
                              glm::dvec3(0, 0, sigma.z * sigma.z));
        const double scale = sigma.x * sigma.x + sigma.y * sigma.y + sigma.z * sigma.z;
        const double tol = 1e-13 * scale; // a few roundings of products of order sigma^2
        EXPECT_NEAR(glm::dot(n, obj * n), glm::dot(n, orig * n) / (s * s), tol); // 1/s in std deviation
        EXPECT_NEAR(glm::dot(t, obj * t), glm::dot(t, orig * t), tol);           // tangent plane kept
        EXPECT_NEAR(glm::dot(n, obj * t), glm::dot(n, orig * t) / s, tol);       // correlation kept
        // det's relative rounding ~ eps |obj| / lambda_min(obj) <= 2e-16 * 12 / (0.09 / 100) ~ 3e-12.
        EXPECT_NEAR(glm::determinant(obj) / glm::determinant(orig) * (s * s), 1.0, 1e-10);
    }
}

TEST(ShadingSurface, IsotropicKernelBecomesADiscOfTheRightShape) {
    std::mt19937_64 rng(6);
    for (int i = 0; i < 200; ++i) {
        const glm::dmat3 w = randomRotation(rng);
        const glm::dvec3 n = randomUnit(rng), t = perpendicular(n), b = glm::cross(n, t);
        const double sigma = 0.7, s = 1.0 + i;
        const glm::dmat3 v = surfaceVarianceCamera(glm::dvec3(sigma), w, n, s);
        // Eigenvectors W n (eigenvalue sigma^2 / s^2) and the tangent plane (sigma^2, twice).
        const std::pair<glm::dvec3, double> eigenpairs[] = {
            {w * n, sigma * sigma / (s * s)}, {w * t, sigma * sigma}, {w * b, sigma * sigma}};
        for (const auto& [dir, lambda] : eigenpairs) {
            const glm::dvec3 r = v * dir - lambda * dir;
            EXPECT_LT(glm::length(r), 1e-14) << "flatten " << s;
        }
    }
    const glm::dvec3 n = glm::normalize(glm::dvec3(1, 2, 3));
    const glm::dmat3 disc =
        surfaceVarianceCamera(glm::dvec3(0.7), glm::dmat3(1.0), n, std::numeric_limits<double>::infinity());
    EXPECT_LT(glm::length(disc * n), 1e-15); // s = inf: no extent along n at all
}

TEST(ShadingSurface, FlattenOneOrNoNormalIsTheVolumeKernelExactly) {
    std::mt19937_64 rng(8);
    std::uniform_real_distribution<double> unit(0.1, 3.0);
    const double nan = std::numeric_limits<double>::quiet_NaN(),
                 inf = std::numeric_limits<double>::infinity();
    for (int i = 0; i < 200; ++i) {
        const glm::dvec3 sigma(unit(rng), unit(rng), unit(rng));
        const glm::dmat3 w = randomRotation(rng);
        const glm::dmat3 expected = kernelVarianceCamera(sigma, w);
        EXPECT_EQ(surfaceVarianceCamera(sigma, w, randomUnit(rng), 1.0), expected);
        for (glm::dvec3 n : {glm::dvec3(0.0), glm::dvec3(nan, 0, 0), glm::dvec3(0, inf, 0)})
            EXPECT_EQ(surfaceVarianceCamera(sigma, w, n, 8.0), expected);
    }
    EXPECT_THROW(surfaceVarianceCamera(glm::dvec3(1), glm::dmat3(1.0), glm::dvec3(0, 0, 1), 0.5),
                 RenderError);
    EXPECT_THROW(surfaceVarianceCamera(glm::dvec3(1), glm::dmat3(1.0), glm::dvec3(0, 0, 1), nan),
                 RenderError);
}

TEST(ShadingSurface, FlattenedFootprintIntegratesToTheJacobianDeterminant) {
    // Unit mass survives flattening: each mode's footprint still sums to |J|, and |J| does not change.
    std::mt19937_64 rng(9);
    const glm::dvec3 u(-1.2, 0.8, 25.0);
    for (int i = 0; i < 20; ++i) {
        const glm::dmat3 v =
            surfaceVarianceCamera(glm::dvec3(0.5, 0.7, 0.9), randomRotation(rng), randomUnit(rng), 8.0);
        for (FilterMode m : {FilterMode::Reconstruction, FilterMode::LowPass, FilterMode::Ewa}) {
            Footprint f = projectKernel(u, v, kFpx, m);
            f.variancePx = clampFootprintVariance(f.variancePx);
            f.peak = f.jacobianDet / (2 * kPi * std::sqrt(glm::determinant(f.variancePx)));
            EXPECT_DOUBLE_EQ(f.jacobianDet, rayJacobianDet(u, kFpx));
            EXPECT_NEAR(integrateFootprint(f), f.jacobianDet, 1e-9 * f.jacobianDet) << filterModeName(m);
        }
    }
}

TEST(ShadingSurface, EdgeOnFootprintsAreFiniteAndBoundedAfterTheClamp) {
    const double inf = std::numeric_limits<double>::infinity();
    const glm::dvec3 sigma(0.6, 0.8, 1.0);
    const double sigmaMax = 1.0;
    for (bool ortho : {false, true}) {
        for (glm::dvec3 u : {glm::dvec3(0, 0, 20), glm::dvec3(-3, 2, 20), glm::dvec3(5, -4, 8)}) {
            // Edge-on: the normal is perpendicular to the ray through the splat (+z when orthographic).
            const glm::dvec3 ray = ortho ? glm::dvec3(0, 0, 1) : glm::normalize(u);
            for (glm::dvec3 n : {perpendicular(ray), glm::normalize(glm::cross(ray, perpendicular(ray)))}) {
                const glm::dmat3 v = surfaceVarianceCamera(sigma, glm::dmat3(1.0), n, inf);
                // Bound: W S diag(sigma^2) S^T W^T <= sigmaMax^2 I since |S| <= 1, so the footprint of
                // the isotropic sigmaMax kernel bounds every direction.
                const Footprint bound = projectKernel(u, glm::dmat3(sigmaMax * sigmaMax), kFpx,
                                                      FilterMode::Reconstruction, glm::dmat2(1.0), ortho);
                const double boundHi = eigenvalues(bound.variancePx).y;
                const Footprint raw =
                    projectKernel(u, v, kFpx, FilterMode::Reconstruction, glm::dmat2(1.0), ortho);
                EXPECT_LT(eigenvalues(raw.variancePx).x, 1e-9 * boundHi); // singular before the clamp
                for (FilterMode m : {FilterMode::Reconstruction, FilterMode::LowPass, FilterMode::Ewa}) {
                    Footprint f = projectKernel(u, v, kFpx, m, glm::dmat2(1.0), ortho);
                    const glm::dmat2 before = f.variancePx;
                    f.variancePx = clampFootprintVariance(f.variancePx);
                    if (m != FilterMode::Reconstruction) {
                        EXPECT_EQ(f.variancePx, before); // V_h = I: untouched
                    }
                    const glm::dvec2 ev = eigenvalues(f.variancePx);
                    const double extra = m == FilterMode::Reconstruction ? 0.0 : 1.0; // + V_h
                    EXPECT_TRUE(finite(f.variancePx));
                    EXPECT_GE(ev.x, kMinFootprintVariancePx2 - 1e-12 * ev.y) << filterModeName(m);
                    EXPECT_LE(ev.y, std::max(boundHi, kMinFootprintVariancePx2) + extra + 1e-12 * boundHi);
                    const double peak = f.jacobianDet / (2 * kPi * std::sqrt(glm::determinant(f.variancePx)));
                    EXPECT_TRUE(std::isfinite(peak) && peak > 0) << filterModeName(m);
                }
            }
        }
    }
}

TEST(ShadingSurface, RandomNormalsNeverGiveNanOrInf) {
    std::mt19937_64 rng(10);
    std::normal_distribution<double> gauss;
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const double inf = std::numeric_limits<double>::infinity();
    for (int i = 0; i < 20000; ++i) {
        const glm::dvec3 n =
            glm::dvec3(gauss(rng), gauss(rng), gauss(rng)) * std::pow(10.0, 200 * unit(rng) - 100);
        const double flatten = i % 10 == 0 ? inf : std::pow(10.0, 6 * unit(rng));
        const glm::dvec3 sigma(0.1 + unit(rng), 0.1 + unit(rng), 0.1 + unit(rng));
        const glm::dmat3 v = surfaceVarianceCamera(sigma, randomRotation(rng), n, flatten);
        ASSERT_TRUE(finite(v)) << i;
        const glm::dvec3 u(4 * gauss(rng), 4 * gauss(rng), 5 + 50 * unit(rng));
        Footprint f = projectKernel(u, v, kFpx, FilterMode::Reconstruction);
        f.variancePx = clampFootprintVariance(f.variancePx);
        ASSERT_TRUE(finite(f.variancePx)) << i;
        ASSERT_GT(glm::determinant(f.variancePx), 0.0) << i;
    }
}

// == Footprint clamp

TEST(ShadingClamp, LeavesFineMatricesBitForBit) {
    std::mt19937_64 rng(12);
    // 0.1 % above the floor: far more than the ~1e-14 px^2 rounding of building v.
    std::uniform_real_distribution<double> ev(1.001 * kMinFootprintVariancePx2, 100.0), angle(0, kPi);
    for (int i = 0; i < 1000; ++i) {
        const double a = angle(rng), l0 = ev(rng), l1 = ev(rng), c = std::cos(a), s = std::sin(a);
        const glm::dmat2 r(c, s, -s, c);
        const glm::dmat2 v = r * glm::dmat2(l0, 0, 0, l1) * glm::transpose(r);
        EXPECT_EQ(clampFootprintVariance(v), v);
    }
}

TEST(ShadingClamp, RaisesOnlyTheSmallEigenvalue) {
    std::mt19937_64 rng(13);
    std::uniform_real_distribution<double> angle(0, kPi), logSmall(-12, std::log10(0.29)), logBig(0, 6);
    const double floor = kMinFootprintVariancePx2;
    for (int i = 0; i < 1000; ++i) {
        const double a = angle(rng), c = std::cos(a), s = std::sin(a);
        const double lo = i % 7 == 0 ? -1e-9 : std::pow(10.0, logSmall(rng)); // slightly indefinite too
        const double hi = std::pow(10.0, logBig(rng));
        const glm::dvec2 e0(c, s), e1(-s, c);
        const glm::dmat2 v = lo * glm::outerProduct(e0, e0) + hi * glm::outerProduct(e1, e1);
        const glm::dmat2 got = clampFootprintVariance(v, floor);
        EXPECT_EQ(got[0][1], got[1][0]);
        const double tol = 1e-14 * hi; // rounding of order hi in each entry
        EXPECT_LT(glm::length(got * e0 - floor * e0), tol) << "lo " << lo << " hi " << hi;
        EXPECT_LT(glm::length(got * e1 - hi * e1), tol) << "lo " << lo << " hi " << hi;
    }
    EXPECT_EQ(clampFootprintVariance(glm::dmat2(0.1, 0.05, 0.05, 0.1), floor), glm::dmat2(floor));
    EXPECT_EQ(clampFootprintVariance(glm::dmat2(0.0), floor), glm::dmat2(floor));
    // Asymmetric rounding noise in: a symmetric matrix out.
    const glm::dmat2 asym = clampFootprintVariance(glm::dmat2(10, 3 + 1e-12, 3 - 1e-12, 0.9), floor);
    EXPECT_EQ(asym[0][1], asym[1][0]);
}

TEST(ShadingClamp, FloorKeepsPixelSampledMassWithinThePoissonBound) {
    // Sum of G_V(p - x) over the integer lattice = 1 + sum_{k != 0} exp(-2 pi^2 k^T V k) cos(2 pi k.x).
    // With eigenvalues >= floor the ripple is at most theta(q)^2 - 1, q = exp(-2 pi^2 floor).
    const auto ripple = [](const glm::dmat2& v) {
        const glm::dmat2 inv = glm::inverse(v);
        const double norm = 1.0 / (2 * kPi * std::sqrt(glm::determinant(v)));
        double worst = 0;
        for (int ox = 0; ox < 8; ++ox)
            for (int oy = 0; oy < 8; ++oy) {
                double sum = 0;
                for (int i = -16; i <= 16; ++i) // +-8 sigma of the 4 px^2 needles below
                    for (int j = -16; j <= 16; ++j) {
                        const glm::dvec2 d(i - ox / 8.0, j - oy / 8.0);
                        sum += norm * std::exp(-0.5 * glm::dot(d, inv * d));
                    }
                worst = std::max(worst, std::abs(sum - 1));
            }
        return worst;
    };
    const double q = std::exp(-2 * kPi * kPi * kMinFootprintVariancePx2);
    const double theta = 1 + 2 * q + 2 * std::pow(q, 4) + 2 * std::pow(q, 9);
    const double bound = theta * theta - 1;
    EXPECT_LT(bound, 0.011);             // the 1.1 % shading.h quotes
    const auto needle = [](double deg) { // edge-on: 1e-6 px^2 across, 4 px^2 along
        const double a = deg * kPi / 180, c = std::cos(a), s = std::sin(a);
        const glm::dmat2 r(c, s, -s, c);
        return r * glm::dmat2(1e-6, 0, 0, 4) * glm::transpose(r);
    };
    for (double deg : {0.0, 20.0, 45.0, 90.0})
        EXPECT_LE(ripple(clampFootprintVariance(needle(deg))), bound) << deg;
    // Along a pixel row (the worst case) the leading terms 2 q cos(2 pi x) are what is left: the bound
    // is tight there, and a floor of 0.05 px^2 would let the sampled mass swing by more than 50 %.
    EXPECT_GT(ripple(clampFootprintVariance(needle(0))), 0.4 * bound);
    EXPECT_GT(ripple(clampFootprintVariance(needle(0), 0.05)), 0.5);
}

TEST(ShadingGlsl, DeclaresTheMirroredFunctionsWithoutAVersionLine) {
    const std::string src = shadingGlsl();
    EXPECT_EQ(src.find("#version"), std::string::npos);
    for (const char* decl :
         {"struct ShadingParams", "vec3 shade(", "mat3 surfaceVarianceCamera(",
          "mat2 clampFootprintVariance(", "vec4 unpackGradient(uint", "kMinFootprintVariancePx2 = 0.3;"})
        EXPECT_NE(src.find(decl), std::string::npos) << decl;
}
