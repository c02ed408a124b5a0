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

Preview::Preview(const renderer::Volume& full) : volume(renderer::halfResolution(full)) {}

void Preview::classify(const renderer::TransferFunction& tf, renderer::ValueRange window) {
    scene = classifiedScene(volume, tf, window, gradients);
}

void Preview::setTransferFunction(const renderer::TransferFunction& tf) {
    renderer::setTransferFunction(scene, tf);
}

void Preview::addGradients() {
    gradients = renderer::computeGradients(volume);
    if (!gradients) return;
    renderer::addGradients(scene, *gradients);
}

std::shared_ptr<const renderer::SplatScene> previewScene(const Document& doc) {
    return doc.preview ? std::make_shared<const renderer::SplatScene>(doc.preview->scene) : nullptr;
}
