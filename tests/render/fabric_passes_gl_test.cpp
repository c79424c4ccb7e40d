// SPDX-License-Identifier: GPL-3.0-or-later
// Each fabric pass in isolation against a small CPU reference on synthetic input.
#include "support/gl_test.h"
#include "support/vector_texels.h"

#include "io/model/tensor.h"
#include "render/fabric/advection_pass.h"
#include "render/fabric/composite_pass.h"
#include "render/fabric/projection_pass.h"
#include "render/fabric/silhouette_pass.h"
#include "render/reference/scenes.h"
#include "render/shader_program.h"

#include <glm/gtc/matrix_transform.hpp>

#include <cstring>
#include <random>

using namespace dtf;
using namespace dtf::render;
using dtf::test::readTexture;
using dtf::test::readVectors;
using dtf::test::textureFrom;

namespace {

class FabricPass : public GlTest {};

constexpr int kW = 64, kH = 48;

std::vector<float> randomField(int w, int h, int channels, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<float> v(static_cast<std::size_t>(w) * h * channels);
  for (auto& x : v) x = u(rng);
  return v;
}

// Surface texture: beta from `beta`, coverage everywhere (or per mask), depth 100.
std::vector<float> surfaceData(const std::vector<float>& beta, const std::vector<unsigned char>* mask = nullptr) {
  std::vector<float> s(beta.size() * 4);
  for (std::size_t i = 0; i < beta.size(); ++i) {
    bool on = !mask || (*mask)[i];
    s[i * 4 + 0] = on ? beta[i] : 0.0f;
    s[i * 4 + 1] = 0.5f;
    s[i * 4 + 2] = 100.0f;
    s[i * 4 + 3] = on ? 1.0f : 0.0f;
  }
  return s;
}

// Coverage of the fixture's target: 1, but for an uncovered strip of 6 columns at the left.
std::vector<unsigned char> uncoveredStripMask() {
  std::vector<unsigned char> mask(static_cast<std::size_t>(kW) * kH, 1);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < 6; ++x) mask[static_cast<std::size_t>(y) * kW + x] = 0;
  return mask;
}

// CPU reference of one Eq. 12 iteration (advection.frag): bilinear sampling in pixel units; a sample whose
// footprint touches a blocked texel (silhouette, off the surface, the target's outer ring, outside) is
// replaced by p_i(x); blocked pixels keep their value.
std::vector<float> advectReference(const std::vector<float>& prev, const std::vector<float>& vectors,
                                   const std::vector<float>& surface, const std::vector<float>& edges, int w, int h,
                                   float k, float step) {
  auto blockedTexel = [&](int x, int y) {
    if (x <= 0 || y <= 0 || x >= w - 1 || y >= h - 1) return true; // outside, or the target's outer ring
    std::size_t i = static_cast<std::size_t>(y) * w + x;
    return surface[i * 4 + 3] < 0.5f || edges[i] > 0.5f;
  };
  // Returns false when the footprint touches a blocked texel.
  auto bilinear = [&](double px, double py, int c, double& out) {
    double u = px - 0.5, v = py - 0.5;
    int x0 = static_cast<int>(std::floor(u)), y0 = static_cast<int>(std::floor(v));
    double fx = u - x0, fy = v - y0;
    double acc = 0;
    for (int n = 0; n < 4; ++n) {
      int x = x0 + (n & 1), y = y0 + (n >> 1);
      double wgt = ((n & 1) ? fx : 1 - fx) * ((n >> 1) ? fy : 1 - fy);
      if (wgt <= 0) continue;
      if (blockedTexel(x, y)) return false;
      acc += wgt * prev[(static_cast<std::size_t>(y) * w + x) * 2 + c];
    }
    out = acc;
    return true;
  };
  std::vector<float> out(prev);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      std::size_t i = static_cast<std::size_t>(y) * w + x;
      if (blockedTexel(x, y)) continue;
      double beta = surface[i * 4];
      for (int c = 0; c < 2; ++c) {
        double here = prev[i * 2 + c];
        double vx = vectors[i * 4 + 2 * c] * step, vy = vectors[i * 4 + 2 * c + 1] * step;
        double avg = here;
        if (vx != 0 || vy != 0) {
          double cx = x + 0.5, cy = y + 0.5, a = here, b = here;
          if (!bilinear(cx + vx, cy + vy, c, a)) a = here;
          if (!bilinear(cx - vx, cy - vy, c, b)) b = here;
          avg = 0.5 * (a + b);
        }
        out[i * 2 + c] = static_cast<float>(k * beta + (1 - k) * avg);
      }
    }
  return out;
}

// One Eq. 12 iteration by `pass` (the compute shader or the fragment pass) from a restart on `surface` and
// `edges` with the fields set to `start`: the (p1, p2) pairs after it.
std::vector<float> iterateOnce(AdvectionPass& pass, bool compute, const Texture& surface,
                               const Texture& edges, const std::vector<float>& start, const Texture& vectors,
                               const AdvectionSettings& as) {
  pass.setCompute(compute);
  pass.reset(surface, edges);
  pass.setFields(start.data());
  pass.iterate(vectors, as, 1);
  return pass.readFields();
}

// The silhouette texture as the silhouette pass leaves it: 1 on edges and off the surface, border 1.
Texture edgeTexture(std::vector<float> edges, const std::vector<float>& surface) {
  for (std::size_t i = 0; i < edges.size(); ++i)
    if (surface[i * 4 + 3] < 0.5f) edges[i] = 1.0f;
  Texture t = textureFrom(GL_R16F, GL_RED, kW, kH, edges);
  t.setWrap(GL_CLAMP_TO_BORDER);
  const float one[4] = {1, 1, 1, 1};
  glTextureParameterfv(t.id(), GL_TEXTURE_BORDER_COLOR, one);
  return t;
}

// The projection's vectors target as an advection iteration reads it (support/vector_texels.h), at the
// fixture's size unless told.
Texture vectorTexture(const std::vector<float>& v, const std::vector<float>& beta, int w = kW, int h = kH) {
  return dtf::test::vectorTexture(v, beta, w, h);
}

// The three-field layout of the same vectors, with a third direction of zero everywhere.
Texture vectors3Texture(const std::vector<float>& v, const std::vector<float>& beta, int w = kW, int h = kH) {
  return dtf::test::vectors3Texture(v, beta, std::vector<float>(static_cast<std::size_t>(w) * h * 2, 0.0f), w, h);
}

// A constant noise tile (beta = 0.5): the projection tests look at directions, not at the noise.
Texture flatNoise() {
  NoiseTile tile;
  tile.size = 8;
  tile.values.assign(64, 0.5f);
  return uploadNoise(tile);
}

// Unit image-space directions at random angles, max-norm scaled.
std::vector<float> randomVectors(int w, int h, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> ang(0.0f, 6.2831853f);
  std::vector<float> v(static_cast<std::size_t>(w) * h * 4);
  for (std::size_t i = 0; i < v.size(); i += 2) {
    float a = ang(rng);
    float x = std::cos(a), y = std::sin(a), m = std::max(std::abs(x), std::abs(y));
    v[i] = x / m;
    v[i + 1] = y / m;
  }
  return v;
}

} // namespace

TEST_F(FabricPass, ShaderPreprocessorInjectsDefinesAndLineDirectives) {
  ShaderSource s = preprocessShader("fabric/projection.frag", {"WITH_PRINCIPAL", "ANSWER 42"});
  ASSERT_EQ(s.text.rfind("#version 450 core\n#define WITH_PRINCIPAL\n#define ANSWER 42\n", 0), 0u) << s.text.substr(0, 200);
  ASSERT_GE(s.files.size(), 5u);
  EXPECT_EQ(s.files[0], "fabric/projection.frag");
  EXPECT_EQ(s.files[1], "common/projection_pixel.glsl"); // which includes the rest
  EXPECT_EQ(s.files[2], "common/projection_params.glsl");
  EXPECT_EQ(s.files[3], "common/eigen.glsl");
  EXPECT_NE(s.text.find("#line 1 1\n"), std::string::npos);
  EXPECT_NE(s.text.find("void eigenDecompose("), std::string::npos);
  EXPECT_EQ(s.text.find("#include"), std::string::npos);
  EXPECT_THROW(preprocessShader("fabric/no_such_file.frag"), GlError);
}

TEST_F(FabricPass, CompileErrorsNameTheFileAndLine) {
  try {
    ShaderProgram p("common/fullscreen.vert", "test/broken.frag");
    FAIL() << "the broken shader compiled";
  } catch (const GlError& e) {
    std::string msg = e.what();
    EXPECT_NE(msg.find("test/broken.frag:7"), std::string::npos) << msg;
    EXPECT_NE(msg.find("1 = common/eigen.glsl"), std::string::npos) << msg;
  }
  takeDebugMessages(); // the compiler's own debug message about the failure is expected here
}

TEST_F(FabricPass, GlslEigenSolverMatchesCpuReference) {
  // Random SPD tensors plus the hard cases: zero, isotropic, repeated eigenvalues, diagonal, tiny scale.
  std::vector<glm::dmat3> cases = {glm::dmat3(0.0), glm::dmat3(1e-3), glm::dmat3(2.0, 0, 0, 0, 1, 0, 0, 0, 1),
                                   glm::dmat3(1.0, 0, 0, 0, 1, 0, 0, 0, 3), glm::dmat3(3.0, 0, 0, 0, 2, 0, 0, 0, 1)};
  std::mt19937 rng(7);
  std::normal_distribution<double> g(0, 1);
  while (cases.size() < 64) {
    glm::dmat3 r;
    glm::dvec3 a(g(rng), g(rng), g(rng)), b(g(rng), g(rng), g(rng));
    a = glm::normalize(a);
    b = glm::normalize(b - a * glm::dot(a, b));
    r = glm::dmat3(a, b, glm::cross(a, b));
    glm::dvec3 l(std::abs(g(rng)) * 1e-3, std::abs(g(rng)) * 1e-3, std::abs(g(rng)) * 1e-3);
    if (cases.size() % 3 == 0) l.y = l.x; // repeated
    cases.push_back(r * glm::dmat3(l.x, 0, 0, 0, l.y, 0, 0, 0, l.z) * glm::transpose(r));
  }
  const int n = static_cast<int>(cases.size());
  std::vector<float> a(n * 4), b(n * 4);
  for (int i = 0; i < n; ++i) {
    SymTensor t = SymTensor::fromMat(cases[i]);
    a[i * 4] = t.xx, a[i * 4 + 1] = t.xy, a[i * 4 + 2] = t.xz, a[i * 4 + 3] = t.yy;
    b[i * 4] = t.yz, b[i * 4 + 1] = t.zz;
  }
  Texture ta = textureFrom(GL_RGBA32F, GL_RGBA, n, 1, a), tb = textureFrom(GL_RGBA32F, GL_RGBA, n, 1, b);
  Texture out[5];
  for (auto& o : out) o = Texture::create2D(GL_RGBA32F, n, 1);
  Framebuffer fbo = createFramebuffer();
  attachTargets(fbo, {&out[0], &out[1], &out[2], &out[3], &out[4]}, nullptr);
  ShaderProgram prog("common/fullscreen.vert", "test/eigen_probe.frag");
  VertexArray vao = createVertexArray();
  glBindFramebuffer(GL_FRAMEBUFFER, fbo.id());
  glViewport(0, 0, n, 1);
  prog.use();
  glBindTextureUnit(0, ta.id());
  glBindTextureUnit(1, tb.id());
  glBindVertexArray(vao.id());
  glDrawArrays(GL_TRIANGLES, 0, 3);
  auto vals = readTexture(out[0], 4);
  std::vector<float> vecs[3] = {readTexture(out[1], 4), readTexture(out[2], 4), readTexture(out[3], 4)};
  auto principal = readTexture(out[4], 4);
  for (int i = 0; i < n; ++i) {
    glm::dmat3 m = SymTensor::fromMat(cases[i]).toMat();
    EigenSystem e = eigenDecompose(m);
    double scale = std::max(std::abs(e.values.x), std::abs(e.values.z)) + 1e-12;
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(vals[i * 4 + c], e.values[c], 2e-4 * scale) << "case " << i << " value " << c;
      glm::dvec3 v(vecs[c][i * 4], vecs[c][i * 4 + 1], vecs[c][i * 4 + 2]);
      ASSERT_TRUE(std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z)) << "case " << i;
      EXPECT_NEAR(glm::length(v), 1.0, 1e-3) << "case " << i;
      // Residual |A v - lambda v| small: valid even for repeated eigenvalues, where the basis is free.
      double res = glm::length(m * v - double(vals[i * 4 + c]) * v);
      EXPECT_LT(res, 2e-3 * scale + 1e-9) << "case " << i << " vector " << c;
    }
    // principalEigenvector: a unit eigenvector of the largest eigenvalue, the same as eigenDecompose's
    // first vector wherever that eigenvalue is separated from the second.
    glm::dvec3 pv(principal[i * 4], principal[i * 4 + 1], principal[i * 4 + 2]);
    EXPECT_NEAR(glm::length(pv), 1.0, 1e-3) << "case " << i;
    EXPECT_LT(glm::length(m * pv - double(vals[i * 4]) * pv), 2e-3 * scale + 1e-9) << "case " << i;
    if (e.values.x - e.values.y > 1e-2 * scale) {
      EXPECT_GT(std::abs(glm::dot(pv, e.vectors[0])), 0.999) << "case " << i;
    }
  }
}

namespace {
struct ProjectionCase {
  bool perspective;
};
} // namespace

TEST_F(FabricPass, ProjectedEigenvectorsLieInTheTangentPlaneAndAreMaxNormScaled) {
  for (bool perspective : {false, true}) {
    SCOPED_TRACE(perspective ? "perspective" : "orthographic");
    const glm::dvec3 n = glm::normalize(glm::dvec3(0.3, -0.2, 1.0));
    const glm::dvec3 u = glm::normalize(glm::cross(n, glm::dvec3(0, 1, 0))), v = glm::cross(n, u);
    Mesh plane = reference::planeMesh({0, 0, 0}, u, v, 50, 50, 4);
    plane.normals.assign(plane.positions.size(), glm::vec3(n));
    const glm::dvec3 d = glm::normalize(glm::dvec3(1.0, 0.5, 0.8)); // partly out of the plane
    Grid grid = reference::centredGrid(32, 2.0);
    TensorField field = reference::constantField(grid, d, 1.7e-3, 0.3e-3);
    // Make the two in-plane eigenvalues distinct also for the second direction: add a third component.
    for (auto& t : field.tensors) t = SymTensor::fromMat(t.toMat() + 0.4e-3 * glm::outerProduct(u, u));

    GpuMesh mesh;
    mesh.upload(plane);
    GpuTensorField gpuField;
    gpuField.upload(field);
    Texture noise = flatNoise();

    Camera cam;
    cam.orthographic = !perspective;
    cam.lookAt({20, -30, 80}, {0, 0, 0}, {0, 1, 0});
    cam.fit({-25, -25, -10}, {25, 25, 10}, double(kW) / kH);
    FrameView view = FrameView::make(cam, {kW, kH}, 4, {-25, -25, -10}, {25, 25, 10});
    ProjectionPass pass;
    ProjectionSettings ps;
    pass.run(mesh, gpuField, noise, view, ps);
    auto vec = readVectors(pass.vectors());
    auto surf = readTexture(pass.surface(), 4);
    const auto beta = dtf::test::readVectorBeta(pass.vectors()); // 12 bits of the surface target's beta

    // CPU reference directions in the plane.
    glm::dmat3 P = glm::dmat3(1.0) - glm::outerProduct(n, n);
    glm::dmat3 T = field.tensors[0].toMat();
    EigenSystem e = eigenDecompose(P * T * glm::transpose(P));
    std::vector<glm::dvec3> inPlane;
    for (int i = 0; i < 3; ++i)
      if (std::abs(glm::dot(e.vectors[i], n)) < 0.5) inPlane.push_back(e.vectors[i]);
    ASSERT_EQ(inPlane.size(), 2u);

    glm::dmat4 inv = glm::inverse(glm::dmat4(view.viewProj));
    auto unproject = [&](glm::dvec2 px) { // pixel -> point on the plane
      glm::dvec2 ndc = px / glm::dvec2(view.target) * 2.0 - 1.0;
      glm::dvec4 a = inv * glm::dvec4(ndc, -1, 1), b = inv * glm::dvec4(ndc, 1, 1);
      glm::dvec3 pa = glm::dvec3(a) / a.w, pb = glm::dvec3(b) / b.w;
      double t = -glm::dot(pa, n) / glm::dot(pb - pa, n);
      return pa + t * (pb - pa);
    };
    int checked = 0;
    for (int y = 0; y < view.target.y; y += 3)
      for (int x = 0; x < view.target.x; x += 3) {
        std::size_t i = static_cast<std::size_t>(y) * view.target.x + x;
        if (surf[i * 4 + 3] < 0.5f) continue;
        EXPECT_NEAR(beta[i], surf[i * 4], 0.5 / 4095 + 1e-6);
        for (int c = 0; c < 2; ++c) {
          glm::dvec2 iv(vec[i * 4 + 2 * c], vec[i * 4 + 2 * c + 1]);
          EXPECT_NEAR(std::max(std::abs(iv.x), std::abs(iv.y)), 1.0, 2e-3);
          glm::dvec2 px(x + 0.5, y + 0.5);
          glm::dvec3 q0 = unproject(px), q1 = unproject(px + 0.25 * iv);
          glm::dvec3 w = glm::normalize(q1 - q0);
          EXPECT_NEAR(glm::dot(w, n), 0.0, 1e-6); // in the tangent plane by construction of the unprojection
          EXPECT_GT(std::abs(glm::dot(w, inPlane[c])), 0.999) << "pixel " << x << "," << y << " dir " << c;
        }
        ++checked;
      }
    EXPECT_GT(checked, 50);
  }
}

TEST_F(FabricPass, DegenerateAndMissingTensorsGiveZeroVectorsAndNoNaN) {
  Mesh plane = reference::planeMesh({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 100, 100, 4); // beyond the 64 mm grid
  Grid grid = reference::centredGrid(32, 2.0);
  TensorField field = reference::constantField(grid, {1, 0, 0}, 1e-3, 1e-3); // isotropic
  for (int j = 0; j < 32; ++j)
    for (int i = 0; i < 16; ++i) {
      field.at(i, j, 15) = SymTensor{}; // left half: no data
      field.at(i, j, 16) = SymTensor{};
      field.valid[grid.index(i, j, 15)] = field.valid[grid.index(i, j, 16)] = 0;
    }
  GpuMesh mesh;
  mesh.upload(plane);
  GpuTensorField gpuField;
  gpuField.upload(field);
  Texture noise = flatNoise();
  Camera cam = Camera::standard(StandardView::Superior, {-50, -50, -1}, {50, 50, 1}, double(kW) / kH);
  FrameView view = FrameView::make(cam, {kW, kH}, 0, {-50, -50, -1}, {50, 50, 1});
  ProjectionPass pass;
  pass.run(mesh, gpuField, noise, view, {});
  for (const Texture* t : {&pass.surface(), &pass.eigen(), &pass.lambda()}) {
    auto data = readTexture(*t, 4);
    for (float x : data) ASSERT_TRUE(std::isfinite(x));
  }
  auto vec = readVectors(pass.vectors());
  auto surf = readTexture(pass.surface(), 4);
  auto lam = readTexture(pass.lambda(), 4);
  int withData = 0, without = 0;
  for (std::size_t i = 0; i < vec.size() / 4; ++i) {
    if (surf[i * 4 + 3] < 0.5f) continue; // the other targets are defined where the surface is
    for (int c = 0; c < 4; ++c) EXPECT_EQ(vec[i * 4 + c], 0.0f);
    (lam[i * 4 + 3] > 0.5f ? withData : without)++;
  }
  EXPECT_GT(withData, 100); // the isotropic half has data but no direction
  EXPECT_GT(without, 100);  // the invalid half and beyond the grid have none
}

TEST_F(FabricPass, AdvectionMatchesCpuReferenceForOneIteration) {
  auto beta = randomField(kW, kH, 1, 1);
  const std::vector<unsigned char> mask = uncoveredStripMask();
  auto surface = surfaceData(beta, &mask);
  auto vectors = randomVectors(kW, kH, 2);
  std::vector<float> edges(beta.size(), 0.0f);
  for (int y = 0; y < kH; ++y) edges[static_cast<std::size_t>(y) * kW + 30] = 1.0f; // a silhouette column
  auto start = randomField(kW, kH, 2, 3);
  Texture tv = vectorTexture(vectors, beta), ts = textureFrom(GL_RGBA32F, GL_RGBA, kW, kH, surface);
  Texture te = edgeTexture(edges, surface);
  vectors = readVectors(tv); // the 16-bit values the GPU sees
  for (bool compute : {false, true}) {
  SCOPED_TRACE(compute ? "compute shader" : "fragment pass");
  AdvectionPass pass;
  const AdvectionSettings as{0.2f, 1.7f, 0.05f};
  const auto state = iterateOnce(pass, compute, ts, te, start, tv, as);
  auto cpu = advectReference(start, vectors, surface, edges, kW, kH, as.k, as.stepPixels);
  auto blocked = [&](std::size_t i) {
    int x = static_cast<int>(i % kW), y = static_cast<int>(i / kW);
    return !mask[i] || edges[i] > 0.5f || x == 0 || y == 0 || x == kW - 1 || y == kH - 1;
  };
  // Bilinear weights are 8-bit fixed point on most hardware: values agree to ~1e-2, and a footprint
  // weight below 1/256 may round to zero, which decides "blocked" differently on a few pixels.
  int off = 0, blockedPixels = 0;
  for (std::size_t i = 0; i < cpu.size() / 2; ++i)
    for (int c = 0; c < 2; ++c) {
      if (blocked(i)) {
        EXPECT_EQ(state[i * 2 + c], kBlocked) << i; // blocked pixels keep the blocked state
        blockedPixels += c == 0;
        continue;
      }
      off += std::abs(state[i * 2 + c] - cpu[i * 2 + c]) > 1e-2;
    }
  EXPECT_LT(off, kW * kH / 100) << off << " values differ";
  EXPECT_GT(blockedPixels, 6 * kH); // the uncovered strip, the silhouette column and the ring
  unsigned changed = pass.changedPixels();
  // Covered pixels whose change clearly exceeds / clearly stays below epsilon bound the GPU count.
  unsigned surely = 0, possibly = 0;
  for (std::size_t i = 0; i < cpu.size() / 2; ++i) {
    if (blocked(i)) continue;
    double d = std::max(std::abs(cpu[i * 2] - start[i * 2]), std::abs(cpu[i * 2 + 1] - start[i * 2 + 1]));
    surely += d > 0.05 + 1e-2;
    possibly += d > 0.05 - 1e-2;
  }
  EXPECT_GE(changed, surely - static_cast<unsigned>(off));
  EXPECT_LE(changed, possibly + static_cast<unsigned>(off));
  EXPECT_GT(surely, 100u);
  }
}

// With a whole number of pixels per step (the default 2, and 1 and 3) each sample lies on a texel row or
// column: the iteration reads it as the two texels it falls between (INTEGER_STEP), which is the bilinear
// sample with exact weights. Every value, and every decision that a footprint touches a blocked texel, is the
// CPU reference's (against the beta the iterations read, 12 bits), in the fragment pass and the compute shader.
TEST_F(FabricPass, AdvectionWithAWholePixelStepMatchesTheCpuReferenceExactly) {
  auto beta = randomField(kW, kH, 1, 11);
  const std::vector<unsigned char> mask = uncoveredStripMask();
  auto surface = surfaceData(beta, &mask);
  auto vectors = randomVectors(kW, kH, 12);
  for (std::size_t i = 0; i < vectors.size(); i += 16) vectors[i] = vectors[i + 1] = 0.0f; // no direction
  std::vector<float> edges(beta.size(), 0.0f);
  for (int y = 0; y < kH; ++y) edges[static_cast<std::size_t>(y) * kW + 30] = 1.0f; // a silhouette column
  for (int x = 8; x < kW; ++x) edges[static_cast<std::size_t>(20) * kW + x] = 1.0f;  // and a row
  auto start = randomField(kW, kH, 2, 13);
  Texture tv = vectorTexture(vectors, beta), ts = textureFrom(GL_RGBA32F, GL_RGBA, kW, kH, surface);
  Texture te = edgeTexture(edges, surface);
  vectors = readVectors(tv); // the 16-bit values the GPU sees
  const auto iterated = dtf::test::readVectorBeta(tv);
  auto reference = surface;
  for (std::size_t i = 0; i < iterated.size(); ++i) reference[i * 4] = iterated[i];
  for (float step : {1.0f, 2.0f, 3.0f})
    for (bool compute : {false, true}) {
      SCOPED_TRACE(std::string(compute ? "compute shader" : "fragment pass") + ", step " + std::to_string(step));
      AdvectionPass pass;
      const AdvectionSettings as{0.2f, step, 0.05f};
      ASSERT_TRUE(as.integerStep());
      const auto state = iterateOnce(pass, compute, ts, te, start, tv, as);
      const auto cpu = advectReference(start, vectors, reference, edges, kW, kH, as.k, as.stepPixels);
      int compared = 0;
      for (std::size_t i = 0; i < cpu.size(); ++i) {
        const std::size_t px = i / 2;
        const int x = static_cast<int>(px % kW), y = static_cast<int>(px / kW);
        if (!mask[px] || edges[px] > 0.5f || x == 0 || y == 0 || x == kW - 1 || y == kH - 1) {
          EXPECT_EQ(state[i], kBlocked) << "pixel " << px; // blocked pixels keep the blocked state
          continue;
        }
        ASSERT_NEAR(state[i], cpu[i], 2e-6) << "pixel " << i / 2 << " field " << i % 2;
        ++compared;
      }
      EXPECT_GT(compared, kW * kH);
    }
  EXPECT_FALSE((AdvectionSettings{0.2f, 1.7f, 0.05f}.integerStep()));
}

// Each pixel reads its own state exactly, however its neighbours are blocked: at a size that is no power of
// two (a texel's centre scaled to texture coordinates and back is not exact there) every other column is a
// silhouette, and both samples of every pixel between them land on one, so p_{i+1} = k beta + (1 - k) p_i(x).
// The state textures are bilinear for the samples; p_i(x) must still be the texel's own value.
TEST_F(FabricPass, AdvectionReadsEachPixelsOwnStateBesideBlockedTexels) {
  constexpr int w = 97, h = 61;
  auto beta = randomField(w, h, 1, 41);
  auto surface = surfaceData(beta);
  std::vector<float> edges(beta.size(), 0.0f);
  for (std::size_t i = 0; i < edges.size(); ++i) edges[i] = i % w % 2 == 1 ? 1.0f : 0.0f;
  std::vector<float> directions(beta.size() * 4);
  for (std::size_t i = 0; i < beta.size(); ++i) {
    directions[i * 4] = 1.0f; // v1 along +x, v2 along -x: one pixel at a step of 1
    directions[i * 4 + 2] = -1.0f;
  }
  Texture tv = vectorTexture(directions, beta, w, h), ts = textureFrom(GL_RGBA32F, GL_RGBA, w, h, surface);
  Texture te = textureFrom(GL_R16F, GL_RED, w, h, edges);
  const auto iterated = dtf::test::readVectorBeta(tv); // beta as the iterations read it (12 bits)
  auto start = randomField(w, h, 2, 42);
  for (bool compute : {false, true}) {
  SCOPED_TRACE(compute ? "compute shader" : "fragment pass");
  AdvectionPass pass;
  const AdvectionSettings as{0.2f, 1.0f, 0.05f};
  const auto state = iterateOnce(pass, compute, ts, te, start, tv, as);
  int checked = 0;
  for (int y = 1; y < h - 1; ++y)
    for (int x = 2; x < w - 2; x += 2) {
      const std::size_t i = static_cast<std::size_t>(y) * w + x;
      for (int c = 0; c < 2; ++c)
        ASSERT_NEAR(state[i * 2 + c], as.k * iterated[i] + (1 - as.k) * start[i * 2 + c], 1e-6) << x << "," << y;
      ++checked;
    }
  EXPECT_EQ(checked, (h - 2) * (w / 2 - 1));
  }
}

// The compute shader and the fullscreen pass (with and without the early depth test) run the same
// iteration: the same three fields after counted and uncounted iterations, the same changed-pixel count.
TEST_F(FabricPass, AdvectionComputeShaderEqualsTheFragmentPass) {
  auto beta = randomField(kW, kH, 1, 21);
  std::vector<unsigned char> mask(beta.size(), 1);
  for (int y = 10; y < 20; ++y)
    for (int x = 0; x < kW; ++x) mask[static_cast<std::size_t>(y) * kW + x] = 0; // an uncovered band
  auto surface = surfaceData(beta, &mask);
  std::vector<float> edges(beta.size(), 0.0f);
  for (int x = 0; x < kW; ++x) edges[static_cast<std::size_t>(40) * kW + x] = 1.0f; // a silhouette row
  auto vectors = randomVectors(kW, kH, 22);
  Texture tv = vectorTexture(vectors, beta), ts = textureFrom(GL_RGBA32F, GL_RGBA, kW, kH, surface);
  Texture te = edgeTexture(edges, surface);
  // The third field's direction: another random field's v1, beside the same vectors in the three-field layout.
  const auto other = randomVectors(kW, kH, 23);
  std::vector<float> v3(beta.size() * 2);
  for (std::size_t i = 0; i < beta.size(); ++i) {
    v3[i * 2] = other[i * 4];
    v3[i * 2 + 1] = other[i * 4 + 1];
  }
  Texture tv3 = dtf::test::vectors3Texture(vectors, beta, v3, kW, kH);
  // The covered pixels' depth for the fragment pass's early test: covered 0.5 passes GL_GREATER at 1.
  std::vector<float> depth(beta.size());
  for (std::size_t i = 0; i < depth.size(); ++i) depth[i] = mask[i] ? 0.5f : 1.0f;
  Texture td = Texture::create2D(GL_DEPTH_COMPONENT32F, kW, kH);
  glTextureSubImage2D(td.id(), 0, 0, 0, kW, kH, GL_DEPTH_COMPONENT, GL_FLOAT, depth.data());
  struct Run {
    std::vector<float> fields;
    std::vector<float> third;
    unsigned changed;
  };
  auto run = [&](bool compute, const Texture* covered) {
    AdvectionPass pass;
    pass.setCompute(compute);
    pass.reset(ts, te, 3);
    AdvectionSettings as{0.15f, 1.5f, 0.002f};
    pass.iterate(tv3, as, 4, false, covered, 3);
    pass.iterate(tv3, as, 3, true, covered, 3);
    Run r{pass.readFields(), std::vector<float>(beta.size()), pass.changedPixels()};
    glGetTextureImage(pass.field(2).id(), 0, GL_RED, GL_FLOAT, static_cast<GLsizei>(r.third.size() * sizeof(float)),
                      r.third.data());
    return r;
  };
  const Run fragment = run(false, nullptr), early = run(false, &td), compute = run(true, nullptr);
  for (const Run* other : {&early, &compute}) {
    EXPECT_EQ(other->fields, fragment.fields);
    EXPECT_EQ(other->third, fragment.third);
    EXPECT_EQ(other->changed, fragment.changed);
  }
  EXPECT_GT(fragment.changed, 100u);
  std::size_t blocked = 0;
  for (float v : fragment.third) blocked += v == kBlocked;
  EXPECT_GT(blocked, static_cast<std::size_t>(11 * kW)); // the band, the silhouette row and the ring
}

TEST_F(FabricPass, AdvectionWithZeroVectorsConvergesToBeta) {
  auto beta = randomField(kW, kH, 1, 4);
  auto surface = surfaceData(beta);
  std::vector<float> zero(static_cast<std::size_t>(kW) * kH * 4, 0.0f), edges(beta.size(), 0.0f);
  Texture tv = vectorTexture(zero, beta), ts = textureFrom(GL_RGBA32F, GL_RGBA, kW, kH, surface);
  Texture te = edgeTexture(edges, surface);
  const auto b = dtf::test::readVectorBeta(tv); // beta as the iterations read it (12 bits)
  AdvectionPass pass;
  pass.reset(ts, te);
  std::vector<float> start(beta.size() * 2, 1.0f);
  pass.setFields(start.data());
  const float k = 0.25f;
  pass.iterate(tv, {k, 2.0f, 0.05f}, 20);
  auto p = pass.readFields();
  auto ring = [&](std::size_t i) {
    int x = static_cast<int>(i % kW), y = static_cast<int>(i / kW);
    return x == 0 || y == 0 || x == kW - 1 || y == kH - 1;
  };
  // p_n = beta + (1 - k)^n (p_0 - beta) exactly when v = 0; the target's outer ring stays blocked.
  for (std::size_t i = 0; i < beta.size(); ++i)
    for (int c = 0; c < 2; ++c)
      EXPECT_NEAR(p[i * 2 + c], ring(i) ? kBlocked : b[i] + std::pow(1 - k, 20) * (1 - b[i]), 1e-5);
  pass.iterate(tv, {k, 2.0f, 0.05f}, 40);
  p = pass.readFields();
  for (std::size_t i = 0; i < beta.size(); ++i) EXPECT_NEAR(p[i * 2], ring(i) ? kBlocked : b[i], 1e-5);
  EXPECT_EQ(pass.changedPixels(), 0u);
}

TEST_F(FabricPass, AdvectionIsSymmetricUnderVectorNegation) {
  auto beta = randomField(kW, kH, 1, 5);
  auto surface = surfaceData(beta);
  auto vectors = randomVectors(kW, kH, 6);
  std::vector<float> negated(vectors);
  for (auto& x : negated) x = -x;
  std::vector<float> edges(beta.size(), 0.0f);
  Texture ts = textureFrom(GL_RGBA32F, GL_RGBA, kW, kH, surface), te = edgeTexture(edges, surface);
  std::vector<float> results[2];
  for (int s = 0; s < 2; ++s) {
    Texture tv = vectorTexture(s ? negated : vectors, beta);
    AdvectionPass pass;
    pass.reset(ts, te);
    pass.iterate(tv, {0.1f, 2.0f, 0.05f}, 15);
    results[s] = pass.readFields();
  }
  for (std::size_t i = 0; i < results[0].size(); ++i) EXPECT_NEAR(results[0][i], results[1][i], 1e-5);
}

TEST_F(FabricPass, AdvectionForgetsItsStartAsOneMinusKToTheN) {
  auto beta = randomField(kW, kH, 1, 7);
  auto surface = surfaceData(beta);
  auto vectors = randomVectors(kW, kH, 8);
  std::vector<float> edges(beta.size(), 0.0f);
  Texture ts = textureFrom(GL_RGBA32F, GL_RGBA, kW, kH, surface), te = edgeTexture(edges, surface);
  Texture tv = vectorTexture(vectors, beta);
  const float k = 0.2f;
  const int n = 12;
  std::vector<float> out[2];
  for (int s = 0; s < 2; ++s) {
    AdvectionPass pass;
    pass.reset(ts, te);
    std::vector<float> start(beta.size() * 2, s ? 1.0f : 0.0f);
    pass.setFields(start.data());
    pass.iterate(tv, {k, 1.5f, 0.05f}, n);
    out[s] = pass.readFields();
  }
  // The map is affine in p with a stochastic (averaging) linear part scaled by 1 - k: two starts differing
  // by 1 everywhere differ by exactly (1 - k)^n after n iterations (where no sample leaves the image).
  const double expect = std::pow(1.0 - k, n);
  double sum = 0;
  int count = 0;
  for (int y = 20; y < kH - 20; ++y)
    for (int x = 20; x < kW - 20; ++x) {
      std::size_t i = static_cast<std::size_t>(y) * kW + x;
      for (int c = 0; c < 2; ++c) {
        double d = out[1][i * 2 + c] - out[0][i * 2 + c];
        EXPECT_NEAR(d, expect, 1e-3);
        sum += d;
        ++count;
      }
    }
  EXPECT_NEAR(sum / count, expect, 1e-4);
}

// A surface target over a bowl of linear depth with a step at x = 46 and a hole of empty pixels; beta noise.
std::vector<float> bowlSurface() {
  std::vector<float> surface(static_cast<std::size_t>(kW) * kH * 4, 0.0f);
  auto depthAt = [&](int x, int y) {
    double dx = x - 30.0, dy = y - 20.0;
    double d = 200.0 + 0.02 * (dx * dx + dy * dy) + (x > 45 ? 15.0 : 0.0);
    return d;
  };
  auto beta = randomField(kW, kH, 1, 21);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      std::size_t i = static_cast<std::size_t>(y) * kW + x;
      bool on = !(x > 10 && x < 16 && y > 10 && y < 30);
      surface[i * 4 + 0] = on ? beta[i] : 0.0f;
      surface[i * 4 + 2] = on ? static_cast<float>(depthAt(x, y)) : 0.0f;
      surface[i * 4 + 3] = on ? 1.0f : 0.0f;
    }
  return surface;
}

TEST_F(FabricPass, SilhouetteMatchesCpuLaplacianOfLinearDepth) {
  const std::vector<float> surface = bowlSurface();
  Texture ts = textureFrom(GL_RGBA32F, GL_RGBA, kW, kH, surface);
  SilhouettePass pass;
  const float threshold = 0.5f, background = 1000.0f;
  pass.run(ts, threshold, background);
  auto e = readTexture(pass.edges(), 1);
  int edges = 0;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      std::size_t i = static_cast<std::size_t>(y) * kW + x;
      if (surface[i * 4 + 3] < 0.5f) {
        EXPECT_EQ(e[i], 1.0f); // off the surface: blocked for the advection
        continue;
      }
      auto d = [&](int xx, int yy) {
        xx = std::clamp(xx, 0, kW - 1);
        yy = std::clamp(yy, 0, kH - 1);
        std::size_t j = static_cast<std::size_t>(yy) * kW + xx;
        return surface[j * 4 + 3] > 0.5f ? double(surface[j * 4 + 2]) : double(background);
      };
      double lap = d(x + 1, y) + d(x - 1, y) + d(x, y + 1) + d(x, y - 1) - 4 * d(x, y);
      float expect = std::abs(lap) > threshold ? 1.0f : 0.0f;
      EXPECT_EQ(e[i], expect) << x << "," << y << " lap " << lap;
      edges += expect > 0;
    }
  EXPECT_GT(edges, 40); // the step and the hole's rim
}

// A frame that restarts finds its silhouettes in the restart pass itself: the same edges as the silhouette
// pass and the same start state as the silhouette pass followed by the reset, bit for bit.
TEST_F(FabricPass, RestartFindingSilhouettesEqualsSilhouettePassThenReset) {
  // Also as compute shaders (the default on hardware GPUs): the fused and the plain restart.
  const std::vector<float> surface = bowlSurface();
  Texture ts = textureFrom(GL_RGBA32F, GL_RGBA, kW, kH, surface);
  const float threshold = 0.5f, background = 1000.0f;
  SilhouettePass twoPass;
  twoPass.run(ts, threshold, background);
  for (bool compute : {false, true}) {
    SCOPED_TRACE(compute ? "compute shaders" : "fragment passes");
    SilhouettePass fused;
    AdvectionPass resetAfter, resetFinding;
    resetAfter.setCompute(compute);
    resetFinding.setCompute(compute);
    resetAfter.reset(ts, twoPass.edges());
    fused.resize({kW, kH});
    fused.clear(); // the restart pass must write every pixel of the edges, not rely on what is there
    {
      // An earlier frame's state in both ping-pong textures (a surface covering every pixel), which the
      // restart must overwrite in both.
      const auto earlier = surfaceData(randomField(kW, kH, 1, 31));
      std::vector<float> none(static_cast<std::size_t>(kW) * kH, 0.0f), v(none.size() * 4, 0.0f);
      Texture te = textureFrom(GL_RGBA32F, GL_RGBA, kW, kH, earlier), tn = edgeTexture(none, earlier);
      Texture tv = vectorTexture(v, none);
      resetFinding.reset(te, tn);
      resetFinding.iterate(tv, {0.5f, 1.0f, 0.05f}, 1);
    }
    resetFinding.resetFindingSilhouettes(ts, fused.edges(), threshold, background);
    const auto e2 = readTexture(twoPass.edges(), 1), e1 = readTexture(fused.edges(), 1);
    ASSERT_EQ(e1.size(), e2.size());
    int edges = 0;
    for (std::size_t i = 0; i < e1.size(); ++i) {
      EXPECT_EQ(e1[i], e2[i]) << i;
      edges += e1[i] > 0.5f;
    }
    EXPECT_GT(edges, 40);
    const auto s2 = resetAfter.readFields(), s1 = resetFinding.readFields();
    ASSERT_EQ(s1.size(), s2.size());
    int blocked = 0, started = 0;
    for (std::size_t i = 0; i < s1.size(); ++i) {
      EXPECT_EQ(s1[i], s2[i]) << i;
      if (s1[i] == kBlocked) ++blocked;
      else if (s1[i] == surface[i / 2 * 4]) ++started; // p1 = p2 = beta
    }
    EXPECT_GT(blocked, 2 * 40);
    EXPECT_EQ(blocked + started, static_cast<int>(s1.size()));
    // The second ping-pong texture holds the start too (an iteration leaves blocked pixels to it): one
    // iteration with zero vectors and k = 0 changes nothing.
    std::vector<float> zero(static_cast<std::size_t>(kW) * kH * 4, 0.0f), beta(static_cast<std::size_t>(kW) * kH);
    Texture tv = vectorTexture(zero, beta);
    resetFinding.iterate(tv, {0.0f, 1.0f, 1e-4f}, 1);
    const auto after = resetFinding.readFields();
    for (std::size_t i = 0; i < s1.size(); ++i) {
      if (s1[i] == kBlocked) EXPECT_EQ(after[i], kBlocked) << i;
      else EXPECT_NEAR(after[i], s1[i], 1e-5f) << i;
    }
    EXPECT_EQ(resetFinding.changedPixels(), 0u);
  }
}

// The fragment restarts shade only the cover rect (FrameView::targetCoverRect) and clear the rest: every
// field in both ping-pong textures and the edges equal those of a restart over the whole target, bit for
// bit, for the plain and the silhouette-finding restart with two and three fields, over an earlier state.
TEST_F(FabricPass, RestartsInsideTheCoverRectEqualRestartsOfTheWholeTarget) {
  std::vector<float> surface = bowlSurface();
  const glm::ivec4 rect(11, 7, 42, 34); // the surface below lies in [12, 52) x [8, 40)
  std::vector<float> depthData(static_cast<std::size_t>(kW) * kH, 1.0f);
  int outside = 0;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * kW + x;
      if (x < 12 || x >= 52 || y < 8 || y >= 40) {
        for (int c = 0; c < 4; ++c) surface[i * 4 + c] = 0.0f;
        ++outside;
      }
      if (surface[i * 4 + 3] > 0.5f) depthData[i] = 0.5f;
    }
  Texture ts = textureFrom(GL_RGBA32F, GL_RGBA, kW, kH, surface);
  // The iterations' early depth test (uncovered pixels keep what the restart wrote in the other texture).
  Texture depth = Texture::create2D(GL_DEPTH_COMPONENT32F, kW, kH);
  glTextureSubImage2D(depth.id(), 0, 0, 0, kW, kH, GL_DEPTH_COMPONENT, GL_FLOAT, depthData.data());
  const float threshold = 0.5f, background = 1000.0f;
  SilhouettePass given;
  given.run(ts, threshold, background);
  const std::size_t n = static_cast<std::size_t>(kW) * kH;
  std::vector<float> zero(n * 4, 0.0f), beta(n);
  Texture still = vectorTexture(zero, beta), still3 = vectors3Texture(zero, beta);
  const auto earlier = surfaceData(randomField(kW, kH, 1, 57));
  std::vector<float> none(static_cast<std::size_t>(kW) * kH, 0.0f);
  Texture te = textureFrom(GL_RGBA32F, GL_RGBA, kW, kH, earlier), tn = edgeTexture(none, earlier);
  const auto moving = randomField(kW, kH, 4, 58);
  Texture tv = vectorTexture(moving, none), tv3 = vectors3Texture(moving, none);
  for (int fields : {2, 3})
    for (bool finding : {false, true}) {
      SCOPED_TRACE(std::to_string(fields) + " fields" + (finding ? ", finding silhouettes" : ""));
      AdvectionPass whole, part;
      SilhouettePass edgesWhole, edgesPart;
      for (AdvectionPass* a : {&whole, &part}) {
        a->reset(te, tn, fields); // an earlier frame's state everywhere, in both textures
        a->iterate(fields == 3 ? tv3 : tv, {0.5f, 1.0f, 0.05f}, 1, false, nullptr, fields);
      }
      for (SilhouettePass* e : {&edgesWhole, &edgesPart}) {
        e->resize({kW, kH});
        e->clear();
      }
      part.setCover(rect);
      if (finding) {
        whole.resetFindingSilhouettes(ts, edgesWhole.edges(), threshold, background, fields);
        part.resetFindingSilhouettes(ts, edgesPart.edges(), threshold, background, fields);
        EXPECT_EQ(readTexture(edgesPart.edges(), 1), readTexture(edgesWhole.edges(), 1));
      } else {
        whole.reset(ts, given.edges(), fields);
        part.reset(ts, given.edges(), fields);
      }
      for (int round = 0; round < 2; ++round) {
        SCOPED_TRACE(round == 0 ? "the restart's texture" : "the other texture");
        for (int c = 0; c < fields; ++c) {
          const auto a = readTexture(whole.field(c), 1), b = readTexture(part.field(c), 1);
          EXPECT_EQ(a, b) << "field " << c;
          int blocked = 0;
          for (float v : b) blocked += v == kBlocked;
          EXPECT_GE(blocked, outside);
        }
        // One iteration that leaves beta unchanged writes the covered pixels only.
        for (AdvectionPass* a : {&whole, &part})
          a->iterate(fields == 3 ? still3 : still, {0.0f, 1.0f, 1e-4f}, 1, false, &depth, fields);
      }
    }
  EXPECT_GT(outside, kW * kH / 3);
}

TEST_F(FabricPass, CompositeMatchesEquation13) {
  // Also at a size that is no power of two, where a texel's centre scaled to texture coordinates and back is
  // not exact: each pixel must read its own fields even beside blocked texels (common/texel.glsl).
  for (const glm::ivec2 size : {glm::ivec2(kW, kH), glm::ivec2(97, 61)}) {
  SCOPED_TRACE(size.x);
  const int w = size.x, h = size.y;
  auto p = randomField(w, h, 2, 9);
  auto beta = randomField(w, h, 1, 10);
  auto surface = surfaceData(beta);
  auto light = randomField(w, h, 1, 11);
  for (std::size_t i = 0; i < beta.size(); ++i) surface[i * 4 + 1] = light[i];
  // Silhouettes reach the composite as the advection's blocked pixels: every 7th pixel is blocked, and is a
  // silhouette (e = 1, Eq. 13 on the noise beta itself) unless it lies on the target's outermost ring, which
  // the advection blocks as well without it being a silhouette.
  std::vector<float> edges(beta.size(), 0.0f);
  std::vector<bool> blocked(beta.size(), false);
  for (std::size_t i = 0; i < blocked.size(); i += 7) {
    const int x = static_cast<int>(i % w), y = static_cast<int>(i / w);
    blocked[i] = true;
    edges[i] = x > 0 && y > 0 && x < w - 1 && y < h - 1 ? 1.0f : 0.0f;
  }
  std::vector<float> zeros(beta.size() * 4, 0.0f), depth(beta.size(), 0.5f);
  std::vector<float> p1(beta.size()), p2(beta.size());
  for (std::size_t i = 0; i < beta.size(); ++i) {
    p1[i] = blocked[i] ? kBlocked : p[i * 2];
    p2[i] = blocked[i] ? kBlocked : p[i * 2 + 1];
  }
  Texture ta = textureFrom(GL_R32F, GL_RED, w, h, p1), tb = textureFrom(GL_R32F, GL_RED, w, h, p2);
  ta.setFilter(GL_LINEAR, GL_LINEAR); // bilinear, as the advection's state for its samples
  tb.setFilter(GL_LINEAR, GL_LINEAR);
  Texture ts = textureFrom(GL_RGBA32F, GL_RGBA, w, h, surface);
  Texture tz = textureFrom(GL_RGBA8, GL_RGBA, w, h, zeros);
  // The projection's lambda: .w is the data's cover (1: inside the data's edge).
  std::vector<float> covered(beta.size() * 4, 0.0f);
  for (std::size_t i = 0; i < beta.size(); ++i) covered[i * 4 + 3] = 1.0f;
  Texture tl = textureFrom(GL_RGBA8, GL_RGBA, w, h, covered);
  Texture td = Texture::create2D(GL_DEPTH_COMPONENT32F, w, h);
  glTextureSubImage2D(td.id(), 0, 0, 0, w, h, GL_DEPTH_COMPONENT, GL_FLOAT, depth.data());
  Texture out = Texture::create2D(GL_RGBA32F, w, h);
  Framebuffer fbo = createFramebuffer();
  attachTargets(fbo, {&out}, nullptr);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo.id());
  CompositePass pass;
  CompositeSettings cs;
  cs.mode = ColourMode::Engineering;
  cs.r = 0.3f;
  cs.contrast = 1.0f;
  cs.lightWeight = 0.4f;
  FrameView view;
  view.viewport = {w, h};
  view.internal = {w, h};
  view.target = {w, h};
  pass.run({&ta, &tb, &ts, &tz, &tl}, view, cs);
  auto c = readTexture(out, 4);
  int silhouettes = 0, ring = 0;
  for (std::size_t i = 0; i < beta.size(); ++i) {
    silhouettes += edges[i] > 0.0f;
    ring += blocked[i] && edges[i] == 0.0f;
    const double q1 = blocked[i] ? beta[i] : p[i * 2], q2 = blocked[i] ? beta[i] : p[i * 2 + 1];
    double p1 = std::max(q1, 1e-3), p2 = std::max(q2, 1e-3);
    double e = edges[i], l = 0.4 * light[i];
    double r = std::clamp(0.3 * p2 / (8 * p1 * p1) + e + l, 0.0, 1.0);
    double g = std::clamp(0.7 * p1 / (8 * p2 * p2) + e + l, 0.0, 1.0);
    double b = std::clamp(e + l, 0.0, 1.0);
    ASSERT_NEAR(c[i * 4], r, 1e-4) << i;
    ASSERT_NEAR(c[i * 4 + 1], g, 1e-4) << i;
    ASSERT_NEAR(c[i * 4 + 2], b, 1e-4) << i;
  }
  EXPECT_GT(silhouettes, 100);
  EXPECT_GT(ring, 5);
  }
}

// CompositeDepth::Present (the renderer's full-resolution frames): the composite's depth drawn alone by
// runDepth, copied into the framebuffer, then the composite behind the early depth test, gives the colour and
// the depth of the composite that computes and writes its depth, bit for bit: the same pixels drawn (off the
// surface and, without a background volume, outside the data's cover nothing) and the same depth values.
TEST_F(FabricPass, CompositeBehindItsPresentDepthEqualsTheCompositeWritingIt) {
  constexpr int w = 97, h = 61, guard = 3;
  const glm::ivec2 vp(w - 2 * guard, h - 2 * guard);
  auto beta = randomField(w, h, 1, 51), rnd = randomField(w, h, 4, 52), p = randomField(w, h, 2, 53);
  std::vector<unsigned char> mask(beta.size(), 1);
  std::vector<float> lambda(beta.size() * 4), eigen(beta.size() * 4), p1(beta.size()), p2(beta.size());
  for (std::size_t i = 0; i < beta.size(); ++i) {
    const int x = static_cast<int>(i % w), y = static_cast<int>(i / w);
    mask[i] = (x - 48) * (x - 48) + (y - 30) * (y - 30) < 27 * 27; // a disc of surface
    lambda[i * 4] = rnd[i * 4];
    lambda[i * 4 + 1] = rnd[i * 4 + 1];
    lambda[i * 4 + 2] = rnd[i * 4 + 2];
    lambda[i * 4 + 3] = std::clamp((x - 30) / 4.0f, 0.0f, 1.0f); // the data's edge: cover 0, a ramp, then 1
    for (int c = 0; c < 4; ++c) eigen[i * 4 + c] = rnd[(i * 4 + c + 1) % rnd.size()];
    p1[i] = i % 11 == 0 ? kBlocked : p[i * 2];
    p2[i] = i % 11 == 0 ? kBlocked : p[i * 2 + 1];
  }
  auto surface = surfaceData(beta, &mask);
  for (std::size_t i = 0; i < beta.size(); ++i)
    surface[i * 4 + 2] = 40.0f + 0.37f * static_cast<float>(i % w) + 0.21f * static_cast<float>(i / w);
  Texture ta = textureFrom(GL_R32F, GL_RED, w, h, p1), tb = textureFrom(GL_R32F, GL_RED, w, h, p2);
  ta.setFilter(GL_LINEAR, GL_LINEAR);
  tb.setFilter(GL_LINEAR, GL_LINEAR);
  Texture ts = textureFrom(GL_RGBA32F, GL_RGBA, w, h, surface);
  Texture te = textureFrom(GL_RGBA8, GL_RGBA, w, h, eigen), tl = textureFrom(GL_RGBA8, GL_RGBA, w, h, lambda);
  const glm::mat4 proj = glm::perspective(glm::radians(40.0f), float(vp.x) / float(vp.y), 10.0f, 400.0f);
  FrameView view;
  view.viewport = vp;
  view.internal = vp;
  view.guard = guard;
  view.target = {w, h};
  view.eyeDepth = {proj[2][2], proj[3][2], proj[2][3], proj[3][3]};
  auto target = [&](Texture& colour, Texture& depth) {
    colour = Texture::create2D(GL_RGBA32F, vp.x, vp.y);
    depth = Texture::create2D(GL_DEPTH_COMPONENT32F, vp.x, vp.y);
    Framebuffer fbo = createFramebuffer();
    attachTargets(fbo, {&colour}, &depth);
    const float clear[4] = {0.1f, 0.2f, 0.3f, 0.0f}, one = 1.0f;
    glClearNamedFramebufferfv(fbo.id(), GL_COLOR, 0, clear);
    glClearNamedFramebufferfv(fbo.id(), GL_DEPTH, 0, &one);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo.id());
    return fbo;
  };
  auto readDepth = [](const Texture& t) {
    std::vector<float> d(static_cast<std::size_t>(t.width()) * t.height());
    glGetTextureImage(t.id(), 0, GL_DEPTH_COMPONENT, GL_FLOAT, static_cast<GLsizei>(d.size() * 4), d.data());
    return d;
  };
  CompositePass pass;
  for (const bool background : {false, true})
    for (const ColourMode mode : {ColourMode::Medical, ColourMode::Engineering}) {
      SCOPED_TRACE(std::string(background ? "background " : "") +
                   (mode == ColourMode::Medical ? "medical" : "engineering"));
      CompositeSettings cs;
      cs.mode = mode;
      cs.background = background;
      Texture colourA, depthA, colourB, depthB, depthOnly, unused;
      {
        Framebuffer fbo = target(colourA, depthA);
        pass.run({&ta, &tb, &ts, &te, &tl}, view, cs);
      }
      {
        Framebuffer fbo = target(unused, depthOnly);
        pass.runDepth({nullptr, nullptr, &ts, nullptr, &tl}, view, background);
      }
      {
        Framebuffer fbo = target(colourB, depthB);
        glCopyImageSubData(depthOnly.id(), GL_TEXTURE_2D, 0, 0, 0, 0, depthB.id(), GL_TEXTURE_2D, 0, 0, 0, 0,
                           vp.x, vp.y, 1);
        cs.depth = CompositeDepth::Present;
        pass.run({&ta, &tb, &ts, &te, &tl}, view, cs);
      }
      const auto a = readTexture(colourA, 4), b = readTexture(colourB, 4);
      const auto da = readDepth(depthA), db = readDepth(depthB);
      ASSERT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(float)), 0);
      ASSERT_EQ(std::memcmp(da.data(), db.data(), da.size() * sizeof(float)), 0);
      const auto drawn = std::count_if(da.begin(), da.end(), [](float d) { return d < 1.0f; });
      EXPECT_GT(drawn, 1000);                            // the disc, at least where there is data
      EXPECT_LT(drawn, static_cast<long>(da.size()) - 500); // around the disc nothing
      if (!background) {
        const auto depthOf = [&](int x, int y) {
          return da[static_cast<std::size_t>(y - guard) * vp.x + x - guard];
        };
        EXPECT_EQ(depthOf(28, 30), 1.0f); // on the surface, outside the data's cover: discarded
        EXPECT_LT(depthOf(40, 30), 1.0f);
      }
    }
}

// CompositeSettings::overClear (the renderer's output, cleared just before): the data's edge laid over the
// known clear colour in the shader gives the blended composite's RGBA8 colour to within one level, the same
// colour wherever the data covers the pixel whole, and alpha 1, at full resolution (behind the present
// depth) and computing its depth, in the medical, anatomy and engineering looks.
TEST_F(FabricPass, CompositeOverTheClearColourEqualsBlendingOverIt) {
  constexpr int w = 97, h = 61, guard = 3;
  const glm::ivec2 vp(w - 2 * guard, h - 2 * guard);
  auto beta = randomField(w, h, 1, 61), rnd = randomField(w, h, 4, 62), p = randomField(w, h, 2, 63);
  std::vector<unsigned char> mask(beta.size(), 1);
  std::vector<float> lambda(beta.size() * 4), eigen(beta.size() * 4), p1(beta.size()), p2(beta.size());
  for (std::size_t i = 0; i < beta.size(); ++i) {
    const int x = static_cast<int>(i % w), y = static_cast<int>(i / w);
    mask[i] = (x - 48) * (x - 48) + (y - 30) * (y - 30) < 27 * 27; // a disc of surface
    for (int c = 0; c < 3; ++c) lambda[i * 4 + c] = rnd[i * 4 + c];
    lambda[i * 4 + 3] = std::clamp((x - 30) / 12.0f, 0.0f, 1.0f); // the data's edge: cover 0, a ramp, then 1
    for (int c = 0; c < 4; ++c) eigen[i * 4 + c] = rnd[(i * 4 + c + 1) % rnd.size()];
    p1[i] = i % 11 == 0 ? kBlocked : p[i * 2];
    p2[i] = i % 11 == 0 ? kBlocked : p[i * 2 + 1];
  }
  auto surface = surfaceData(beta, &mask);
  Texture ta = textureFrom(GL_R32F, GL_RED, w, h, p1), tb = textureFrom(GL_R32F, GL_RED, w, h, p2);
  Texture ts = textureFrom(GL_RGBA32F, GL_RGBA, w, h, surface);
  Texture te = textureFrom(GL_RGBA8, GL_RGBA, w, h, eigen), tl = textureFrom(GL_RGBA8, GL_RGBA, w, h, lambda);
  FrameView view;
  view.viewport = vp;
  view.internal = vp;
  view.guard = guard;
  view.target = {w, h};
  const glm::mat4 proj = glm::ortho(-50.0f, 50.0f, -30.0f, 30.0f, 1.0f, 400.0f);
  view.eyeDepth = {proj[2][2], proj[3][2], proj[2][3], proj[3][3]};
  const glm::vec3 clear(0.15f, 0.55f, 0.8f);
  CompositePass pass;
  // The composite into an RGBA8 target cleared to `clear` (alpha 1); present: runDepth's depth, drawn into
  // a depth-only framebuffer as the renderer does, copied there first.
  const float one = 1.0f;
  Texture presentDepth = Texture::create2D(GL_DEPTH_COMPONENT32F, vp.x, vp.y);
  {
    Framebuffer fbo = createFramebuffer();
    attachTargets(fbo, {}, &presentDepth);
    glClearNamedFramebufferfv(fbo.id(), GL_DEPTH, 0, &one);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo.id());
    pass.runDepth({nullptr, nullptr, &ts, nullptr, &tl}, view, false);
  }
  auto draw = [&](const CompositeSettings& cs) {
    Texture colour = Texture::create2D(GL_RGBA8, vp.x, vp.y);
    Texture depth = Texture::create2D(GL_DEPTH_COMPONENT32F, vp.x, vp.y);
    Framebuffer fbo = createFramebuffer();
    attachTargets(fbo, {&colour}, &depth);
    const float c[4] = {clear.x, clear.y, clear.z, 1.0f};
    glClearNamedFramebufferfv(fbo.id(), GL_COLOR, 0, c);
    glClearNamedFramebufferfv(fbo.id(), GL_DEPTH, 0, &one);
    if (cs.depth == CompositeDepth::Present)
      glCopyImageSubData(presentDepth.id(), GL_TEXTURE_2D, 0, 0, 0, 0, depth.id(), GL_TEXTURE_2D, 0, 0, 0, 0,
                         vp.x, vp.y, 1);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo.id());
    pass.run({&ta, &tb, &ts, &te, &tl}, view, cs);
    return readTexture(colour, 4);
  };
  for (const CompositeDepth depth : {CompositeDepth::Present, CompositeDepth::Computed})
    for (const int look : {0, 1, 2}) {
      SCOPED_TRACE(std::string(depth == CompositeDepth::Present ? "present " : "computed ") +
                   (look == 0 ? "medical" : look == 1 ? "anatomy" : "engineering"));
      CompositeSettings cs;
      cs.mode = look == 2 ? ColourMode::Engineering : ColourMode::Medical;
      cs.anatomy = look == 1;
      cs.depth = depth;
      const auto blended = draw(cs);
      cs.overClear = true;
      cs.clearColour = clear;
      const auto over = draw(cs);
      // The colour laid under the edge is the one given, not the framebuffer's (no blending left on).
      cs.clearColour = glm::vec3(1.0f) - clear;
      const auto otherClear = draw(cs);
      int edge = 0, mixed = 0, fromGiven = 0;
      for (std::size_t i = 0; i < over.size(); i += 4) {
        const int x = static_cast<int>(i / 4) % vp.x + guard, y = static_cast<int>(i / 4) / vp.x + guard;
        const float cover = lambda[(static_cast<std::size_t>(y) * w + x) * 4 + 3];
        const bool onSurface = mask[static_cast<std::size_t>(y) * w + x] != 0;
        ASSERT_EQ(over[i + 3], 1.0f) << x << "," << y;
        ASSERT_EQ(blended[i + 3], 1.0f) << x << "," << y;
        for (int c = 0; c < 3; ++c) {
          if (cover >= 1.0f || !onSurface || cover <= 0.0f)
            ASSERT_EQ(over[i + c], blended[i + c]) << x << "," << y << " channel " << c;
          else
            ASSERT_NEAR(over[i + c], blended[i + c], 1.01f / 255.0f) << x << "," << y << " channel " << c;
        }
        if (onSurface && cover > 0.0f && cover < 1.0f) {
          ++edge;
          // The ramp mixes: neither the clear colour nor the colour alone.
          const float fromClear =
              std::abs(over[i] - clear.x) + std::abs(over[i + 1] - clear.y) + std::abs(over[i + 2] - clear.z);
          mixed += fromClear > 4.0f / 255.0f;
          fromGiven += std::abs(otherClear[i + 1] - over[i + 1]) > 2.0f / 255.0f;
        }
      }
      EXPECT_GT(edge, 300);
      EXPECT_GT(mixed, edge / 2);
      EXPECT_GT(fromGiven, edge / 2);
    }
}

TEST_F(FabricPass, MedicalModeDrawsTheSecondaryDirectionInGreyBeneathThePrimary) {
  // Four pixels, principal direction x (red), FA 0.7, no light, no silhouettes:
  //   0: one dominant direction (lambda2'/lambda1' = 0.1), p1 low  -> still red (no secondary shown)
  //   1: secondary present (ratio 0.95), p1 high (primary thread)  -> red on top
  //   2: secondary present, p1 low, p2 high (secondary thread)     -> grey
  //   3: no tensor data                                            -> grey, no DEC colour
  const int n = 4;
  std::vector<float> adv = {0.1f, 0.9f, 0.95f, 0.5f, 0.05f, 0.95f, 0.5f, 0.5f};
  std::vector<float> surface(n * 4), eigen(n * 4), lambda(n * 4), depth(n, 0.5f);
  for (int i = 0; i < n; ++i) {
    surface[i * 4 + 0] = 0.5f, surface[i * 4 + 1] = 1.0f, surface[i * 4 + 2] = 100.0f, surface[i * 4 + 3] = 1.0f;
    eigen[i * 4 + 0] = 1.0f, eigen[i * 4 + 3] = 0.7f;
    lambda[i * 4 + 0] = i == 0 ? 0.1f : 0.95f, lambda[i * 4 + 3] = i == 3 ? 0.0f : 1.0f; // lambda2'/lambda1', data
  }
  std::vector<float> adv1(n), adv2(n);
  for (int i = 0; i < n; ++i) adv1[i] = adv[i * 2], adv2[i] = adv[i * 2 + 1];
  Texture ta = textureFrom(GL_R32F, GL_RED, n, 1, adv1), tb = textureFrom(GL_R32F, GL_RED, n, 1, adv2);
  Texture ts = textureFrom(GL_RGBA32F, GL_RGBA, n, 1, surface);
  Texture tg = textureFrom(GL_RGBA8, GL_RGBA, n, 1, eigen);
  Texture tl = textureFrom(GL_RGBA8, GL_RGBA, n, 1, lambda);
  Texture td = Texture::create2D(GL_DEPTH_COMPONENT32F, n, 1);
  glTextureSubImage2D(td.id(), 0, 0, 0, n, 1, GL_DEPTH_COMPONENT, GL_FLOAT, depth.data());
  Texture out = Texture::create2D(GL_RGBA32F, n, 1);
  Framebuffer fbo = createFramebuffer();
  attachTargets(fbo, {&out}, nullptr);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo.id());
  CompositePass pass;
  CompositeSettings cs;
  cs.mode = ColourMode::Medical;
  cs.lighting = false;
  cs.silhouettes = false;
  FrameView view;
  view.viewport = view.internal = view.target = {n, 1};
  pass.run({&ta, &tb, &ts, &tg, &tl}, view, cs);
  auto c = readTexture(out, 4);
  auto saturation = [&](int i) {
    float mx = std::max({c[i * 4], c[i * 4 + 1], c[i * 4 + 2]}), mn = std::min({c[i * 4], c[i * 4 + 1], c[i * 4 + 2]});
    return mx > 0 ? (mx - mn) / mx : 0.0f;
  };
  EXPECT_GT(c[0], 2 * c[1]);            // red hue even on a dark stretch of the only direction
  EXPECT_GT(saturation(0), 0.5f);
  EXPECT_GT(c[4], 2 * c[5]);            // primary thread drawn over the secondary
  EXPECT_GT(saturation(1), 0.5f);
  EXPECT_LT(saturation(2), 0.1f);       // the secondary thread is grey
  EXPECT_GT(c[8], 0.2f);                // and visible
  EXPECT_LT(saturation(3), 0.05f);      // no data: grey
}

TEST_F(FabricPass, CullingBackFacesOfAClosedSurfaceChangesNothingAndStopsWhenTheNearPlaneCuts) {
  Mesh sphere = reference::uvSphere({0, 0, 0}, 20.0, 24, 32);
  ASSERT_TRUE(sphere.isClosedOutward());
  Grid grid = reference::centredGrid(24, 2.0);
  TensorField field = reference::constantField(grid, glm::normalize(glm::dvec3(1, 0.3, 0.2)), 1.7e-3, 0.3e-3);
  GpuMesh mesh;
  mesh.upload(sphere);
  EXPECT_TRUE(mesh.closedOutward());
  GpuTensorField gpuField;
  gpuField.upload(field);
  Texture noise = flatNoise();

  // Outside: the same targets with and without culling.
  Camera cam = Camera::standard(StandardView::Anterior, {-20, -20, -20}, {20, 20, 20}, double(kW) / kH);
  FrameView view = FrameView::make(cam, {kW, kH}, 2, mesh.boundsLo(), mesh.boundsHi());
  ASSERT_TRUE(view.boundsInFront);
  std::vector<float> out[2][3];
  for (int cull = 0; cull < 2; ++cull) {
    ProjectionPass pass;
    ProjectionSettings ps;
    ps.cullHidden = cull == 1;
    pass.run(mesh, gpuField, noise, view, ps);
    out[cull][0] = readTexture(pass.surface(), 4);
    out[cull][1] = readVectors(pass.vectors());
    std::vector<std::uint32_t> g(static_cast<std::size_t>(kW + 4) * (kH + 4) * 2);
    glGetTextureImage(pass.geometry().id(), 0, GL_RG_INTEGER, GL_UNSIGNED_INT, static_cast<GLsizei>(g.size() * 4),
                      g.data());
    for (std::size_t i = 0; i < g.size() / 2; ++i) // normal and depth bits, compared exactly below
      out[cull][2].insert(out[cull][2].end(), {float(g[i * 2] & 0xffffu), float(g[i * 2] >> 16),
                                               float(g[i * 2 + 1] & 0xffffu), float(g[i * 2 + 1] >> 16)});
  }
  int covered = 0;
  for (std::size_t i = 0; i < out[0][0].size() / 4; ++i) {
    if (out[0][0][i * 4 + 3] < 0.5f) {
      EXPECT_EQ(out[1][0][i * 4 + 3], 0.0f);
      continue;
    }
    ++covered;
    for (int t = 0; t < 3; ++t)
      for (int c = 0; c < 4; ++c) ASSERT_EQ(out[0][t][i * 4 + c], out[1][t][i * 4 + c]) << "pixel " << i;
  }
  EXPECT_GT(covered, kW * kH / 4);

  // Inside (perspective eye at the centre): the near plane cuts the bounds, nothing is culled, and the
  // inner side of the sphere fills the view.
  Camera inside;
  inside.orthographic = false;
  inside.fovYDeg = 60;
  inside.nearPlane = 0.5;
  inside.lookAt({0, 0, 0}, {0, 1, 0}, {0, 0, 1});
  FrameView in = FrameView::make(inside, {kW, kH}, 2, mesh.boundsLo(), mesh.boundsHi());
  EXPECT_FALSE(in.boundsInFront);
  ProjectionPass pass;
  pass.run(mesh, gpuField, noise, in, {});
  auto surf = readTexture(pass.surface(), 4);
  for (std::size_t i = 0; i < surf.size() / 4; ++i) ASSERT_EQ(surf[i * 4 + 3], 1.0f) << "pixel " << i;
}
