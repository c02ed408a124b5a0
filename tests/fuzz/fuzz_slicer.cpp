// libFuzzer target: renderer::loadSlicerPresets on the input written as "fuzz_slicer.xml". A LoadError is
// the expected answer to a bad file; every preset that loads must bake to a finite table.
#include "fuzz_common.h"
#include "renderer/errors.h"
#include "renderer/model/slicer_preset.h"

#include <cmath>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const auto path = fuzz::writeInput("fuzz_slicer.xml", data, size);
    try {
        for (const renderer::SlicerPreset& preset : renderer::loadSlicerPresets(path))
            for (const glm::vec4& c : renderer::bakeLut(preset.tf, {-1000.0f, 3000.0f}))
                if (!std::isfinite(c.r) || !std::isfinite(c.a) || c.a < 0.0f || c.a > 1.0f) std::abort();
    } catch (const renderer::LoadError&) {
    }
    return 0;
}
