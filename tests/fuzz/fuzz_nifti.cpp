// libFuzzer target: renderer::loadNifti on the input written as "fuzz.nii" (see fuzz_common.h).
#include "fuzz_common.h"
#include "renderer/io/volume_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const auto path = fuzz::writeInput("fuzz.nii", data, size);
    fuzz::loadAndCheck([&] { return renderer::loadNifti(path); });
    return 0;
}
