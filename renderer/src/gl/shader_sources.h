// The GLSL of renderer/shaders/, embedded at build time (renderer/cmake/embed_shaders.cmake), and the
// define sets the build validated each program with (renderer/shaders/programs.cmake).
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace renderer {

// The text of shader file `file` (e.g. "splat.vert") with its #include lines resolved; no #version (the
// renderer prepends it and the program's #defines). Throws std::logic_error for a file that is not there.
const char* shaderSource(std::string_view file);

// What the driver compiles: "#version 450 core", then `defines` (#define lines), then `file`'s text.
// Throws std::logic_error when the build did not validate `program` with exactly these defines, so a
// variant the renderer starts to build cannot skip the build's check: add its set to programs.cmake.
std::string programSource(std::string_view program, const std::string& defines, std::string_view file);

namespace embedded {   // written by embed_shaders.cmake
struct ShaderFile {
    const char* name;
    const char* text;
};
struct ProgramDefines {
    const char* program;
    const char* defines;   // "#define NAME[ VALUE]\n" lines sorted by name
};
extern const ShaderFile kShaderFiles[];
extern const size_t kShaderFileCount;
extern const ProgramDefines kValidatedDefines[];
extern const size_t kValidatedDefineCount;
} // namespace embedded

} // namespace renderer
