// Program building with the driver's log attached to the error.
#include "gl_util.h"

#include "renderer/errors.h"

#include <initializer_list>
#include <string>
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

static GLuint link(const std::string& base, std::initializer_list<GLuint> shaders) {
    GLuint program = glCreateProgram();
    for (GLuint s : shaders) glAttachShader(program, s);
    glLinkProgram(program);
    for (GLuint s : shaders) glDeleteShader(s);
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
    return link(base, {vs, fs});
}

GLuint buildComputeProgram(const char* name, const char* source) {
    const std::string base(name);
    return link(base, {compile(GL_COMPUTE_SHADER, source, base + ".comp")});
}

} // namespace renderer::gl
