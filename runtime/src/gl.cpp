#include "gl.hpp"

#include "shader_sources.hpp"

#include <dawnforge/core/format.hpp>

#include <stdexcept>

namespace dawnforge::runtime::gl {

void deleteBuffer(GLuint id) { glDeleteBuffers(1, &id); }
void deleteTexture(GLuint id) { glDeleteTextures(1, &id); }
void deleteVertexArray(GLuint id) { glDeleteVertexArrays(1, &id); }
void deleteFramebuffer(GLuint id) { glDeleteFramebuffers(1, &id); }
void deleteProgram(GLuint id) { glDeleteProgram(id); }
void deleteQuery(GLuint id) { glDeleteQueries(1, &id); }

Buffer makeBuffer(const void* data, std::size_t bytes, GLbitfield flags) {
    GLuint id = 0;
    glCreateBuffers(1, &id);
    glNamedBufferStorage(id, GLsizeiptr(bytes == 0 ? 4 : bytes), bytes == 0 ? nullptr : data, flags);
    return Buffer(id);
}
Texture makeTexture(GLenum target) {
    GLuint id = 0;
    glCreateTextures(target, 1, &id);
    return Texture(id);
}
Texture makeTexture2D(GLenum format, int width, int height, int levels, GLenum minFilter, GLenum magFilter, GLenum wrap) {
    Texture t = makeTexture(GL_TEXTURE_2D);
    glTextureStorage2D(t.id(), levels, format, width, height);
    glTextureParameteri(t.id(), GL_TEXTURE_MAX_LEVEL, levels - 1);
    glTextureParameteri(t.id(), GL_TEXTURE_MIN_FILTER, GLint(minFilter));
    glTextureParameteri(t.id(), GL_TEXTURE_MAG_FILTER, GLint(magFilter));
    glTextureParameteri(t.id(), GL_TEXTURE_WRAP_S, GLint(wrap));
    glTextureParameteri(t.id(), GL_TEXTURE_WRAP_T, GLint(wrap));
    return t;
}

VertexArray makeVertexArray() {
    GLuint id = 0;
    glCreateVertexArrays(1, &id);
    return VertexArray(id);
}
Framebuffer makeFramebuffer() {
    GLuint id = 0;
    glCreateFramebuffers(1, &id);
    return Framebuffer(id);
}

namespace {

GLuint compile(GLenum stage, const std::string& name, const std::vector<std::string>& defines) {
    const std::string source = detail::shaderSource(name, defines);
    const GLuint shader = glCreateShader(stage);
    const char* text = source.c_str();
    glShaderSource(shader, 1, &text, nullptr);
    glCompileShader(shader);
    GLint ok = 0;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        GLint length = 0;
        glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
        std::string log(std::size_t(std::max(length, 1)), '\0');
        glGetShaderInfoLog(shader, length, nullptr, log.data());
        glDeleteShader(shader);
        throw std::logic_error(format("shader {} does not compile: {}", name, log));
    }
    return shader;
}

}  // namespace

Program makeProgram(const std::string& vertex, const std::string& fragment, const std::vector<std::string>& defines) {
    Program program(glCreateProgram());
    std::vector<GLuint> shaders{compile(GL_VERTEX_SHADER, vertex, defines)};
    if (!fragment.empty()) shaders.push_back(compile(GL_FRAGMENT_SHADER, fragment, defines));
    for (GLuint s : shaders) glAttachShader(program.id(), s);
    glLinkProgram(program.id());
    for (GLuint s : shaders) glDeleteShader(s);
    GLint ok = 0;
    glGetProgramiv(program.id(), GL_LINK_STATUS, &ok);
    if (!ok) {
        GLint length = 0;
        glGetProgramiv(program.id(), GL_INFO_LOG_LENGTH, &length);
        std::string log(std::size_t(std::max(length, 1)), '\0');
        glGetProgramInfoLog(program.id(), length, nullptr, log.data());
        throw std::logic_error(format("program {} + {} does not link: {}", vertex, fragment, log));
    }
    return program;
}

Program makeComputeProgram(const std::string& compute, const std::vector<std::string>& defines) {
    Program program(glCreateProgram());
    const GLuint shader = compile(GL_COMPUTE_SHADER, compute, defines);
    glAttachShader(program.id(), shader);
    glLinkProgram(program.id());
    glDeleteShader(shader);
    GLint ok = 0;
    glGetProgramiv(program.id(), GL_LINK_STATUS, &ok);
    if (!ok) throw std::logic_error(format("program {} does not link", compute));
    return program;
}

void check(const char* where) {
    const GLenum e = glGetError();
    if (e != GL_NO_ERROR) throw std::logic_error(format("OpenGL error {} in {}", e, where));
}

}  // namespace dawnforge::runtime::gl
