// Reference integrator (see ground_truth.h). Per ray: (1) gather the visible kernels whose cutoff
// ellipsoid the ray crosses; (2) write each as a 1D Gaussian on an interval of the ray parameter;
// (3) integrate with steps of length h, each step's optical depth and emission in closed form; halve h
// until the result settles.
#include "renderer/oracle/ground_truth.h"
#include "renderer/oracle/ground_truth_cache.h"
#include "renderer/oracle/pixel_filter.h"

#include "renderer/errors.h"
#include "renderer/math/shading.h"
#include "renderer/model/post_classification.h"
#include "renderer/oracle/ray_kernel.h"
#include "renderer/oracle/reference_renderer.h"
#include "renderer/out_of_memory.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <mutex>
#include <numbers>

namespace renderer {

namespace {

struct Ray {
    glm::dvec3 origin, dir;   // object space, dir unit length
    double start = 0.0;       // first parameter in front of the near plane
};

class Integrator {
public:
    Integrator(const SplatScene& scene, const SplatSettings& settings, const glm::dmat3& viewFromObject, bool post)
        : m_scene(scene), m_settings(settings), m_viewFromObject(viewFromObject),
          m_shaded(settings.shading != SplatSettings::Shading::None), m_post(post) {
        m_sigma = settings.kernelScale * scene.spacing;
        m_kernelPeak = kernelPeak(scene.spacing, m_sigma, settings.cutoffSigmas);
        m_reach = glm::ivec3(glm::ceil(glm::dvec3(settings.cutoffSigmas * settings.kernelScale)));
    }

    // Visible kernels whose truncated support the ray crosses, as 1D Gaussians along it.
    std::vector<RayKernel> gather(const Ray& ray) const {
        std::vector<uint32_t> ids;
        const glm::ivec3 d = m_scene.dims;
        const glm::dvec3 lo = m_scene.origin - m_settings.cutoffSigmas * m_sigma;
        const glm::dvec3 hi = m_scene.origin + m_scene.spacing * glm::dvec3(d - 1) + m_settings.cutoffSigmas * m_sigma;
        double s0 = ray.start, s1 = 1e300;
        for (int a = 0; a < 3; ++a) {   // slab test against the kernels' bounding box
            if (std::abs(ray.dir[a]) < 1e-300) {
                if (ray.origin[a] < lo[a] || ray.origin[a] > hi[a]) return {};
                continue;
            }
            double t0 = (lo[a] - ray.origin[a]) / ray.dir[a], t1 = (hi[a] - ray.origin[a]) / ray.dir[a];
            if (t0 > t1) std::swap(t0, t1);
            s0 = std::max(s0, t0);
            s1 = std::min(s1, t1);
        }
        if (s1 <= s0) return {};
        // March at half the smallest spacing; each sample's neighbourhood holds every kernel within
        // the cutoff of the ray between samples. Along a straight ray the boxes move monotonically on
        // each axis, so what a box shares with any earlier one it shares with the one before: only
        // the voxels it adds are visited, each once (visiting whole boxes and sorting out the repeats
        // was most of a reference's time).
        const double step = 0.5 * std::min({m_scene.spacing.x, m_scene.spacing.y, m_scene.spacing.z});
        glm::ivec3 pa(1), pb(0);   // the previous box (none yet: empty)
        for (double s = s0; s <= s1 + step; s += step) {
            const glm::dvec3 q = (ray.origin + s * ray.dir - m_scene.origin) / m_scene.spacing;
            const glm::ivec3 c(glm::round(q));
            const glm::ivec3 a = glm::max(c - m_reach - 1, glm::ivec3(0)), b = glm::min(c + m_reach + 1, d - 1);
            if (a == pa && b == pb) continue;
            const bool none = glm::any(glm::greaterThan(pa, pb));
            const auto add = [&](int x0, int x1, int y, int z) {
                for (int x = x0; x <= x1; ++x) {
                    const uint32_t i = uint32_t((size_t(z) * d.y + y) * d.x + x);
                    // Post-classified, transparent voxels count too: they pull the mean value down.
                    if (m_post || m_scene.opacityOf(i) > 0.0f) ids.push_back(i);
                }
            };
            for (int z = a.z; z <= b.z; ++z)
                for (int y = a.y; y <= b.y; ++y) {
                    if (none || z < pa.z || z > pb.z || y < pa.y || y > pb.y) {
                        add(a.x, b.x, y, z);
                    } else {   // the row minus the previous box's part of it
                        add(a.x, std::min(b.x, pa.x - 1), y, z);
                        add(std::max(a.x, pb.x + 1), b.x, y, z);
                    }
                }
            pa = a, pb = b;
        }
        std::sort(ids.begin(), ids.end());   // the kernels' order, as it always was

        std::vector<RayKernel> kernels;
        for (uint32_t i : ids) {
            std::optional<RayKernel> along = kernelAlongRay(ray.origin, ray.dir, m_scene.positionOf(i),
                                                            m_sigma, m_settings.cutoffSigmas, m_kernelPeak);
            if (!along) continue;
            RayKernel& k = *along;
            k.extinction = voxelExtinction(m_scene, m_settings, i);
            k.colour = m_scene.colourOf(i);
            k.value = m_scene.classes[i];
            // Shaded: the kernel's colour lit along this very ray (the Phong of shading.h with the
            // voxel's gradient, as both renderers decode it); per-splat shading approximates the ray's
            // direction by the splat centre's, per-fragment by the pixel centre's.
            // Post-classified, the gradients are averaged like the values and lit after classification.
            if (m_shaded) k.gradient = m_viewFromObject * decodeGradient(m_scene.gradients[i]).gradient();
            if (m_shaded && !m_post)
                k.colour = shade(k.colour, k.gradient, -(m_viewFromObject * ray.dir), m_settings.shadingParams);
            if (k.mid + k.halfLength > ray.start) kernels.push_back(k);
        }
        std::sort(kernels.begin(), kernels.end(),
                  [](const RayKernel& p, const RayKernel& q) { return p.mid - p.halfLength < q.mid - q.halfLength; });
        return kernels;
    }

    // RGBA (premultiplied) of one ray with steps of length h. X-ray: no attenuation, the ray's whole
    // emission E and optical depth D, shown as the renderer resolves its sum: 1 - exp(-x) of each of
    // (E, D) (exact at any h: the steps' integrals are).
    static glm::dvec4 march(const std::vector<RayKernel>& kernels, double start, double h, bool xray) {
        if (kernels.empty()) return glm::dvec4(0.0);
        double end = start;
        for (const auto& k : kernels) end = std::max(end, k.mid + k.halfLength);
        double s = std::max(start, kernels.front().mid - kernels.front().halfLength);
        glm::dvec3 colour(0.0), emissionSum(0.0);
        double transmittance = 1.0, depthSum = 0.0;
        size_t first = 0;   // kernels before it ended before the current step
        std::vector<ErfAt> erfs(kernels.size());
        while (s < end && (xray || transmittance > 1e-12)) {
            const double s1 = s + h;
            double depth = 0.0;
            glm::dvec3 emission(0.0);
            for (size_t j = first; j < kernels.size(); ++j) {
                const RayKernel& k = kernels[j];
                if (k.mid - k.halfLength >= s1) break;   // sorted by start: none further overlaps
                const double tau = k.extinction * integrate(k, s, s1, erfs[j]);
                depth += tau;
                emission += k.colour * tau;
            }
            while (first < kernels.size() && kernels[first].mid + kernels[first].halfLength <= s1) ++first;
            depthSum += depth;
            emissionSum += emission;
            if (depth > 0.0 && !xray) {
                const double a = -std::expm1(-depth);
                colour += transmittance * (emission / depth) * a;
                transmittance *= 1.0 - a;
            }
            s = s1;
        }
        if (xray)
            return glm::dvec4(-std::expm1(-emissionSum.r), -std::expm1(-emissionSum.g), -std::expm1(-emissionSum.b),
                              -std::expm1(-depthSum));
        return glm::dvec4(colour, 1.0 - transmittance);
    }

    // Post-classified RGBA of one ray with steps of length h: each step's weight W = sum of the kernels'
    // integrals over it and value V / W (V weighting each by its class), classified by the LUT; the step's
    // optical depth is the TF's extinction at that value times W. Shaded, lit with the step's mean
    // gradient from `toEye` (classifyPost).
    glm::dvec4 marchPost(const std::vector<RayKernel>& kernels, double start, double h, glm::dvec3 toEye) const {
        if (kernels.empty()) return glm::dvec4(0.0);
        const double perOpacity = extinctionPerOpacity(m_scene, m_settings);
        double end = start;
        for (const auto& k : kernels) end = std::max(end, k.mid + k.halfLength);
        double s = std::max(start, kernels.front().mid - kernels.front().halfLength);
        glm::dvec3 colour(0.0);
        double transmittance = 1.0;
        size_t first = 0;
        std::vector<ErfAt> erfs(kernels.size());
        while (s < end && transmittance > 1e-12) {
            const double s1 = s + h;
            PostSample sample;
            for (size_t j = first; j < kernels.size(); ++j) {
                const RayKernel& k = kernels[j];
                if (k.mid - k.halfLength >= s1) break;
                const double w = integrate(k, s, s1, erfs[j]);
                sample.weight += w;
                sample.valueSum += k.value * w;
                sample.gradientSum += k.gradient * w;
            }
            while (first < kernels.size() && kernels[first].mid + kernels[first].halfLength <= s1) ++first;
            const glm::dvec4 rgba =
                classifyPost(m_scene.lut, perOpacity, sample, m_shaded ? &m_settings.shadingParams : nullptr, toEye);
            colour += transmittance * glm::dvec3(rgba);
            transmittance *= 1.0 - rgba.a;
            s = s1;
        }
        return glm::dvec4(colour, 1.0 - transmittance);
    }

    double smallestSigma() const { return std::min({m_sigma.x, m_sigma.y, m_sigma.z}); }

private:
    const SplatScene& m_scene;
    const SplatSettings& m_settings;
    glm::dmat3 m_viewFromObject;
    bool m_shaded = false;
    bool m_post = false;
    glm::dvec3 m_sigma;
    double m_kernelPeak = 0.0;
    glm::ivec3 m_reach{3};
};

} // namespace

static Image renderGroundTruthOrThrow(const SplatScene& scene, const ImagePlane& plane, const SplatSettings& settings,
                                     const GroundTruthOptions& options, const Progress& progress,
                                     GroundTruthStats* stats) {
    const auto t0 = std::chrono::steady_clock::now();
    if (!(options.tolerance > 0.0)) throw RenderError("ground truth: tolerance must be > 0");
    if (options.supersample < 0 || options.supersample > 8)
        throw RenderError("ground truth: supersample must be 0..8, got " + std::to_string(options.supersample));
    const bool filtered = options.supersample > 0;

    // 1. Unfiltered rays on a grid of `ss` samples per pixel, with a margin for the filter's reach.
    //    Sample i sits at pixel coordinate (i + 0.5) / ss - margin / ss.
    const int ss = std::max(options.supersample, 1);
    const int margin = filtered ? pixelFilterMargin(ss) : 0;
    const int gw = plane.width * ss + 2 * margin, gh = plane.height * ss + 2 * margin;
    const auto samplePx = [&](int i) { return (i - margin + 0.5) / ss; };

    if (!hasGroundTruth(settings))
        throw RenderError("ground truth: surface splats have none (flattened kernels are not the volume's)");
    requireGradients(settings, scene.gradients.size() == scene.classes.size(), scene.name);
    const bool xray = settings.compositing == Compositing::XRay;
    if (options.postClassified) {
        requirePostClassifiable(scene, settings, "ground truth");
        if (xray) throw RenderError("ground truth: post-classification composites in order, not as X-ray's sum");
    }
    const Integrator integrator(scene, settings, plane.viewFromObject, options.postClassified);
    const auto march = [&](const std::vector<RayKernel>& kernels, const Ray& ray, double h) {
        return options.postClassified ? integrator.marchPost(kernels, ray.start, h, -(plane.viewFromObject * ray.dir))
                                      : Integrator::march(kernels, ray.start, h, xray);
    };
    const glm::dmat3 objectFromView = glm::transpose(plane.viewFromObject);
    const glm::dvec3 eye = objectFromView * -plane.translation;
    std::vector<glm::dvec4> samples(size_t(gw) * size_t(gh));
    std::atomic<uint64_t> unconverged{0}, halvings{0};
    std::atomic<int> rowsDone{0};
    std::atomic<bool> cancelled{false};
    std::mutex progressMutex;
    tbb::parallel_for(0, gh, [&](int j) {
        if (cancelled) return;
        for (int i = 0; i < gw; ++i) {
            const glm::dvec2 m = (glm::dvec2(samplePx(i), samplePx(j)) - plane.centrePx) / plane.fPx;
            Ray ray;
            if (plane.orthographic) {
                ray.origin = objectFromView * (glm::dvec3(m, 0.0) - plane.translation);
                ray.dir = objectFromView * glm::dvec3(0, 0, 1);
                ray.start = plane.nearDepth;
            } else {
                const glm::dvec3 dirCamera = glm::normalize(glm::dvec3(m, 1.0));
                ray.origin = eye;
                ray.dir = objectFromView * dirCamera;
                ray.start = plane.nearDepth / dirCamera.z;   // where u2 reaches the near plane
            }
            const auto kernels = integrator.gather(ray);
            double step = options.initialStepSigmas * integrator.smallestSigma();
            glm::dvec4 coarse = march(kernels, ray, step), fine = coarse;
            int k = 0;
            for (; k < options.maxHalvings; ++k) {
                step *= 0.5;
                fine = march(kernels, ray, step);
                const glm::dvec4 d = glm::abs(fine - coarse);
                if (std::max({d.x, d.y, d.z, d.w}) <= options.tolerance) break;
                coarse = fine;
            }
            if (k == options.maxHalvings) ++unconverged;
            halvings += uint64_t(k + 1);
            samples[size_t(j) * gw + i] = fine;
        }
        const int done = ++rowsDone;
        if (progress) {
            std::lock_guard lock(progressMutex);
            if (!progress(0.98 * done / gh)) cancelled = true;
        }
    });
    if (cancelled) throw RenderError("ground truth: cancelled");

    Image img(plane.width, plane.height);
    if (!filtered) {
        for (int y = 0; y < plane.height; ++y)
            for (int x = 0; x < plane.width; ++x)
                for (int c = 0; c < 4; ++c) img.pixel(x, y)[c] = float(samples[size_t(y) * gw + x][c]);
    }
    // 2. The V_h filter.
    if (filtered) img = filterToPixels(samples, ss, plane.width, plane.height);
    if (progress) progress(1.0);
    if (stats) {
        stats->rays = uint64_t(gw) * uint64_t(gh);
        stats->unconvergedRays = unconverged;
        stats->meanHalvings = double(halvings) / double(std::max<uint64_t>(stats->rays, 1));
        stats->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        stats->fromCache = false;
    }
    return img;
}

namespace {

struct Fnv1a {
    uint64_t h = 1469598103934665603ull;
    void bytes(const void* p, size_t n) {
        for (size_t i = 0; i < n; ++i) h = (h ^ static_cast<const unsigned char*>(p)[i]) * 1099511628211ull;
    }
    template <class T> void value(const T& v) { bytes(&v, sizeof v); }
};

} // namespace

bool hasGroundTruth(const SplatSettings& settings) { return settings.surfaceFlatten <= 1.0; }

std::string groundTruthKey(const SplatScene& scene, const ImagePlane& plane, const SplatSettings& settings,
                           const GroundTruthOptions& options) {
    Fnv1a f;
    f.value(uint32_t(3));   // integrator version: bump when its output changes (3: kernels of unit mass)
    f.value(scene.dims);
    f.value(scene.spacing);
    f.value(scene.origin);
    f.bytes(scene.classes.data(), scene.classes.size() * sizeof(uint16_t));
    f.bytes(scene.lut.data(), scene.lut.size() * sizeof(glm::vec4));
    f.value(plane.width);
    f.value(plane.height);
    f.value(plane.viewFromObject);
    f.value(plane.translation);
    f.value(plane.fPx);
    f.value(plane.centrePx);
    f.value(plane.nearDepth);
    f.value(plane.orthographic);
    f.value(settings.kernelScale);
    f.value(settings.cutoffSigmas);
    f.value(settings.density);
    f.value(options.tolerance);
    f.value(options.initialStepSigmas);
    f.value(options.maxHalvings);
    f.value(options.supersample);
    if (settings.compositing == Compositing::XRay) f.value(uint8_t(1));   // the other integral (keys before it stand)
    if (options.postClassified) f.value(uint8_t(5));                       // post-classified (keys before it stand)
    if (!scene.gradientFactors.empty()) {   // gradient opacity (keys without it stand)
        f.value(uint8_t(3));
        f.bytes(scene.gradientFactors.data(), scene.gradientFactors.size() * sizeof(float));
        f.bytes(scene.gradients.data(), scene.gradients.size() * sizeof(uint32_t));
    }
    if (!scene.tf2d.empty()) {   // the 2D TF (keys without it stand)
        f.value(uint8_t(4));
        f.bytes(scene.tf2d.data(), scene.tf2d.size() * sizeof(glm::vec4));
        f.bytes(scene.gradients.data(), scene.gradients.size() * sizeof(uint32_t));
    }
    if (settings.shading != SplatSettings::Shading::None) {   // one truth for both shading modes
        f.value(uint8_t(2));
        f.bytes(scene.gradients.data(), scene.gradients.size() * sizeof(uint32_t));
        f.value(settings.shadingParams.ambient);
        f.value(settings.shadingParams.diffuse);
        f.value(settings.shadingParams.specular);
        f.value(settings.shadingParams.shininess);
        f.value(settings.shadingParams.flatGradient);
    }
    char hex[17];
    std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(f.h));
    return hex;
}

std::filesystem::path defaultGroundTruthCacheDir() {
    if (const char* d = std::getenv("SPLATLAB_CACHE_DIR"); d && *d) return d;
    if (const char* d = std::getenv("XDG_CACHE_HOME"); d && *d) return std::filesystem::path(d) / "splatlab" / "reference";
    if (const char* d = std::getenv("HOME"); d && *d) return std::filesystem::path(d) / ".cache" / "splatlab" / "reference";
    return std::filesystem::temp_directory_path() / "splatlab-reference";
}

// An allocation that fails (the samples, the image) names the volume and the view's size.
Image renderGroundTruth(const SplatScene& scene, const ImagePlane& plane, const SplatSettings& settings,
                        const GroundTruthOptions& options, const Progress& progress, GroundTruthStats* stats) {
    try {
        return renderGroundTruthOrThrow(scene, plane, settings, options, progress, stats);
    } catch (const std::bad_alloc&) {
        throw outOfMemory(volumeSubject(scene.name), "ground truth's samples and image", 0,
                          " at " + std::to_string(plane.width) + "x" + std::to_string(plane.height));
    }
}

Image cachedGroundTruth(const SplatScene& scene, const ImagePlane& plane, const SplatSettings& settings,
                        const GroundTruthOptions& options, const std::filesystem::path& cacheDir,
                        const Progress& progress, GroundTruthStats* stats) {
    const uint64_t budget = groundTruthCacheBudgetBytes();   // a bad $SPLATLAB_CACHE_MAX_MB fails first
    const auto file = cacheDir / (groundTruthKey(scene, plane, settings, options) + ".exr");
    if (std::filesystem::exists(file)) {
        try {
            Image img = readImage(file);
            if (img.width == plane.width && img.height == plane.height) {
                if (stats) *stats = GroundTruthStats{.fromCache = true, .cacheNote = {}};
                // Used now: pruning removes the entries used longest ago first.
                std::error_code touched;
                std::filesystem::last_write_time(file, std::filesystem::file_time_type::clock::now(), touched);
                return img;
            }
        } catch (const LoadError&) {
            // An unreadable entry is computed again and replaced.
        }
    }
    // The folder is made before the rays are traced, so that a path that cannot be one fails at once.
    std::error_code ec;
    std::filesystem::create_directories(cacheDir, ec);
    if (ec || !std::filesystem::is_directory(cacheDir))
        throw LoadError(cacheDir.string(), "",
                        "cannot be the ground-truth cache folder: " + (ec ? ec.message() : std::string("not a folder")));
    Image img = renderGroundTruth(scene, plane, settings, options, progress, stats);
    try {
        writeImage(img, file);   // atomically: a reader never sees half a file
        pruneGroundTruthCache(cacheDir, budget, file);
    } catch (const LoadError& e) {
        if (stats) stats->cacheNote = e.what();
    }
    return img;
}

} // namespace renderer
