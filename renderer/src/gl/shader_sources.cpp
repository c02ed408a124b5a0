// Looks up the embedded shader files and checks a program's #defines against the validated sets; the
// data itself is generated (embedded_shaders.cpp in the build folder).
#include "gl/shader_sources.h"

#include <algorithm>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace renderer {

const char* shaderSource(std::string_view file) {
    for (size_t i = 0; i < embedded::kShaderFileCount; ++i)
        if (file == embedded::kShaderFiles[i].name) return embedded::kShaderFiles[i].text;
    throw std::logic_error("no shader file renderer/shaders/" + std::string(file) + " was embedded");
}

namespace {

// The "#define" lines of `header`, sorted: the form programs.cmake's sets are embedded in.
std::string sortedDefines(const std::string& header) {
    std::vector<std::string> lines;
    std::istringstream in(header);
    for (std::string line; std::getline(in, line);)
        if (line.rfind("#define ", 0) == 0) lines.push_back(line);
    std::sort(lines.begin(), lines.end());
    std::string out;
    for (const std::string& l : lines) out += l + "\n";
    return out;
}

} // namespace

std::string programSource(std::string_view program, const std::string& defines, std::string_view file) {
    const std::string wanted = sortedDefines(defines);
    bool validated = false;
    for (size_t i = 0; i < embedded::kValidatedDefineCount && !validated; ++i)
        validated = program == embedded::kValidatedDefines[i].program &&
                    wanted == embedded::kValidatedDefines[i].defines;
    if (!validated)
        throw std::logic_error("shader program '" + std::string(program) +
                               "' with defines not validated at build time (add the set to "
                               "renderer/shaders/programs.cmake):\n" + defines);
    return "#version 450 core\n" + defines + shaderSource(file);
}

} // namespace renderer
