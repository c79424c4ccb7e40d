// SPDX-License-Identifier: GPL-3.0-or-later
#include "render/gl_objects.h"

#include "io/model/error.h"

#include <string>
#include <vector>

namespace dtf::render {

Texture Texture::create2D(GLenum internalFormat, int width, int height, int levels) {
  Texture t;
  GLuint id = 0;
  glCreateTextures(GL_TEXTURE_2D, 1, &id);
  t.handle_ = GlHandle<detail::deleteTexture>(id);
  glTextureStorage2D(id, levels, internalFormat, width, height);
  t.width_ = width;
  t.height_ = height;
  t.depth_ = 1;
  t.format_ = internalFormat;
  t.setFilter(levels > 1 ? GL_LINEAR_MIPMAP_LINEAR : GL_LINEAR, GL_LINEAR);
  t.setWrap(GL_CLAMP_TO_EDGE);
  return t;
}

Texture Texture::create3D(GLenum internalFormat, int width, int height, int depth) {
  Texture t;
  GLuint id = 0;
  glCreateTextures(GL_TEXTURE_3D, 1, &id);
  t.handle_ = GlHandle<detail::deleteTexture>(id);
  glTextureStorage3D(id, 1, internalFormat, width, height, depth);
  t.width_ = width;
  t.height_ = height;
  t.depth_ = depth;
  t.format_ = internalFormat;
  t.setFilter(GL_LINEAR, GL_LINEAR);
  t.setWrap(GL_CLAMP_TO_BORDER);
  const float zero[4] = {0, 0, 0, 0};
  glTextureParameterfv(id, GL_TEXTURE_BORDER_COLOR, zero);
  return t;
}

void Texture::setFilter(GLenum minFilter, GLenum magFilter) {
  glTextureParameteri(id(), GL_TEXTURE_MIN_FILTER, static_cast<GLint>(minFilter));
  glTextureParameteri(id(), GL_TEXTURE_MAG_FILTER, static_cast<GLint>(magFilter));
}

void Texture::setWrap(GLenum wrap) {
  glTextureParameteri(id(), GL_TEXTURE_WRAP_S, static_cast<GLint>(wrap));
  glTextureParameteri(id(), GL_TEXTURE_WRAP_T, static_cast<GLint>(wrap));
  glTextureParameteri(id(), GL_TEXTURE_WRAP_R, static_cast<GLint>(wrap));
}

Sampler createTexelSampler() {
  GLuint id = 0;
  glCreateSamplers(1, &id);
  Sampler sampler(id);
  glSamplerParameteri(id, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glSamplerParameteri(id, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glSamplerParameteri(id, GL_TEXTURE_COMPARE_MODE, GL_NONE);
  glSamplerParameteri(id, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glSamplerParameteri(id, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  return sampler;
}

void attachTargets(const Framebuffer& fbo, std::initializer_list<const Texture*> colour, const Texture* depth) {
  std::vector<GLenum> buffers;
  GLenum n = 0;
  for (const Texture* t : colour) {
    glNamedFramebufferTexture(fbo.id(), GL_COLOR_ATTACHMENT0 + n, t->id(), 0);
    buffers.push_back(GL_COLOR_ATTACHMENT0 + n);
    ++n;
  }
  if (depth) glNamedFramebufferTexture(fbo.id(), GL_DEPTH_ATTACHMENT, depth->id(), 0);
  glNamedFramebufferDrawBuffers(fbo.id(), static_cast<GLsizei>(buffers.size()), buffers.data());
  GLenum status = glCheckNamedFramebufferStatus(fbo.id(), GL_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE)
    throw GlError("framebuffer incomplete (status 0x" + std::to_string(status) + ")");
}

void dispatchPerPixel(int width, int height) {
  glDispatchCompute(static_cast<GLuint>((width + 7) / 8), static_cast<GLuint>((height + 7) / 8), 1);
  glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT |
                  GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
}

} // namespace dtf::render
