// What the editor's viewport shows: the loaded volume, its classified scene and the half-resolution
// preview level. The frame steps that change them are in editor_loop.h.
#pragma once
#include "renderer/model/gradients.h"
#include "renderer/model/splat_scene.h"
#include "renderer/model/transfer_function.h"
#include "renderer/model/window.h"

#include <memory>
#include <optional>
#include <vector>

// The volume's scene classified over `window`, with its gradients once they are computed.
renderer::SplatScene classifiedScene(const renderer::Volume& volume, const renderer::TransferFunction& tf,
                                     renderer::ValueRange window,
                                     const std::optional<renderer::GradientField>& gradients);

// A coarser level of detail: the volume at 1/2, 1/4 or 1/8 resolution per axis (each 2x2x2 block of the
// level before averaged) with its own scene, classified with the document's TF and window (the window of
// the full volume's values: the means span a narrower range). Its renderer is the render thread's.
struct Level {
    renderer::Volume volume;
    renderer::SplatScene scene;
    std::optional<renderer::GradientField> gradients;
};

// The levels drawn first while the full frame misses the frame budget (ui::PreviewSettings): 1/2, 1/4 and
// 1/8 per axis, as many as keep kMinLevelVoxels voxels. levels[0], the finest, is "the preview".
struct Preview {
    static constexpr int kMaxLevels = 3;
    static constexpr size_t kMinLevelVoxels = 4096;
    std::vector<Level> levels;

    explicit Preview(const renderer::Volume& full);
    void classify(const renderer::TransferFunction& tf, renderer::ValueRange window);
    void setTransferFunction(const renderer::TransferFunction& tf);
};

// What the viewport shows. No volume (none given, or it failed to load) leaves `volume` empty.
struct Document {
    std::optional<renderer::Volume> volume;
    renderer::SplatScene scene;
    renderer::TransferFunction tf;                    // what the scene was classified with
    renderer::Histogram histogram;                    // of the whole volume, for the Window section
    renderer::ValueRange percentile;                  // p1..p99
    std::optional<renderer::GradientField> gradients; // once computed (for shading, a later issue)
    std::vector<uint64_t> gradientHistogram;          // voxels per magnitude byte, once computed
    std::vector<uint32_t> histogram2d;                // voxels per 2D TF cell over scene.window, once computed
    std::unique_ptr<Preview> preview;                 // levels, for volumes of PreviewSettings::kMinVoxels or more
};

// A copy of `scene` for the render thread. Out of memory, a RenderError naming the volume and the
// copy's size (its classes, lists and gradients).
std::shared_ptr<const renderer::SplatScene> copyForRender(const renderer::SplatScene& scene);

// The levels' LUTs and gradient factors, finest first.
std::vector<renderer::TfTables> levelTables(const Document& doc);
