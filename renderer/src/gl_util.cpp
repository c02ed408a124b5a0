// Program building with the driver's log attached to the error.
#include "gl_util.h"

#include "renderer/errors.h"

#include <vector>

namespace renderer::gl {

static GLuint compile(GLenum type, const char* source, const std::string& label) {
    GLuint shader = glCreateShader(type);
    glShaderSource(shader, 1, &source, nullptr);
    glCompileShader(shader);
    GLint ok = 0;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        GLint len = 0;
        glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &len);
        std::vector<char> log(size_t(len) + 1, '\0');
        glGetShaderInfoLog(shader, len, nullptr, log.data());
        glDeleteShader(shader);
        throw GlError(label, std::string("compile failed:\n") + log.data());
    }
    return shader;
}

GLuint buildProgram(const char* name, const char* vertexSource, const char* fragmentSource) {
    const std::string base(name);
    GLuint vs = compile(GL_VERTEX_SHADER, vertexSource, base + ".vert");
    GLuint fs = 0;
    try {
        fs = compile(GL_FRAGMENT_SHADER, fragmentSource, base + ".frag");
    } catch (...) {
        glDeleteShader(vs);
        throw;
    }
    GLuint program = glCreateProgram();
    glAttachShader(program, vs);
    glAttachShader(program, fs);
    glLinkProgram(program);
    glDeleteShader(vs);
    glDeleteShader(fs);
    GLint ok = 0;
    glGetProgramiv(program, GL_LINK_STATUS, &ok);
    if (!ok) {
        GLint len = 0;
        glGetProgramiv(program, GL_INFO_LOG_LENGTH, &len);
        std::vector<char> log(size_t(len) + 1, '\0');
        glGetProgramInfoLog(program, len, nullptr, log.data());
        glDeleteProgram(program);
        throw GlError(base + " link", log.data());
    }
    return program;
}

} // namespace renderer::gl
