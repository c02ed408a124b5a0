// libFuzzer target: ui::loadSession on the input written as "fuzz_session.json". A LoadError is the
// expected answer to a bad file; a session that opens must leave values the editor can use.
#include "fuzz_common.h"
#include "ui/session.h"

#include <cmath>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const auto path = fuzz::writeInput("fuzz_session.json", data, size);
    ui::EditorState state;
    try {
        ui::loadSession(path, state);
        const renderer::Camera& c = state.camera;
        if (!(c.distance > 0.0) || !std::isfinite(c.azimuthDeg) || !(std::abs(glm::length(c.up) - 1.0) < 1e-9)) std::abort();
        if (!(state.settings.density > 0.0) || state.settings.patchSize < 1 || state.tf.colours.empty() || state.tf.opacities.empty()) std::abort();
        if (state.window.mode == renderer::WindowMode::Custom && !(state.window.custom.lo < state.window.custom.hi))
            std::abort();
    } catch (const renderer::LoadError&) {
    }
    return 0;
}
