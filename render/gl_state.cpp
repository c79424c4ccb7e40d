// SPDX-License-Identifier: GPL-3.0-or-later
#include "render/gl_state.h"

#include <type_traits>

namespace dtf::render {

namespace {

constexpr GLenum kPixelStoreNames[GlState::kPixelStore] = {
    GL_PACK_SWAP_BYTES,   GL_PACK_LSB_FIRST,     GL_PACK_ROW_LENGTH,    GL_PACK_IMAGE_HEIGHT,
    GL_PACK_SKIP_ROWS,    GL_PACK_SKIP_PIXELS,   GL_PACK_SKIP_IMAGES,   GL_PACK_ALIGNMENT,
    GL_UNPACK_SWAP_BYTES, GL_UNPACK_LSB_FIRST,   GL_UNPACK_ROW_LENGTH,  GL_UNPACK_IMAGE_HEIGHT,
    GL_UNPACK_SKIP_ROWS,  GL_UNPACK_SKIP_PIXELS, GL_UNPACK_SKIP_IMAGES, GL_UNPACK_ALIGNMENT};

// The switches captured one by one (the per-buffer blend and the clip distances are separate).
struct Switch {
  GLenum cap;
  GLboolean GlState::*field;
  GLboolean passValue; // what the passes run with
};
constexpr Switch kSwitches[] = {
    {GL_DEPTH_TEST, &GlState::depthTest, GL_FALSE},
    {GL_CULL_FACE, &GlState::cullFace, GL_FALSE},
    {GL_SCISSOR_TEST, &GlState::scissorTest, GL_FALSE},
    {GL_STENCIL_TEST, &GlState::stencilTest, GL_FALSE},
    {GL_POLYGON_OFFSET_FILL, &GlState::polygonOffsetFill, GL_FALSE},
    {GL_DEPTH_CLAMP, &GlState::depthClamp, GL_FALSE},
    {GL_RASTERIZER_DISCARD, &GlState::rasterizerDiscard, GL_FALSE},
    {GL_COLOR_LOGIC_OP, &GlState::colourLogicOp, GL_FALSE},
    {GL_FRAMEBUFFER_SRGB, &GlState::framebufferSrgb, GL_FALSE},
};

void setSwitch(GLenum cap, GLboolean on) {
  if (on)
    glEnable(cap);
  else
    glDisable(cap);
}

template <class T> std::string text(const T& v) {
  if constexpr (std::is_arithmetic_v<T>) {
    return std::to_string(v);
  } else {
    std::string t;
    for (const auto& x : v)
      t += (t.empty() ? "" : " ") + text(x);
    return "(" + t + ")";
  }
}

template <class T> void diff(std::string& out, const char* name, const T& a, const T& b) {
  if (a == b) return;
  out += (out.empty() ? "" : ", ") + std::string(name) + " " + text(a) + " != " + text(b);
}

} // namespace

GlState GlState::capture() {
  GlState s;
  glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &s.drawFramebuffer);
  glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &s.readFramebuffer);
  glGetIntegerv(GL_VIEWPORT, s.viewport.data());
  for (int i = 0; i < kViewports; ++i)
    glGetFloati_v(GL_VIEWPORT, static_cast<GLuint>(i), s.viewports[i].data());
  for (int i = 0; i < kViewports; ++i)
    glGetIntegeri_v(GL_SCISSOR_BOX, static_cast<GLuint>(i), s.scissorBoxes[i].data());
  glGetDoublev(GL_DEPTH_RANGE, s.depthRange.data());
  glGetIntegerv(GL_CLIP_ORIGIN, &s.clipOrigin);
  glGetIntegerv(GL_CLIP_DEPTH_MODE, &s.clipDepthMode);
  for (const Switch& w : kSwitches)
    s.*w.field = glIsEnabled(w.cap);
  s.blend = glIsEnabled(GL_BLEND);
  for (int i = 0; i < kDrawBuffers; ++i)
    s.blendi[i] = glIsEnabledi(GL_BLEND, static_cast<GLuint>(i));
  glGetIntegerv(GL_BLEND_SRC_RGB, &s.blendFunc[0]);
  glGetIntegerv(GL_BLEND_DST_RGB, &s.blendFunc[1]);
  glGetIntegerv(GL_BLEND_SRC_ALPHA, &s.blendFunc[2]);
  glGetIntegerv(GL_BLEND_DST_ALPHA, &s.blendFunc[3]);
  glGetIntegerv(GL_BLEND_EQUATION_RGB, &s.blendEquation[0]);
  glGetIntegerv(GL_BLEND_EQUATION_ALPHA, &s.blendEquation[1]);
  for (int i = 0; i < kClipDistances; ++i)
    s.clipDistance[i] = glIsEnabled(static_cast<GLenum>(GL_CLIP_DISTANCE0 + i));
  glGetBooleanv(GL_DEPTH_WRITEMASK, &s.depthMask);
  glGetIntegerv(GL_DEPTH_FUNC, &s.depthFunc);
  for (int i = 0; i < kDrawBuffers; ++i)
    glGetBooleani_v(GL_COLOR_WRITEMASK, static_cast<GLuint>(i), s.colourMask[i].data());
  glGetIntegerv(GL_CULL_FACE_MODE, &s.cullFaceMode);
  glGetIntegerv(GL_FRONT_FACE, &s.frontFace);
  glGetIntegerv(GL_POLYGON_MODE, s.polygonMode.data());
  glGetIntegerv(GL_CURRENT_PROGRAM, &s.program);
  if (s.program != 0) {
    GLint deleted = GL_FALSE;
    glGetProgramiv(static_cast<GLuint>(s.program), GL_DELETE_STATUS, &deleted);
    s.programDeleted = deleted ? GL_TRUE : GL_FALSE;
  }
  glGetIntegerv(GL_VERTEX_ARRAY_BINDING, &s.vertexArray);
  glGetIntegerv(GL_ATOMIC_COUNTER_BUFFER_BINDING, &s.atomicCounterBuffer);
  glGetIntegeri_v(GL_ATOMIC_COUNTER_BUFFER_BINDING, 0, &s.atomicCounterBuffer0);
  glGetInteger64i_v(GL_ATOMIC_COUNTER_BUFFER_START, 0, &s.atomicCounterStart0);
  glGetInteger64i_v(GL_ATOMIC_COUNTER_BUFFER_SIZE, 0, &s.atomicCounterSize0);
  glGetIntegerv(GL_PIXEL_PACK_BUFFER_BINDING, &s.pixelPackBuffer);
  glGetIntegerv(GL_PIXEL_UNPACK_BUFFER_BINDING, &s.pixelUnpackBuffer);
  for (int i = 0; i < kPixelStore; ++i)
    glGetIntegerv(kPixelStoreNames[i], &s.pixelStore[i]);
  glGetIntegerv(GL_ACTIVE_TEXTURE, &s.activeTexture);
  for (int u = 0; u < kTextureUnits; ++u) {
    glActiveTexture(static_cast<GLenum>(GL_TEXTURE0 + u));
    glGetIntegerv(GL_TEXTURE_BINDING_2D, &s.textures2d[u]);
    glGetIntegerv(GL_TEXTURE_BINDING_3D, &s.textures3d[u]);
    glGetIntegerv(GL_SAMPLER_BINDING, &s.samplers[u]);
  }
  glActiveTexture(static_cast<GLenum>(s.activeTexture));
  constexpr GLenum kImageParams[6] = {GL_IMAGE_BINDING_NAME,    GL_IMAGE_BINDING_LEVEL,
                                      GL_IMAGE_BINDING_LAYERED, GL_IMAGE_BINDING_LAYER,
                                      GL_IMAGE_BINDING_ACCESS,  GL_IMAGE_BINDING_FORMAT};
  for (int u = 0; u < kImageUnits; ++u)
    for (int i = 0; i < 6; ++i)
      glGetIntegeri_v(kImageParams[i], static_cast<GLuint>(u), &s.images[u][i]);
  return s;
}

void GlState::restore() const {
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, static_cast<GLuint>(drawFramebuffer));
  glBindFramebuffer(GL_READ_FRAMEBUFFER, static_cast<GLuint>(readFramebuffer));
  glViewportArrayv(0, kViewports, viewports[0].data());
  glScissorArrayv(0, kViewports, scissorBoxes[0].data());
  glDepthRange(depthRange[0], depthRange[1]);
  glClipControl(static_cast<GLenum>(clipOrigin), static_cast<GLenum>(clipDepthMode));
  for (const Switch& w : kSwitches)
    setSwitch(w.cap, this->*w.field);
  for (int i = 0; i < kDrawBuffers; ++i) {
    if (blendi[i])
      glEnablei(GL_BLEND, static_cast<GLuint>(i));
    else
      glDisablei(GL_BLEND, static_cast<GLuint>(i));
  }
  glBlendFuncSeparate(static_cast<GLenum>(blendFunc[0]), static_cast<GLenum>(blendFunc[1]),
                      static_cast<GLenum>(blendFunc[2]), static_cast<GLenum>(blendFunc[3]));
  glBlendEquationSeparate(static_cast<GLenum>(blendEquation[0]), static_cast<GLenum>(blendEquation[1]));
  for (int i = 0; i < kClipDistances; ++i)
    setSwitch(static_cast<GLenum>(GL_CLIP_DISTANCE0 + i), clipDistance[i]);
  glDepthMask(depthMask);
  glDepthFunc(static_cast<GLenum>(depthFunc));
  for (int i = 0; i < kDrawBuffers; ++i)
    glColorMaski(static_cast<GLuint>(i), colourMask[i][0], colourMask[i][1], colourMask[i][2],
                 colourMask[i][3]);
  glCullFace(static_cast<GLenum>(cullFaceMode));
  glFrontFace(static_cast<GLenum>(frontFace));
  glPolygonMode(GL_FRONT_AND_BACK, static_cast<GLenum>(polygonMode[0]));
  glUseProgram(programDeleted ? 0u : static_cast<GLuint>(program));
  glBindVertexArray(static_cast<GLuint>(vertexArray));
  if (atomicCounterSize0 > 0)
    glBindBufferRange(GL_ATOMIC_COUNTER_BUFFER, 0, static_cast<GLuint>(atomicCounterBuffer0),
                      static_cast<GLintptr>(atomicCounterStart0),
                      static_cast<GLsizeiptr>(atomicCounterSize0));
  else
    glBindBufferBase(GL_ATOMIC_COUNTER_BUFFER, 0, static_cast<GLuint>(atomicCounterBuffer0));
  glBindBuffer(GL_ATOMIC_COUNTER_BUFFER, static_cast<GLuint>(atomicCounterBuffer));
  glBindBuffer(GL_PIXEL_PACK_BUFFER, static_cast<GLuint>(pixelPackBuffer));
  glBindBuffer(GL_PIXEL_UNPACK_BUFFER, static_cast<GLuint>(pixelUnpackBuffer));
  for (int i = 0; i < kPixelStore; ++i)
    glPixelStorei(kPixelStoreNames[i], pixelStore[i]);
  for (int u = 0; u < kTextureUnits; ++u) {
    glActiveTexture(static_cast<GLenum>(GL_TEXTURE0 + u));
    glBindTexture(GL_TEXTURE_2D, static_cast<GLuint>(textures2d[u]));
    glBindTexture(GL_TEXTURE_3D, static_cast<GLuint>(textures3d[u]));
    glBindSampler(static_cast<GLuint>(u), static_cast<GLuint>(samplers[u]));
  }
  glActiveTexture(static_cast<GLenum>(activeTexture));
  for (int u = 0; u < kImageUnits; ++u) {
    const auto& i = images[u];
    glBindImageTexture(static_cast<GLuint>(u), static_cast<GLuint>(i[0]), i[1], static_cast<GLboolean>(i[2]),
                       i[3], static_cast<GLenum>(i[4]), static_cast<GLenum>(i[5]));
  }
}

std::string GlState::differences(const GlState& o) const {
  std::string out;
#define DTF_DIFF(f) diff(out, #f, f, o.f)
  DTF_DIFF(drawFramebuffer);
  DTF_DIFF(readFramebuffer);
  DTF_DIFF(viewport);
  DTF_DIFF(viewports);
  DTF_DIFF(scissorBoxes);
  DTF_DIFF(depthRange);
  DTF_DIFF(clipOrigin);
  DTF_DIFF(clipDepthMode);
  DTF_DIFF(depthTest);
  DTF_DIFF(blend);
  DTF_DIFF(cullFace);
  DTF_DIFF(scissorTest);
  DTF_DIFF(stencilTest);
  DTF_DIFF(polygonOffsetFill);
  DTF_DIFF(depthClamp);
  DTF_DIFF(rasterizerDiscard);
  DTF_DIFF(colourLogicOp);
  DTF_DIFF(framebufferSrgb);
  DTF_DIFF(blendi);
  DTF_DIFF(blendFunc);
  DTF_DIFF(blendEquation);
  DTF_DIFF(clipDistance);
  DTF_DIFF(depthMask);
  DTF_DIFF(depthFunc);
  DTF_DIFF(colourMask);
  DTF_DIFF(cullFaceMode);
  DTF_DIFF(frontFace);
  DTF_DIFF(polygonMode);
  DTF_DIFF(program);
  DTF_DIFF(programDeleted);
  DTF_DIFF(vertexArray);
  DTF_DIFF(activeTexture);
  DTF_DIFF(atomicCounterBuffer);
  DTF_DIFF(atomicCounterBuffer0);
  DTF_DIFF(atomicCounterStart0);
  DTF_DIFF(atomicCounterSize0);
  DTF_DIFF(pixelPackBuffer);
  DTF_DIFF(pixelUnpackBuffer);
  DTF_DIFF(pixelStore);
  DTF_DIFF(textures2d);
  DTF_DIFF(textures3d);
  DTF_DIFF(samplers);
  DTF_DIFF(images);
#undef DTF_DIFF
  return out;
}

GlStateGuard::GlStateGuard() : saved_(GlState::capture()) {
  for (const Switch& w : kSwitches)
    setSwitch(w.cap, w.passValue);
  glDisable(GL_BLEND);
  for (int i = 0; i < GlState::kClipDistances; ++i)
    glDisable(static_cast<GLenum>(GL_CLIP_DISTANCE0 + i));
  glDepthMask(GL_TRUE);
  glDepthFunc(GL_LESS);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glCullFace(GL_BACK);
  glFrontFace(GL_CCW);
  glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
  glDepthRange(0.0, 1.0);
  glClipControl(GL_LOWER_LEFT, GL_NEGATIVE_ONE_TO_ONE);
  glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
  glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
  const GlState defaults;
  for (int i = 0; i < GlState::kPixelStore; ++i)
    glPixelStorei(kPixelStoreNames[i], defaults.pixelStore[i]);
  for (int u = 0; u < GlState::kTextureUnits; ++u)
    if (saved_.samplers[u]) glBindSampler(static_cast<GLuint>(u), 0);
}

GlStateGuard::~GlStateGuard() {
  saved_.restore();
}

} // namespace dtf::render
