// Move-only owners of OpenGL object names (STYLE.md rule 11; the idea of Magnum's GL/Buffer.h):
// an object is deleted exactly once, when its owner goes, and cannot be copied by accident. Create
// them with a context current and destroy them before it (members after the context).
#pragma once

#include <glad/gl.h>

#include <utility>

namespace sph::render::gl {

template <class Traits>
class GlHandle {
 public:
  GlHandle() = default;
  // Creates a new object (DSA glCreate*, so it exists before its first bind).
  template <class... Args>
  static GlHandle create(Args... args) {
    GlHandle h;
    h.id_ = Traits::create(args...);
    return h;
  }
  ~GlHandle() { reset(); }
  GlHandle(GlHandle&& other) noexcept : id_(std::exchange(other.id_, 0)) {}
  GlHandle& operator=(GlHandle&& other) noexcept {
    if (this != &other) {
      reset();
      id_ = std::exchange(other.id_, 0);
    }
    return *this;
  }
  GlHandle(const GlHandle&) = delete;
  GlHandle& operator=(const GlHandle&) = delete;

  GLuint id() const { return id_; }
  explicit operator bool() const { return id_ != 0; }
  void reset() {
    if (id_ != 0) Traits::destroy(id_);
    id_ = 0;
  }

 private:
  GLuint id_ = 0;
};

namespace detail {
struct BufferTraits {
  static GLuint create() {
    GLuint id = 0;
    glCreateBuffers(1, &id);
    return id;
  }
  static void destroy(GLuint id) { glDeleteBuffers(1, &id); }
};
struct TextureTraits {
  static GLuint create(GLenum target) {
    GLuint id = 0;
    glCreateTextures(target, 1, &id);
    return id;
  }
  static void destroy(GLuint id) { glDeleteTextures(1, &id); }
};
struct RenderbufferTraits {
  static GLuint create() {
    GLuint id = 0;
    glCreateRenderbuffers(1, &id);
    return id;
  }
  static void destroy(GLuint id) { glDeleteRenderbuffers(1, &id); }
};
struct FramebufferTraits {
  static GLuint create() {
    GLuint id = 0;
    glCreateFramebuffers(1, &id);
    return id;
  }
  static void destroy(GLuint id) { glDeleteFramebuffers(1, &id); }
};
struct VertexArrayTraits {
  static GLuint create() {
    GLuint id = 0;
    glCreateVertexArrays(1, &id);
    return id;
  }
  static void destroy(GLuint id) { glDeleteVertexArrays(1, &id); }
};
struct TransformFeedbackTraits {
  static GLuint create() {
    GLuint id = 0;
    glCreateTransformFeedbacks(1, &id);
    return id;
  }
  static void destroy(GLuint id) { glDeleteTransformFeedbacks(1, &id); }
};
struct QueryTraits {
  static GLuint create(GLenum target) {
    GLuint id = 0;
    glCreateQueries(target, 1, &id);
    return id;
  }
  static void destroy(GLuint id) { glDeleteQueries(1, &id); }
};
struct ShaderTraits {
  static GLuint create(GLenum type) { return glCreateShader(type); }
  static void destroy(GLuint id) { glDeleteShader(id); }
};
struct ProgramTraits {
  static GLuint create() { return glCreateProgram(); }
  static void destroy(GLuint id) { glDeleteProgram(id); }
};
}  // namespace detail

using Buffer = GlHandle<detail::BufferTraits>;
using Texture = GlHandle<detail::TextureTraits>;
using Renderbuffer = GlHandle<detail::RenderbufferTraits>;
using Framebuffer = GlHandle<detail::FramebufferTraits>;
using VertexArray = GlHandle<detail::VertexArrayTraits>;
using TransformFeedback = GlHandle<detail::TransformFeedbackTraits>;
using Query = GlHandle<detail::QueryTraits>;
using Shader = GlHandle<detail::ShaderTraits>;
using Program = GlHandle<detail::ProgramTraits>;

}  // namespace sph::render::gl
