// Names of the settings' enums, shared by the CLI, the editor and the benchmark output.
#include "renderer/splat_settings.h"

#include "renderer/errors.h"

namespace renderer {

const char* compositingName(Compositing c) {
    switch (c) {
    case Compositing::SplatEverySample: return "splat-every-sample";
    case Compositing::XRay: return "xray";
    case Compositing::SheetBackToFront: return "sheet-back-to-front";
    case Compositing::SheetFrontToBack: return "sheet-front-to-back";
    }
    return "?";
}

Compositing compositingFromName(const std::string& name) {
    for (auto c : {Compositing::SplatEverySample, Compositing::XRay, Compositing::SheetBackToFront,
                   Compositing::SheetFrontToBack})
        if (name == compositingName(c)) return c;
    throw RenderError("unknown compositing '" + name +
                      "' (known: splat-every-sample, xray, sheet-back-to-front, sheet-front-to-back)");
}

bool frontToBack(const SplatSettings& s) {
    return s.compositing == Compositing::SheetFrontToBack ||
           (s.compositing == Compositing::SplatEverySample && s.opaqueAlpha < 1.0);
}

bool needsGradients(const SplatSettings& s) {
    return s.shading != SplatSettings::Shading::None || s.surfaceFlatten > 1.0;
}

void requireGradients(const SplatSettings& s, bool sceneHasGradients, const std::string& sceneName) {
    if (!(s.surfaceFlatten >= 1.0))
        throw RenderError("surface flatten must be >= 1 (1: off), got " + std::to_string(s.surfaceFlatten));
    if (needsGradients(s) && !sceneHasGradients)
        throw RenderError("scene '" + sceneName + "': shading and surface splats need gradients (addGradients)");
}

} // namespace renderer
