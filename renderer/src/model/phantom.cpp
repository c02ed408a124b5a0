// makePhantom (phantom.h): a head built from ellipsoids in mm, partial-volume edges, then per-voxel noise
// from a counter hash, so the voxels depend on the seed and dims only, never on the thread count.
#include "renderer/model/phantom.h"

#include "renderer/errors.h"
#include "renderer/io/volume_io.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>

namespace renderer {
namespace {


// == Anatomy, mm from the middle of the cube; x left-right, y front-back, z up.

// An ellipsoid; a neck is an elliptic cylinder along z, which `cylinderTopZ` marks (NaN: an ellipsoid).
struct Shape {
    glm::dvec3 centre;
    glm::dvec3 semiAxes;
    double cylinderTopZ = std::numeric_limits<double>::quiet_NaN();
};

// Head 148 x 184 x 200 mm, its top 10 mm below the cube's; the neck runs from it to the bottom face.
constexpr Shape kHead{{0.0, 0.0, 18.0}, {74.0, 92.0, 100.0}};
constexpr Shape kNeck{{0.0, 12.0, 0.0}, {50.0, 56.0, 0.0}, 18.0};
// Depths below the head's surface where each layer starts (the skull is 7 mm: 2 + 3 + 2).
constexpr double kSkinMm = 2.5;  // skin, then soft tissue
constexpr double kSkullMm = 6.0; // outer table
constexpr double kDiploeMm = 8.0;
constexpr double kInnerTableMm = 11.0;
constexpr double kCsfMm = 13.0; // the skull ends; a CSF gap, then brain
constexpr double kBrainMm = 14.5;
// Inside the brain, clear of the cube's middle (tests measure the brain there): two lateral ventricles,
// a haemorrhage and a calcification.
constexpr Shape kVentricles[] = {{{-11.0, 8.0, 38.0}, {6.0, 24.0, 11.0}},
                                 {{11.0, 8.0, 38.0}, {6.0, 24.0, 11.0}}};
constexpr Shape kBleed{{30.0, -35.0, 45.0}, {9.0, 9.0, 9.0}};
constexpr Shape kCalcification{{0.0, 32.0, 28.0}, {3.5, 3.5, 3.5}};

// `shape` shrunk by an inset on every semi-axis, prepared for one voxel size: coverage() runs for every
// voxel, and most voxels are far from every surface, where one squared radius decides.
struct Layer {
    glm::dvec3 centre, invSemiAxes;
    bool cylinder = false;
    double topZ = 0.0;
    double halfVoxelMm = 0.0;                       // half the voxel's widest extent, sx + sy + sz over 2
    double emptyBeyondSq = 0.0, fullWithinSq = 0.0; // coverage 0 beyond this squared radius, 1 within
};

Layer prepare(const Shape& shape, double insetMm, const glm::dvec3& spacing) {
    Layer l;
    l.centre = shape.centre;
    l.cylinder = !std::isnan(shape.cylinderTopZ);
    const glm::dvec3 semi = shape.semiAxes - insetMm;
    l.invSemiAxes = 1.0 / glm::dvec3(semi.x, semi.y, l.cylinder ? 1.0 : semi.z);
    l.topZ = l.cylinder ? shape.cylinderTopZ - insetMm : 0.0;
    l.halfVoxelMm = 0.5 * (spacing.x + spacing.y + spacing.z);
    // The distance below is at least (1 - |q|) times the smallest semi-axis on either side of the surface,
    // so beyond these radii the voxel is wholly outside or inside.
    const double smallest = l.cylinder ? std::min(semi.x, semi.y) : std::min({semi.x, semi.y, semi.z});
    const double margin = l.halfVoxelMm / smallest;
    l.emptyBeyondSq = (1.0 + margin) * (1.0 + margin);
    l.fullWithinSq = margin < 1.0 ? (1.0 - margin) * (1.0 - margin) : -1.0;
    return l;
}

// The fraction of a voxel at `p` inside `layer`: a ramp across the voxel's width along the surface normal
// (a box filter's, as a scanner averages), 0 or 1 further away. The distance is first order,
// (1 - |q|) / |grad |q||, exact for a sphere and close for these mild ellipsoids near their surface,
// which is where the ramp needs it.
double coverage(const Layer& layer, const glm::dvec3& p, const glm::dvec3& spacing) {
    glm::dvec3 d = p - layer.centre;
    if (layer.cylinder) d.z = 0.0;
    const glm::dvec3 q = d * layer.invSemiAxes;
    const double radiusSq = glm::dot(q, q); // 1 on the surface
    const double capMm = layer.cylinder ? layer.topZ - p.z : std::numeric_limits<double>::infinity();
    if (radiusSq >= layer.emptyBeyondSq || capMm <= -layer.halfVoxelMm) return 0.0;
    if (radiusSq <= layer.fullWithinSq && capMm >= layer.halfVoxelMm) return 1.0;
    const double radius = std::sqrt(radiusSq);
    const glm::dvec3 gradient = q * layer.invSemiAxes; // times |q|: that factor cancels below
    const double gradientLength = glm::length(gradient);
    double depthMm = gradientLength > 0.0 ? (1.0 - radius) * radius / gradientLength
                                          : std::numeric_limits<double>::infinity(); // the centre
    glm::dvec3 normal = gradientLength > 0.0 ? gradient / gradientLength : glm::dvec3(1.0, 0.0, 0.0);
    if (capMm < depthMm) { // nearer a cylinder's top than its side
        depthMm = capMm;
        normal = {0.0, 0.0, 1.0};
    }
    const double widthMm = glm::dot(glm::abs(normal), spacing);
    return std::clamp(0.5 + depthMm / widthMm, 0.0, 1.0);
}

// Every surface of the head, prepared for one voxel size.
struct Anatomy {
    glm::dvec3 spacing;
    Layer head, neck, headBelowSkin, neckBelowSkin, skull, diploe, innerTable, csf, brain;
    Layer ventricles[2], bleed, calcification;

    explicit Anatomy(const glm::dvec3& s)
        : spacing(s), head(prepare(kHead, 0.0, s)), neck(prepare(kNeck, 0.0, s)),
          headBelowSkin(prepare(kHead, kSkinMm, s)), neckBelowSkin(prepare(kNeck, kSkinMm, s)),
          skull(prepare(kHead, kSkullMm, s)), diploe(prepare(kHead, kDiploeMm, s)),
          innerTable(prepare(kHead, kInnerTableMm, s)), csf(prepare(kHead, kCsfMm, s)),
          brain(prepare(kHead, kBrainMm, s)), ventricles{prepare(kVentricles[0], 0.0, s),
                                                         prepare(kVentricles[1], 0.0, s)},
          bleed(prepare(kBleed, 0.0, s)), calcification(prepare(kCalcification, 0.0, s)) {}

    double cover(const Layer& layer, const glm::dvec3& p) const { return coverage(layer, p, spacing); }

    // The noise-free value at voxel centre `p`: each layer, outside in, replaces what is outside it by
    // its coverage (so a 4 mm voxel across the 2.5 mm skin mixes air, skin and soft tissue). Head and neck
    // together: a point is as far inside as it is inside either.
    double tissueHu(const glm::dvec3& p) const {
        const double body = std::max(cover(head, p), cover(neck, p));
        if (body == 0.0) return kPhantomAirHu;
        double hu = kPhantomAirHu + (kPhantomSkinHu - kPhantomAirHu) * body;
        hu += (kPhantomSoftTissueHu - kPhantomSkinHu) *
              std::max(cover(headBelowSkin, p), cover(neckBelowSkin, p));
        const double bone = cover(skull, p);
        if (bone == 0.0) return hu;
        const double inBrain = cover(brain, p);
        if (inBrain < 1.0) { // within a voxel of the skull: all its layers
            hu += (kPhantomCorticalBoneHu - kPhantomSoftTissueHu) * bone;
            hu += (kPhantomDiploeHu - kPhantomCorticalBoneHu) * cover(diploe, p);
            hu += (kPhantomCorticalBoneHu - kPhantomDiploeHu) * cover(innerTable, p);
            hu += (kPhantomCsfHu - kPhantomCorticalBoneHu) * cover(csf, p);
            hu += (kPhantomBrainHu - kPhantomCsfHu) * inBrain;
        } else {
            hu = kPhantomBrainHu;
        }
        for (const Layer& ventricle : ventricles)
            hu += (kPhantomCsfHu - kPhantomBrainHu) * cover(ventricle, p);
        hu += (kPhantomBleedHu - kPhantomBrainHu) * cover(bleed, p);
        hu += (kPhantomCalcificationHu - kPhantomBrainHu) * cover(calcification, p);
        return hu;
    }
};

// == Noise: two standard normals per pair of voxels (Box-Muller), from a hash of the seed and the pair's
// index, so any thread computes any voxel's noise alone.

// SplitMix64's finaliser: a bijection, so distinct (seed, pair) keys give distinct hashes.
uint64_t hash64(uint64_t x) {
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    return x ^ (x >> 31);
}

struct NormalPair {
    float first, second;
};

NormalPair normalPair(uint32_t seed, uint64_t pair) {
    // Pairs number at most kMaxVoxels / 2, under 2^32, so the seed in the high bits never meets them.
    const uint64_t h = hash64((uint64_t(seed) << 32 | pair) + 0x9e3779b97f4a7c15ull);
    // Two 24-bit uniforms in (0, 1), in float (twice as fast as double here; the noise needs no more):
    // the +0.5 keeps log() finite, and makes the largest |normal| 5.9.
    const float u1 = (float(h >> 40) + 0.5f) * 0x1p-24f,
                u2 = (float((h >> 16) & 0xffffffu) + 0.5f) * 0x1p-24f;
    const float r = std::sqrt(-2.0f * std::log(u1)), angle = 2.0f * std::numbers::pi_v<float> * u2;
    return {r * std::cos(angle), r * std::sin(angle)};
}

std::string sizeText(glm::ivec3 dims) {
    return std::to_string(dims.x) + " x " + std::to_string(dims.y) + " x " + std::to_string(dims.z);
}

// Everything makePhantom refuses, before it allocates.
void checkOptions(const PhantomOptions& o) {
    if (o.dims.x < 1 || o.dims.y < 1 || o.dims.z < 1)
        throw RenderError("phantom: size " + sizeText(o.dims) + ": every axis needs at least 1 voxel");
    if (!(o.noiseHu >= 0.0 && o.noiseHu <= 1000.0))
        throw RenderError("phantom: noise " + std::to_string(o.noiseHu) + " HU, expected 0 to 1000");
    // In double so the product cannot wrap before it is compared.
    const double voxels = double(o.dims.x) * double(o.dims.y) * double(o.dims.z);
    if (voxels > double(kMaxVoxels))
        throw RenderError("phantom: size " + sizeText(o.dims) + " is more than the " +
                          std::to_string(kMaxVoxels) + " voxels a volume may have");
    if (const auto why = overMemoryBudget(uint64_t(voxels), VoxelType::I16))
        throw RenderError("phantom: size " + sizeText(o.dims) + " voxels " + *why);
}

} // namespace

Volume makePhantom(const PhantomOptions& options) {
    // 1. Refuse what cannot be made, before allocating.
    checkOptions(options);
    Volume volume;
    volume.name = "phantom";
    volume.type = VoxelType::I16;
    volume.dims = options.dims;
    volume.spacing = kPhantomFieldMm / glm::dvec3(options.dims);
    volume.origin = -0.5 * volume.spacing * glm::dvec3(options.dims - 1); // (0,0,0) mid-cube
    std::vector<int16_t> hu16(volume.voxelCount());   // whole HU, as a CT stores them

    // 2. Tissue plus noise, a slice per task. Tissues stay within [-1000, 1400] HU and the noise within
    // 5.9 sigma <= 5900 HU, so rounding to a whole HU always fits int16.
    const Anatomy anatomy(volume.spacing);
    tbb::parallel_for(0, volume.dims.z, [&](int z) {
        for (int y = 0; y < volume.dims.y; ++y) {
            const size_t row = volume.index(0, y, z);
            NormalPair noise{0.0f, 0.0f};
            for (int x = 0; x < volume.dims.x; ++x) {
                const size_t i = row + size_t(x);
                if (options.noiseHu > 0.0 && (x == 0 || i % 2 == 0)) noise = normalPair(options.seed, i / 2);
                const double n = i % 2 == 0 ? noise.first : noise.second;
                const double hu =
                    std::round(anatomy.tissueHu(volume.positionOf(x, y, z)) + options.noiseHu * n);
                assert(hu >= -32768.0 && hu <= 32767.0 &&
                       "tissue and noise bounds keep every voxel within int16");
                hu16[i] = int16_t(hu);
            }
        }
    });
    volume.values = std::move(hu16);

    // 3. The range, as every loader leaves it.
    updateRange(volume);
    return volume;
}

} // namespace renderer
