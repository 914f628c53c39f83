#pragma once
// Small RAII owners of GL objects and the program builder. Private to the runtime.
#include <epoxy/gl.h>

#include <glm/glm.hpp>

#include <string>
#include <utility>
#include <vector>

namespace dawnforge::runtime::gl {

// One GL name with its deleter; move-only.
template <void (*Delete)(GLuint)>
class Handle {
public:
    Handle() = default;
    explicit Handle(GLuint id) : id_(id) {}
    Handle(Handle&& o) noexcept : id_(std::exchange(o.id_, 0)) {}
    Handle& operator=(Handle&& o) noexcept {
        if (this != &o) {
            reset();
            id_ = std::exchange(o.id_, 0);
        }
        return *this;
    }
    Handle(const Handle&) = delete;
    Handle& operator=(const Handle&) = delete;
    ~Handle() { reset(); }
    GLuint id() const { return id_; }
    explicit operator bool() const { return id_ != 0; }
    void reset() {
        if (id_) Delete(id_);
        id_ = 0;
    }

private:
    GLuint id_ = 0;
};

void deleteBuffer(GLuint id);
void deleteTexture(GLuint id);
void deleteVertexArray(GLuint id);
void deleteFramebuffer(GLuint id);
void deleteProgram(GLuint id);
void deleteQuery(GLuint id);
using Buffer = Handle<deleteBuffer>;
using Texture = Handle<deleteTexture>;
using VertexArray = Handle<deleteVertexArray>;
using Framebuffer = Handle<deleteFramebuffer>;
using Program = Handle<deleteProgram>;
using Query = Handle<deleteQuery>;

Buffer makeBuffer(const void* data, std::size_t bytes, GLbitfield flags = 0);
template <class T>
Buffer makeBuffer(const std::vector<T>& v, GLbitfield flags = 0) {
    return makeBuffer(v.data(), v.size() * sizeof(T), flags);
}
Texture makeTexture(GLenum target);
// A 2D texture with `levels` levels of `format`, filtered and wrapped as given.
Texture makeTexture2D(GLenum format, int width, int height, int levels, GLenum minFilter, GLenum magFilter, GLenum wrap);
VertexArray makeVertexArray();
Framebuffer makeFramebuffer();

// Compiles and links the embedded vertex (+ fragment, if named) shaders; throws
// std::logic_error with the compiler log on failure (a bug in our shaders).
Program makeProgram(const std::string& vertex, const std::string& fragment, const std::vector<std::string>& defines = {});

Program makeComputeProgram(const std::string& compute, const std::vector<std::string>& defines = {});

// Throws std::logic_error if glGetError reports an error, naming `where`.
void check(const char* where);

}  // namespace dawnforge::runtime::gl
