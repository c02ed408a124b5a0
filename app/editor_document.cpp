// The editor's document: classifying the volume's scene and keeping the preview's scene and renderer
// in step with the full one's transfer function, window and gradients.
#include "editor_document.h"

renderer::SplatScene classifiedScene(const renderer::Volume& volume, const renderer::TransferFunction& tf,
                                     renderer::ValueRange window,
                                     const std::optional<renderer::GradientField>& gradients) {
    renderer::SplatScene scene = renderer::buildSplatScene(volume, tf, window);
    if (gradients) renderer::addGradients(scene, *gradients);
    return scene;
}

Preview::Preview(const renderer::Volume& full) : volume(renderer::halfResolution(full)) {}

void Preview::classify(const renderer::TransferFunction& tf, renderer::ValueRange window) {
    renderer::SplatScene next = classifiedScene(volume, tf, window, gradients);
    splats.setScene(next);
    scene = std::move(next);
}

void Preview::setTransferFunction(const renderer::TransferFunction& tf) {
    renderer::setTransferFunction(scene, tf);
    splats.setLut(scene.lut);
}

void Preview::addGradients() {
    gradients = renderer::computeGradients(volume);
    if (!gradients) return;
    renderer::addGradients(scene, *gradients);
    splats.setGradients(scene);
}
