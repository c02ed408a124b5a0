// libFuzzer target: renderer::loadMetaImage on the input written as "fuzz.mha" (see fuzz_common.h).
#include "fuzz_common.h"
#include "renderer/io/volume_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const auto path = fuzz::writeInput("fuzz.mha", data, size);
    fuzz::loadAndCheck([&] { return renderer::loadMetaImage(path); });
    return 0;
}
