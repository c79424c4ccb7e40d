// SPDX-License-Identifier: GPL-3.0-or-later
#include "render/gpu_scene.h"

#include "render/detail/volume_upload.h"
#include "render/gl_context.h"

#include "io/model/error.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

namespace dtf::render {

void GpuMesh::upload(const Mesh& mesh) {
  Mesh copy;
  const Mesh* m = &mesh;
  if (mesh.normals.size() != mesh.positions.size()) {
    copy = mesh;
    copy.computeNormals();
    m = &copy;
  }
  std::vector<float> interleaved;
  interleaved.reserve(m->positions.size() * 6);
  for (std::size_t i = 0; i < m->positions.size(); ++i) {
    const glm::vec3& p = m->positions[i];
    const glm::vec3& n = m->normals[i];
    interleaved.insert(interleaved.end(), {p.x, p.y, p.z, n.x, n.y, n.z});
  }
  vao_ = createVertexArray();
  vertices_ = createBuffer();
  indices_ = createBuffer();
  glNamedBufferStorage(vertices_.id(), static_cast<GLsizeiptr>(interleaved.size() * sizeof(float)),
                       interleaved.empty() ? nullptr : interleaved.data(), 0);
  glNamedBufferStorage(indices_.id(), static_cast<GLsizeiptr>(m->indices.size() * sizeof(std::uint32_t)),
                       m->indices.empty() ? nullptr : m->indices.data(), 0);
  glVertexArrayVertexBuffer(vao_.id(), 0, vertices_.id(), 0, 6 * sizeof(float));
  glVertexArrayElementBuffer(vao_.id(), indices_.id());
  glEnableVertexArrayAttrib(vao_.id(), 0);
  glEnableVertexArrayAttrib(vao_.id(), 1);
  glVertexArrayAttribFormat(vao_.id(), 0, 3, GL_FLOAT, GL_FALSE, 0);
  glVertexArrayAttribFormat(vao_.id(), 1, 3, GL_FLOAT, GL_FALSE, 3 * sizeof(float));
  glVertexArrayAttribBinding(vao_.id(), 0, 0);
  glVertexArrayAttribBinding(vao_.id(), 1, 0);
  indexCount_ = m->indices.size();
  closedOutward_ = m->isClosedOutward();
  if (!m->positions.empty()) {
    glm::vec3 lo, hi;
    m->bounds(lo, hi);
    lo_ = lo;
    hi_ = hi;
  }
}

void GpuMesh::draw() const {
  if (!indexCount_) return;
  glBindVertexArray(vao_.id());
  glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(indexCount_), GL_UNSIGNED_INT, nullptr);
}

void GpuMesh::drawVisible(bool viewOutside) const {
  const bool cull = closedOutward_ && viewOutside;
  if (cull) {
    glFrontFace(GL_CCW);
    glCullFace(GL_BACK);
    glEnable(GL_CULL_FACE);
  }
  draw();
  if (cull) glDisable(GL_CULL_FACE);
}

namespace detail {
void checkFits3D(const glm::ivec3& d, const char* what) {
  GLint maxSize = 0;
  glGetIntegerv(GL_MAX_3D_TEXTURE_SIZE, &maxSize);
  if (d.x <= 0 || d.y <= 0 || d.z <= 0 || d.x > maxSize || d.y > maxSize || d.z > maxSize)
    throw GlError(std::string(what) + " grid " + std::to_string(d.x) + "x" + std::to_string(d.y) + "x" +
                  std::to_string(d.z) + " exceeds this GL's 3D texture size limit (" +
                  std::to_string(maxSize) + " voxels per axis); crop or resample the volume");
}

void checkUploaded(const glm::ivec3& d, std::size_t bytes, const char* what) {
  const GLenum e = glGetError();
  if (e == GL_NO_ERROR) return;
  const std::string grid = std::to_string(d.x) + "x" + std::to_string(d.y) + "x" + std::to_string(d.z);
  if (e == GL_OUT_OF_MEMORY)
    throw GlError(std::string("out of GPU memory for the ") + what + " 3D textures (" + grid + " voxels, " +
                  std::to_string(bytes >> 20) + " MiB)");
  char code[16];
  std::snprintf(code, sizeof code, "0x%04x", e);
  // The driver's debug messages name the call that failed (the error may be left by an earlier call).
  std::string said;
  for (const std::string& m : takeDebugMessages()) said += "; " + m;
  throw GlError(std::string("uploading the ") + what + " 3D textures (" + grid +
                " voxels) failed: GL error " + code + said);
}

std::vector<float> blurredMask(const std::vector<float>& texels, int stride, int channel, const glm::ivec3& d) {
  const std::size_t n = static_cast<std::size_t>(d.x) * d.y * d.z;
  std::vector<float> e(n), tmp(n);
  for (std::size_t i = 0; i < n; ++i)
    e[i] = texels[i * static_cast<std::size_t>(stride) + static_cast<std::size_t>(channel)];
  const std::size_t step[3] = {1, static_cast<std::size_t>(d.x), static_cast<std::size_t>(d.x) * d.y};
  for (int axis = 0; axis < 3; ++axis) {
    for (int k = 0; k < d.z; ++k)
      for (int j = 0; j < d.y; ++j)
        for (int i = 0; i < d.x; ++i) {
          const std::size_t idx = static_cast<std::size_t>(i) + step[1] * j + step[2] * k;
          const int pos = axis == 0 ? i : axis == 1 ? j : k;
          const float lo = pos > 0 ? e[idx - step[axis]] : e[idx];
          const float hi = pos + 1 < d[axis] ? e[idx + step[axis]] : e[idx];
          tmp[idx] = 0.25f * lo + 0.5f * e[idx] + 0.25f * hi;
        }
    e.swap(tmp);
  }
  return e;
}

glm::mat4 worldToTexture(const Grid& grid) {
  glm::dmat4 worldToVoxel = glm::inverse(grid.voxelToWorld);
  glm::dmat4 voxelToTex(1.0);
  for (int c = 0; c < 3; ++c) {
    voxelToTex[c][c] = 1.0 / grid.dims[c];
    voxelToTex[3][c] = 0.5 / grid.dims[c];
  }
  return glm::mat4(voxelToTex * worldToVoxel);
}
} // namespace detail

using detail::checkFits3D;
using detail::checkUploaded;
using detail::blurredMask;
using detail::worldToTexture;

void GpuTensorField::upload(const TensorField& field) {
  const glm::ivec3 d = field.grid.dims;
  checkFits3D(d, "the tensor field's");
  const std::size_t n = field.grid.voxelCount();
  if (field.tensors.size() != n) throw GlError("tensor field has " + std::to_string(field.tensors.size()) +
                                                " tensors for " + std::to_string(n) + " voxels");
  ScalarVolume fa = computeFaMap(field);
  std::vector<float> a(n * 4), b(n * 4);
  for (std::size_t i = 0; i < n; ++i) {
    const SymTensor& t = field.tensors[i];
    bool ok = (field.valid.empty() || field.valid[i]) && t.isFinite() && !t.isZero();
    a[i * 4 + 0] = ok ? t.xx : 0.0f;
    a[i * 4 + 1] = ok ? t.xy : 0.0f;
    a[i * 4 + 2] = ok ? t.xz : 0.0f;
    a[i * 4 + 3] = ok ? t.yy : 0.0f;
    b[i * 4 + 0] = ok ? t.yz : 0.0f;
    b[i * 4 + 1] = ok ? t.zz : 0.0f;
    b[i * 4 + 2] = ok ? fa.data[i] : 0.0f;
    b[i * 4 + 3] = ok ? 1.0f : 0.0f;
  }
  a_ = Texture::create3D(GL_RGBA32F, d.x, d.y, d.z);
  b_ = Texture::create3D(GL_RGBA32F, d.x, d.y, d.z);
  glTextureSubImage3D(a_.id(), 0, 0, 0, 0, d.x, d.y, d.z, GL_RGBA, GL_FLOAT, a.data());
  glTextureSubImage3D(b_.id(), 0, 0, 0, 0, d.x, d.y, d.z, GL_RGBA, GL_FLOAT, b.data());
  checkUploaded(d, 2 * a.size() * sizeof(float), "tensor field's");
  const std::vector<float> e = blurredMask(b, 4, 3, d); // the mask is b's .w
  edge_ = Texture::create3D(GL_R32F, d.x, d.y, d.z);
  glTextureSubImage3D(edge_.id(), 0, 0, 0, 0, d.x, d.y, d.z, GL_RED, GL_FLOAT, e.data());
  checkUploaded(d, e.size() * sizeof(float), "tensor field's edge");
  edge_.setFilter(GL_LINEAR, GL_LINEAR);
  for (GLenum wrap : {GL_TEXTURE_WRAP_S, GL_TEXTURE_WRAP_T, GL_TEXTURE_WRAP_R})
    glTextureParameteri(edge_.id(), wrap, GL_CLAMP_TO_EDGE);
  worldToTex_ = worldToTexture(field.grid);
}

void GpuScalarVolume::upload(const ScalarVolume& volume, float lo, float hi, int channels) {
  const glm::ivec3 d = volume.grid.dims;
  checkFits3D(d, "the background volume's");
  const std::size_t n = volume.grid.voxelCount(), ch = channels == 3 ? 3 : 1,
                    comps = static_cast<std::size_t>(volume.components);
  const float scale = hi > lo ? 1.0f / (hi - lo) : 0.0f;
  std::vector<float> v(n * ch);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t c = 0; c < ch; ++c) {
      const float x = volume.data[i * comps + (c < comps ? c : 0)];
      v[i * ch + c] = std::isfinite(x) ? std::clamp((x - lo) * scale, 0.0f, 1.0f) : 0.0f;
    }
  texture_ = Texture::create3D(ch == 3 ? GL_RGB32F : GL_R32F, d.x, d.y, d.z);
  glTextureSubImage3D(texture_.id(), 0, 0, 0, 0, d.x, d.y, d.z, ch == 3 ? GL_RGB : GL_RED, GL_FLOAT, v.data());
  checkUploaded(d, v.size() * sizeof(float), "background volume's");
  texture_.setFilter(GL_LINEAR, GL_LINEAR);
  glTextureParameteri(texture_.id(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_BORDER);
  glTextureParameteri(texture_.id(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_BORDER);
  glTextureParameteri(texture_.id(), GL_TEXTURE_WRAP_R, GL_CLAMP_TO_BORDER);
  const float black[4] = {0, 0, 0, 0};
  glTextureParameterfv(texture_.id(), GL_TEXTURE_BORDER_COLOR, black);
  worldToTex_ = worldToTexture(volume.grid);
}

void GpuScalarVolume::bind(GLuint unit) const { glBindTextureUnit(unit, texture_.id()); }

void GpuTensorField::bind(GLuint unitA, GLuint unitB, GLuint unitEdge) const {
  glBindTextureUnit(unitA, a_.id());
  glBindTextureUnit(unitB, b_.id());
  glBindTextureUnit(unitEdge, edge_.id());
}

Texture uploadNoise(const NoiseTile& tile) {
  int levels = 1;
  while ((tile.size >> levels) > 0) ++levels;
  Texture t = Texture::create2D(GL_R32F, tile.size, tile.size, levels);
  glTextureSubImage2D(t.id(), 0, 0, 0, tile.size, tile.size, GL_RED, GL_FLOAT, tile.values.data());
  glGenerateTextureMipmap(t.id());
  t.setWrap(GL_REPEAT);
  t.setFilter(GL_LINEAR_MIPMAP_LINEAR, GL_LINEAR);
  return t;
}

} // namespace dtf::render
