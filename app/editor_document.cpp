// The editor's document: classifying the volume's scene and keeping the preview's scene in step with
// the full one's transfer function, window and gradients.
#include "editor_document.h"

renderer::SplatScene classifiedScene(const renderer::Volume& volume, const renderer::TransferFunction& tf,
                                     renderer::ValueRange window,
                                     const std::optional<renderer::GradientField>& gradients) {
    renderer::SplatScene scene = renderer::buildSplatScene(volume, tf, window);
    if (gradients) renderer::addGradients(scene, *gradients);
    return scene;
}

Preview::Preview(const renderer::Volume& full) {
    levels.reserve(kMaxLevels);
    const renderer::Volume* finer = &full;
    for (int k = 0; k < kMaxLevels; ++k) {
        // One fine voxel's value each, not their mean: a sharp TF's thin features survive (Downsample).
        renderer::Volume coarse = renderer::halfResolution(*finer, renderer::Downsample::PickOne);
        if (coarse.voxelCount() < kMinLevelVoxels) break;
        levels.push_back({std::move(coarse), {}, {}});
        finer = &levels.back().volume;
    }
}

void Preview::classify(const renderer::TransferFunction& tf, renderer::ValueRange window) {
    for (Level& level : levels)
        level.scene = classifiedScene(level.volume, tf, window, level.gradients);
}

void Preview::setTransferFunction(const renderer::TransferFunction& tf) {
    for (Level& level : levels)
        renderer::setTransferFunction(level.scene, tf);
}

std::vector<renderer::Lut> levelLuts(const Document& doc) {
    std::vector<renderer::Lut> luts;
    if (doc.preview)
        for (const Level& level : doc.preview->levels)
            luts.push_back(level.scene.lut);
    return luts;
}
