// libFuzzer target: the raw path. The input's first line is a file name, parsed by
// rawOptionsFromFileName(); the rest is the file's content, loaded with loadRaw() when the name parses.
#include "fuzz_common.h"
#include "renderer/io/volume_io.h"

#include <algorithm>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const uint8_t* newline = std::find(data, data + size, uint8_t('\n'));
    std::string name(reinterpret_cast<const char*>(data), size_t(newline - data));
    const auto options = renderer::rawOptionsFromFileName(name);
    if (!options) return 0;
    // Keep the name a plain file name inside the scratch folder.
    for (char& c : name)
        if (c == '/' || c == '\0') c = '_';
    if (name.size() > 200 || name == "." || name == "..") return 0;
    const size_t rest = newline == data + size ? 0 : size_t(data + size - newline - 1);
    const auto path = fuzz::writeInput(name, newline + (rest ? 1 : 0), rest);
    fuzz::loadAndCheck([&] { return renderer::loadRaw(path, *options); });
    std::filesystem::remove(path);
    return 0;
}
