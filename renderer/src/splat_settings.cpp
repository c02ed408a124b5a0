// Names of the settings' enums, shared by the CLI, the editor and the benchmark output.
#include "renderer/splat_settings.h"

#include "renderer/errors.h"

namespace renderer {

const char* compositingName(Compositing c) {
    switch (c) {
    case Compositing::SplatEverySample: return "splat-every-sample";
    case Compositing::XRay: return "xray";
    }
    return "?";
}

Compositing compositingFromName(const std::string& name) {
    for (auto c : {Compositing::SplatEverySample, Compositing::XRay})
        if (name == compositingName(c)) return c;
    throw RenderError("unknown compositing '" + name + "' (known: splat-every-sample, xray)");
}

} // namespace renderer
