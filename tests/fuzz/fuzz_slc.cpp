// libFuzzer target: renderer::loadSlc on the input written as "fuzz.slc" (see fuzz_common.h).
#include "fuzz_common.h"
#include "renderer/io/volume_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const auto path = fuzz::writeInput("fuzz.slc", data, size);
    fuzz::loadAndCheck([&] { return renderer::loadSlc(path); });
    return 0;
}
