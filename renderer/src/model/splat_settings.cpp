// Names of the settings' enums, shared by the CLI, the editor and the benchmark output.
#include "renderer/model/splat_settings.h"

#include "renderer/model/enum_names.h"
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
    return enumFromName(name, {Compositing::SplatEverySample, Compositing::XRay, Compositing::SheetBackToFront,
                               Compositing::SheetFrontToBack},
                        &compositingName, "compositing");
}

const char* shadingName(SplatSettings::Shading s) {
    switch (s) {
    case SplatSettings::Shading::None: return "none";
    case SplatSettings::Shading::PerSplat: return "per-splat";
    case SplatSettings::Shading::PerFragment: return "per-fragment";
    }
    return "?";
}

SplatSettings::Shading shadingFromName(const std::string& name) {
    using S = SplatSettings::Shading;
    return enumFromName(name, {S::None, S::PerSplat, S::PerFragment}, &shadingName, "shading");
}

const char* primitiveName(SplatSettings::Primitive p) {
    switch (p) {
    case SplatSettings::Primitive::Auto: return "auto";
    case SplatSettings::Primitive::Raster: return "raster";
    case SplatSettings::Primitive::Points: return "points";
    case SplatSettings::Primitive::Quads: return "quads";
    case SplatSettings::Primitive::Tiles: return "tiles";
    }
    return "?";
}

SplatSettings::Primitive primitiveFromName(const std::string& name) {
    using P = SplatSettings::Primitive;
    return enumFromName(name, {P::Auto, P::Raster, P::Points, P::Quads, P::Tiles}, &primitiveName, "primitive");
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
