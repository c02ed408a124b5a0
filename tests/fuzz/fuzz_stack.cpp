// libFuzzer target: renderer::loadImageStack on the input written as "fuzz.tif" (see fuzz_common.h).
#include "fuzz_common.h"
#include "renderer/io/volume_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const auto path = fuzz::writeInput("fuzz.tif", data, size);
    fuzz::loadAndCheck([&] { return renderer::loadImageStack(path); });
    return 0;
}
