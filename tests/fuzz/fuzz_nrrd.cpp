// libFuzzer target: renderer::loadNrrd on the input written as "fuzz.nrrd" (see fuzz_common.h).
#include "fuzz_common.h"
#include "renderer/io/volume_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const auto path = fuzz::writeInput("fuzz.nrrd", data, size);
    fuzz::loadAndCheck([&] { return renderer::loadNrrd(path); });
    return 0;
}
