// libFuzzer target: renderer::loadTransferFunction on the input written as "fuzz_tf.json". A
// LoadError is the expected answer to a bad file; a TF that loads must bake to a finite table.
#include "fuzz_common.h"
#include "renderer/model/splat_scene.h"
#include "renderer/model/transfer_function.h"

#include <cmath>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const auto path = fuzz::writeInput("fuzz_tf.json", data, size);
    try {
        const renderer::TransferFunction tf = renderer::loadTransferFunction(path);
        for (const glm::vec4& c : renderer::bakeLut(tf, {-1000.0f, 3000.0f}))
            if (!std::isfinite(c.r) || !std::isfinite(c.a) || c.a < 0.0f || c.a > 1.0f) std::abort();
        for (const glm::vec4& c : renderer::bakeTf2d(tf, {-1000.0f, 3000.0f}, 500.0))   // its 2D widgets
            if (!std::isfinite(c.r) || !std::isfinite(c.a) || c.a < 0.0f || c.a > 1.0f) std::abort();
    } catch (const renderer::LoadError&) {
    }
    return 0;
}
