// Speed against error for one view (speed_error.h).
#include "renderer/oracle/speed_error.h"

namespace renderer {

std::vector<SplatSettings> speedErrorSettings(const SplatSettings& base) {
    if (!hasGroundTruth(base)) return {};
    std::vector<SplatSettings> all;
    for (Compositing c : {Compositing::SplatEverySample, Compositing::SheetBackToFront,
                          Compositing::SheetFrontToBack, Compositing::XRay})
        for (FilterMode f :
             {FilterMode::Reconstruction, FilterMode::LowPass, FilterMode::Ewa, FilterMode::Adaptive}) {
            SplatSettings s = base;
            s.filter = f;
            s.compositing = c;
            if (c == Compositing::SplatEverySample && s.primitive == SplatSettings::Primitive::Tiles)
                s.primitive = SplatSettings::Primitive::Auto;
            all.push_back(s);
        }
    return all;
}

CropTruths cropTruths(const SplatScene& scene, const ImagePlane& crop, const SplatSettings& base,
                      const GroundTruthOptions& options, const std::filesystem::path& cacheDir,
                      const ProgressCallback& progress, bool postClassified) {
    // 1. The attenuating modes' truth (compositing only decides X-ray or not), 2. X-ray's, 3. where asked,
    // the post-classified one; each an equal share of the progress.
    const double parts = postClassified ? 3.0 : 2.0;
    const auto share = [&](int part) -> ProgressCallback {
        if (!progress) return {};
        return [&progress, part, parts](double f) { return progress((double(part) + f) / parts); };
    };
    SplatSettings s = base;
    s.compositing = Compositing::SplatEverySample;
    CropTruths t;
    t.attenuating = cachedGroundTruth(scene, crop, s, options, cacheDir, share(0));
    SplatSettings xray = base;
    xray.compositing = Compositing::XRay;
    t.xray = cachedGroundTruth(scene, crop, xray, options, cacheDir, share(1));
    if (postClassified) {
        GroundTruthOptions post = options;
        post.postClassified = true;
        t.postClassified = cachedGroundTruth(scene, crop, s, post, cacheDir, share(2));
    }
    return t;
}

std::vector<FilterMeasurement> measureSpeedAgainstError(SplatRenderer& gl, const ImagePlane& view,
                                                        const ImagePlane& crop, const CropTruths& truths,
                                                        const SplatSettings& base, int repeats) {
    std::vector<FilterMeasurement> points;
    for (const SplatSettings& s : speedErrorSettings(base))
        points.push_back(measureSetting(gl, view, crop, truths.of(s), s, repeats));
    return points;
}

int groundTruthKind(const FilterMeasurement& m) {
    return m.compositing == Compositing::XRay ? 1 : m.slabThickness > 0.0 && m.postClassified ? 2 : 0;
}

bool sameGroundTruth(const FilterMeasurement& a, const FilterMeasurement& b) {
    return groundTruthKind(a) == groundTruthKind(b);
}

std::vector<bool> paretoFront(std::span<const FilterMeasurement> points) {
    std::vector<bool> front(points.size(), true);
    for (size_t i = 0; i < points.size(); ++i)
        for (const FilterMeasurement& other : points) {
            const FilterMeasurement& p = points[i];
            if (!sameGroundTruth(p, other)) continue;
            const bool noWorse = other.frameMs <= p.frameMs && other.psnrDb >= p.psnrDb;
            const bool better = other.frameMs < p.frameMs || other.psnrDb > p.psnrDb;
            if (noWorse && better) {
                front[i] = false;
                break;
            }
        }
    return front;
}

} // namespace renderer
