// The editor's document: classifying the volume's scene and keeping the preview's scene in step with
// the full one's transfer function, window and gradients.
#include "editor_document.h"

#include "renderer/out_of_memory.h"

renderer::SplatScene classifiedScene(const renderer::Volume& volume, const renderer::TransferFunction& tf,
                                     renderer::ValueRange window,
                                     const std::optional<renderer::GradientField>& gradients) {
    renderer::SplatScene scene = renderer::buildSplatScene(volume, tf, window);
    if (gradients)
        renderer::namingAllocation(renderer::volumeSubject(volume.name), "packed gradients of its scene",
                                   volume.voxelCount() * 4, "",
                                   [&] { renderer::addGradients(scene, *gradients); });
    return scene;
}

std::shared_ptr<const renderer::SplatScene> copyForRender(const renderer::SplatScene& scene) {
    uint64_t bytes = scene.classes.size() * 2 + scene.gradients.size() * 4 + scene.classVoxels.size() * 4 +
                     scene.classGradientVoxels.size() * 4;
    for (const renderer::AxisLists& lists : scene.lists)
        bytes += lists.runs.size() * sizeof(renderer::SliceRun) + lists.sliceRuns.size() * 4;   // entries are shared
    return renderer::namingAllocation(renderer::volumeSubject(scene.name),
                                      "copy of its splat lists for the renderer", bytes, "",
                                      [&] { return std::make_shared<const renderer::SplatScene>(scene); });
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

std::vector<renderer::TfTables> levelTables(const Document& doc) {
    std::vector<renderer::TfTables> luts;
    if (doc.preview)
        for (const Level& level : doc.preview->levels)
            luts.push_back(renderer::tfTables(level.scene));
    return luts;
}
