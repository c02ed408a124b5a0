// libFuzzer target: renderer::loadDat on the input written as "fuzz.dat" (see fuzz_common.h).
#include "fuzz_common.h"
#include "renderer/io/volume_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const auto path = fuzz::writeInput("fuzz.dat", data, size);
    fuzz::loadAndCheck([&] { return renderer::loadDat(path); });
    return 0;
}
