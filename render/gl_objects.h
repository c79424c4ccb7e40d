// SPDX-License-Identifier: GPL-3.0-or-later
// Move-only owners of GL object names (textures, samplers, framebuffers, buffers, vertex arrays, queries), so
// every pass releases what it created and nothing leaks on an exception. All need a current context; creation
// uses GL 4.5 direct state access (glCreate*).
#pragma once

#include <epoxy/gl.h>

#include <utility>

namespace dtf::render {

template <void (*Delete)(GLuint)> class GlHandle {
public:
  GlHandle() = default;
  explicit GlHandle(GLuint id) : id_(id) {}
  ~GlHandle() { reset(); }
  GlHandle(GlHandle&& o) noexcept : id_(std::exchange(o.id_, 0)) {}
  GlHandle& operator=(GlHandle&& o) noexcept {
    if (this != &o) {
      reset();
      id_ = std::exchange(o.id_, 0);
    }
    return *this;
  }
  GlHandle(const GlHandle&) = delete;
  GlHandle& operator=(const GlHandle&) = delete;

  GLuint id() const { return id_; }
  explicit operator bool() const { return id_ != 0; }
  void reset() {
    if (id_) Delete(id_);
    id_ = 0;
  }

private:
  GLuint id_ = 0;
};

namespace detail {
inline void deleteTexture(GLuint id) { glDeleteTextures(1, &id); }
inline void deleteFramebuffer(GLuint id) { glDeleteFramebuffers(1, &id); }
inline void deleteBuffer(GLuint id) { glDeleteBuffers(1, &id); }
inline void deleteVertexArray(GLuint id) { glDeleteVertexArrays(1, &id); }
inline void deleteQuery(GLuint id) { glDeleteQueries(1, &id); }
inline void deleteProgram(GLuint id) { glDeleteProgram(id); }
inline void deleteSampler(GLuint id) { glDeleteSamplers(1, &id); }
} // namespace detail

using Framebuffer = GlHandle<detail::deleteFramebuffer>;
using Buffer = GlHandle<detail::deleteBuffer>;
using VertexArray = GlHandle<detail::deleteVertexArray>;
using Query = GlHandle<detail::deleteQuery>;
using ProgramHandle = GlHandle<detail::deleteProgram>;
using Sampler = GlHandle<detail::deleteSampler>;

// A texture with its size and internal format.
class Texture {
public:
  Texture() = default;
  // Immutable 2D storage (glTextureStorage2D) with linear filtering and clamp-to-edge.
  static Texture create2D(GLenum internalFormat, int width, int height, int levels = 1);
  // Immutable 3D storage with linear filtering and clamp-to-border (border 0: outside means "no data").
  static Texture create3D(GLenum internalFormat, int width, int height, int depth);

  GLuint id() const { return handle_.id(); }
  int width() const { return width_; }
  int height() const { return height_; }
  int depth() const { return depth_; }
  GLenum format() const { return format_; }
  explicit operator bool() const { return bool(handle_); }
  void setFilter(GLenum minFilter, GLenum magFilter);
  void setWrap(GLenum wrap);

private:
  GlHandle<detail::deleteTexture> handle_;
  int width_ = 0, height_ = 0, depth_ = 0;
  GLenum format_ = 0;
};

inline Framebuffer createFramebuffer() {
  GLuint id = 0;
  glCreateFramebuffers(1, &id);
  return Framebuffer(id);
}
inline Buffer createBuffer() {
  GLuint id = 0;
  glCreateBuffers(1, &id);
  return Buffer(id);
}
inline VertexArray createVertexArray() {
  GLuint id = 0;
  glCreateVertexArrays(1, &id);
  return VertexArray(id);
}
inline Query createQuery(GLenum target) {
  GLuint id = 0;
  glCreateQueries(target, 1, &id);
  return Query(id);
}
// A sampler that reads single texels whatever the texture's own parameters: nearest, clamp to edge, no depth
// comparison. Bound to a unit, it lets a shader read a texel as a sample at its centre (common/texel.glsl).
Sampler createTexelSampler();

// Attaches colour textures 0..n-1 (and an optional depth texture), sets the draw buffers and throws
// GlError when the framebuffer is incomplete.
void attachTargets(const Framebuffer& fbo, std::initializer_list<const Texture*> colour, const Texture* depth);

// Dispatches the current compute program over a width x height target in 8x8 work groups (the size the
// per-pixel compute shaders declare), then a barrier after which whatever reads its writes next sees them:
// texture fetches, draws into the targets, copies and readbacks, image loads, buffer reads.
void dispatchPerPixel(int width, int height);

} // namespace dtf::render
