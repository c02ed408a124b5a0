// Small GL helpers private to the renderer: program building with readable logs.
#pragma once
#include <epoxy/gl.h>


namespace renderer::gl {

// Compiles and links; throws GlError("<name>.vert"/"<name>.frag"/"<name> link", driver log).
GLuint buildProgram(const char* name, const char* vertexSource, const char* fragmentSource);
// Throws GlError("<name>.comp"/"<name> link", driver log).
GLuint buildComputeProgram(const char* name, const char* source);

} // namespace renderer::gl
