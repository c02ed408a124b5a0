// What the editor's viewport shows: the loaded volume, its classified scene and the half-resolution
// preview level. The frame steps that change them are in editor_loop.h.
#pragma once
#include "renderer/model/gradients.h"
#include "renderer/model/splat_scene.h"
#include "renderer/model/transfer_function.h"
#include "renderer/model/window.h"

#include <memory>
#include <optional>

// The volume's scene classified over `window`, with its gradients once they are computed.
renderer::SplatScene classifiedScene(const renderer::Volume& volume, const renderer::TransferFunction& tf,
                                     renderer::ValueRange window,
                                     const std::optional<renderer::GradientField>& gradients);

// The preview level, drawn first while the full frame misses the frame budget (ui::PreviewSettings): the
// volume at half resolution with its own scene, classified with the document's TF and window (the window
// of the full volume's values: the means span a narrower range). Its renderer is the render thread's.
struct Preview {
    renderer::Volume volume;
    renderer::SplatScene scene;
    std::optional<renderer::GradientField> gradients;

    explicit Preview(const renderer::Volume& full);
    void classify(const renderer::TransferFunction& tf, renderer::ValueRange window);
    void setTransferFunction(const renderer::TransferFunction& tf);
    // Once the full volume's gradients are ready; an eighth of the voxels, so computed right here.
    void addGradients();
};

// What the viewport shows. No volume (none given, or it failed to load) leaves `volume` empty.
struct Document {
    std::optional<renderer::Volume> volume;
    renderer::SplatScene scene;
    renderer::TransferFunction tf;                    // what the scene was classified with
    renderer::Histogram histogram;                    // of the whole volume, for the Window section
    renderer::ValueRange percentile;                  // p1..p99
    std::optional<renderer::GradientField> gradients; // once computed (for shading, a later issue)
    std::unique_ptr<Preview> preview;                 // volumes of PreviewSettings::kMinVoxels or more
};

// A copy of the preview level's scene for the render thread; null when the document has no preview.
std::shared_ptr<const renderer::SplatScene> previewScene(const Document& doc);
