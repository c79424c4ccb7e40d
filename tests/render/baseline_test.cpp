// SPDX-License-Identifier: GPL-3.0-or-later
// Baseline images (256x256, llvmpipe) of the whole fabric: the paper's analytic data sets (Fig. 6: sphere
// and Bretzel5 Hessian fields on their isosurfaces) and the real brain (axial slice, FA 0.25 isosurface) in
// both colour modes. Compared with a per-channel tolerance, a bad-pixel fraction and a mean difference;
// on failure actual/expected/diff PNGs are written to the build directory. Regenerate on purpose only:
// DTF_UPDATE_BASELINES=1, then look at every image before committing it.
#include "support/baseline.h"
#include "support/gl_test.h"

#include "io/formats/png_io.h"
#include "io/formats/tensor_io.h"
#include "render/fabric_renderer.h"
#include "render/reference/scenes.h"
#include "surfaces/isosurface.h"
#include "surfaces/slices.h"

#include <filesystem>

using namespace dtf;
using namespace dtf::render;
namespace fs = std::filesystem;

namespace {

class Baseline : public GlTest {};

constexpr int kSize = 256;

// Fraction of non-black pixels: guards against committing an empty baseline.
double coverage(const Image& img) {
  std::size_t lit = 0;
  for (std::size_t i = 0; i < img.rgba.size(); i += 4) lit += (img.rgba[i] | img.rgba[i + 1] | img.rgba[i + 2]) != 0;
  return double(lit) / (double(img.width) * img.height);
}

Image renderFabric(const Mesh& mesh, const TensorField& field, const Camera& cam, const FabricParams& p) {
  FabricRenderer r;
  r.setMesh(mesh);
  r.setField(field);
  r.resize(kSize, kSize);
  return r.renderStill(cam, p);
}

struct Analytic {
  Mesh mesh;
  TensorField field;
  glm::vec3 lo, hi;
};

// The Hessian of `field` on the zero level of `surface`.
Analytic analytic(const std::function<double(const glm::dvec3&)>& field,
                  const std::function<double(const glm::dvec3&)>& surface, double extent, int n) {
  Analytic a;
  Grid grid = reference::centredGrid(n, 2 * extent / (n - 1));
  a.field = reference::hessianField(grid, field, 0.25 * grid.spacing.x);
  a.mesh = reference::marchingTetrahedra(reference::sampleFunction(grid, surface), 0.0);
  a.mesh.bounds(a.lo, a.hi);
  return a;
}

} // namespace

TEST_F(Baseline, SphereHessianOnItsIsosurface) {
  const double r = 40;
  // The true sphere |x| = r carrying the anisotropic Hessian of |x|^2 + c xyz (the Hessian of |x| alone is
  // isotropic in every tangent plane: no direction to show).
  Analytic a = analytic([r](const glm::dvec3& p) { return reference::sphereFunction(p, r); },
                        [r](const glm::dvec3& p) { return glm::dot(p, p) - r * r; }, 48, 49);
  ASSERT_GT(a.mesh.triangleCount(), 1000u);
  Camera cam = Camera::standard(StandardView::Anterior, a.lo, a.hi, 1.0);
  cam.trackball({0, 0}, {0.25, 0.3});
  FabricParams p;
  p.colour = ColourMode::Engineering;
  Image img = renderFabric(a.mesh, a.field, cam, p);
  EXPECT_GT(coverage(img), 0.4);
  test::compareToBaseline("sphere_engineering", img);
}

TEST_F(Baseline, Bretzel5HessianOnItsIsosurface) {
  const double s = 20; // mm per unit of Eq. 14
  auto f = [s](const glm::dvec3& p) { return reference::bretzel5Function(p, s); };
  Analytic a = analytic(f, f, 2.3 * s, 81);
  ASSERT_GT(a.mesh.triangleCount(), 1000u);
  Camera cam = Camera::standard(StandardView::Superior, a.lo, a.hi, 1.0);
  cam.trackball({0, 0}, {0.0, -0.45});
  cam.fit(a.lo, a.hi, 1.0);
  for (ColourMode mode : {ColourMode::Engineering, ColourMode::Medical}) {
    FabricParams p;
    p.colour = mode;
    p.look = Look::Plain; // the paper's look
    Image img = renderFabric(a.mesh, a.field, cam, p);
    EXPECT_GT(coverage(img), 0.2);
    test::compareToBaseline(mode == ColourMode::Engineering ? "bretzel5_engineering" : "bretzel5_medical", img);
  }
}

namespace {
struct Brain {
  TensorField field;
  ScalarVolume fa;
};
Brain loadBrain(const fs::path& path) {
  Brain b;
  b.field = io::readTensorVolume(path.string()).field;
  b.fa = computeFaMap(b.field);
  return b;
}
} // namespace

TEST_F(Baseline, RealBrainAxialSlice) {
  DTF_SHARED_FILE(path, "iu_prisma_dwi/derived/dti_tensor.nii.gz");
  Brain b = loadBrain(path);
  ScalarVolume valid(b.field.grid, 1);
  for (std::size_t i = 0; i < valid.data.size(); ++i) valid.data[i] = b.field.valid[i] ? 1.0f : 0.0f;
  surfaces::SliceOptions so;
  so.clip = &valid;
  // Slice k = 19 of 39 (the middle): genu and splenium of the corpus callosum, internal capsules.
  const int k = b.field.grid.dims.z / 2;
  Mesh slice = surfaces::makeSlice(b.field.grid, surfaces::SliceAxis::Axial, k, so);
  glm::vec3 lo, hi;
  slice.bounds(lo, hi);
  Camera cam = Camera::standard(StandardView::Axial, lo, hi, 1.0);
  for (ColourMode mode : {ColourMode::Medical, ColourMode::Engineering}) {
    FabricParams p;
    p.colour = mode;
    p.look = Look::Plain; // the paper's look
    Image img = renderFabric(slice, b.field, cam, p);
    EXPECT_GT(coverage(img), 0.4);
    if (mode == ColourMode::Medical) {
      // Genu of the corpus callosum (world about (0, 20, z)): red, with left-right threads. Radiological
      // axial view: image x = -world x, image up = anterior.
      glm::dvec3 genu = b.field.grid.toWorld(glm::dvec3(35, 49, k));
      glm::dvec4 clip = glm::dmat4(cam.projection(1.0)) * cam.view() * glm::dvec4(genu, 1.0);
      int gx = static_cast<int>((clip.x / clip.w * 0.5 + 0.5) * kSize), gy = static_cast<int>((0.5 - clip.y / clip.w * 0.5) * kSize);
      double r = 0, g = 0, bl = 0;
      for (int y = gy - 4; y <= gy + 4; ++y)
        for (int x = gx - 4; x <= gx + 4; ++x) {
          r += img.pixel(x, y)[0];
          g += img.pixel(x, y)[1];
          bl += img.pixel(x, y)[2];
        }
      EXPECT_GT(r, 1.5 * g) << "genu at pixel " << gx << "," << gy;
      EXPECT_GT(r, 1.5 * bl);
    }
    test::compareToBaseline(mode == ColourMode::Medical ? "brain_axial_medical" : "brain_axial_engineering", img);
  }
}

TEST_F(Baseline, RealBrainFaIsosurface) {
  DTF_SHARED_FILE(path, "iu_prisma_dwi/derived/dti_tensor.nii.gz");
  Brain b = loadBrain(path);
  surfaces::IsosurfaceOptions io;
  io.smoothSigmaVoxels = 0.6;
  io.minComponentFraction = 0.02;
  Mesh mesh = surfaces::extractIsosurface(b.fa, 0.25, io);
  ASSERT_GT(mesh.triangleCount(), 1000u);
  glm::vec3 lo, hi;
  mesh.bounds(lo, hi);
  Camera cam = Camera::standard(StandardView::Superior, lo, hi, 1.0);
  for (ColourMode mode : {ColourMode::Medical, ColourMode::Engineering}) {
    FabricParams p;
    p.colour = mode;
    p.look = Look::Plain; // the paper's look
    Image img = renderFabric(mesh, b.field, cam, p);
    EXPECT_GT(coverage(img), 0.25);
    test::compareToBaseline(mode == ColourMode::Medical ? "brain_fa025_medical" : "brain_fa025_engineering", img);
  }
}
