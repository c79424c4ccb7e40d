// SPDX-License-Identifier: GPL-3.0-or-later
// The data's outline on a real slice follows a smooth sub-voxel contour, not the voxel lattice. Measure: the
// outline is the set of pixel edges between covered and uncovered pixels (coverage > 1/2); a staircase of
// 3 mm voxels makes long straight horizontal and vertical runs of such edges, one per voxel face, while a
// smooth curve breaks into short runs wherever it is not nearly axis-aligned. The figure is the fraction of
// outline edges that lie in straight runs longer than 0.8 voxel (in pixels).
#include "support/gl_test.h"
#include "support/test_env.h"

#include "ui/session/fibre_input.h"
#include "ui/session/surface_spec.h"
#include "ui/session/tensor_input.h"
#include "io/model/tensor_field.h"
#include "render/fabric_renderer.h"

#include <cmath>
#include <cstdio>

using namespace dtf;

namespace {

class SmoothEdge : public GlTest {};

// Covered: the mesh covers the pixel (projection surface .a) and the data's cover there (lambda .a, the
// anti-aliased edge ramp) is above a half. Guarded targets, GL rows.
std::vector<std::uint8_t> coverage(const render::FabricRenderer& r, int& w, int& h) {
  const auto surface = test::readTexture(r.projection().surface(), 4);
  const auto lambda = test::readTexture(r.projection().lambda(), 4);
  w = r.projection().surface().width();
  h = r.projection().surface().height();
  std::vector<std::uint8_t> c(static_cast<std::size_t>(w) * h);
  for (std::size_t i = 0; i < c.size(); ++i)
    c[i] = surface[i * 4 + 3] > 0.5f && lambda[i * 4 + 3] > 0.5f;
  return c;
}

struct Outline {
  long edges = 0, inLongRuns = 0;
  double fraction() const { return edges ? double(inLongRuns) / double(edges) : 0.0; }
};

// Horizontal outline edges between rows y and y+1 and vertical ones between columns x and x+1, grouped into
// maximal straight runs of the same kind (same side covered).
Outline outline(const std::vector<std::uint8_t>& c, int w, int h, int minRun) {
  Outline o;
  auto at = [&](int x, int y) { return c[static_cast<std::size_t>(y) * w + x]; };
  auto count = [&](int len) {
    o.edges += len;
    if (len > minRun) o.inLongRuns += len;
  };
  for (int y = 0; y + 1 < h; ++y) {
    int run = 0, kind = 0;
    for (int x = 0; x < w; ++x) {
      const int k = at(x, y) == at(x, y + 1) ? 0 : (at(x, y) ? 1 : 2);
      if (k != kind) {
        if (kind) count(run);
        run = 0;
        kind = k;
      }
      if (k) ++run;
    }
    if (kind) count(run);
  }
  for (int x = 0; x + 1 < w; ++x) {
    int run = 0, kind = 0;
    for (int y = 0; y < h; ++y) {
      const int k = at(x, y) == at(x + 1, y) ? 0 : (at(x, y) ? 1 : 2);
      if (k != kind) {
        if (kind) count(run);
        run = 0;
        kind = k;
      }
      if (k) ++run;
    }
    if (kind) count(run);
  }
  return o;
}

} // namespace

TEST_F(SmoothEdge, TheOutlineOfARealSliceNoLongerFollowsTheVoxelAxes) {
  DTF_SHARED_FILE(tensor, "iu_prisma_dwi/derived/dti_tensor.nii.gz");
  session::TensorInputOptions in;
  in.quiet = true;
  const io::LoadedTensors loaded = session::loadTensorInput(tensor.string(), in);
  const ScalarVolume fa = computeFaMap(loaded.field);
  const session::SurfaceSpec spec = session::parseSurfaceSpec("slice=axial:20");
  session::SurfaceBuildOptions lattice, smooth;
  smooth.dataEdgeCells = true;
  const Mesh before = session::buildSurface(spec, loaded.field, fa, lattice);
  const Mesh after = session::buildSurface(spec, loaded.field, fa, smooth);

  constexpr int kSize = 768;
  render::FabricRenderer r;
  r.resize(kSize, kSize);
  r.setField(loaded.field);
  glm::vec3 lo, hi;
  before.bounds(lo, hi);
  const render::Camera cam = render::Camera::standard(render::StandardView::Inferior, glm::dvec3(lo),
                                                      glm::dvec3(hi), 1.0);
  render::FabricParams p;
  p.look = render::Look::Plain; // the outline of the data itself
  p.silhouette = false;
  p.stillMaxIterations = 10;
  r.setMesh(before);
  r.renderStill(cam, p);
  int w = 0, h = 0;
  const auto a = coverage(r, w, h);
  r.setMesh(after);
  r.renderStill(cam, p);
  const auto b = coverage(r, w, h);

  // One 3 mm voxel in pixels.
  const double voxelPx = 3.0 / r.frameView().pixelMm;
  ASSERT_GT(voxelPx, 6.0);
  const int minRun = static_cast<int>(0.8 * voxelPx);
  const Outline o1 = outline(a, w, h, minRun);
  const Outline o2 = outline(b, w, h, minRun);
  ASSERT_GT(o1.edges, 1000);
  ASSERT_GT(o2.edges, 1000);
  std::printf("outline edges in axis-aligned runs > %d px: voxel lattice %.3f (%ld edges), smooth %.3f (%ld "
              "edges)\n",
              minRun, o1.fraction(), o1.edges, o2.fraction(), o2.edges);
  EXPECT_GT(o1.fraction(), 0.8); // the staircase: almost the whole outline
  EXPECT_LT(o2.fraction(), 0.35);
  EXPECT_LT(o2.fraction(), 0.4 * o1.fraction());

  // Anti-aliased: the projection's data cover (lambda.w) ramps from 0 to 1 over about a pixel along the
  // outline, so partially covered pixels number about one per outline edge, not a band and not none.
  const auto surface = test::readTexture(r.projection().surface(), 4);
  const auto lambda = test::readTexture(r.projection().lambda(), 4);
  long partial = 0;
  for (std::size_t i = 0; i < lambda.size() / 4; ++i)
    if (surface[i * 4 + 3] > 0.5f && lambda[i * 4 + 3] > 0.02f && lambda[i * 4 + 3] < 0.98f) ++partial;
  std::printf("partially covered pixels %ld, outline edges %ld\n", partial, o2.edges);
  EXPECT_GT(partial, o2.edges / 3);
  EXPECT_LT(partial, 2 * o2.edges);
}

TEST_F(SmoothEdge, AFibreSetsOutlineIsSmoothAndAntiAliasedToo) {
  DTF_SHARED_FILE(peaks, "iu_prisma_dwi/derived/fibres/peaks_mrtrix.nii.gz");
  const session::FibreInput in = session::loadFibreInput(peaks.string(), "auto", "", true);
  const session::SurfaceSpec spec = session::parseSurfaceSpec("slice=axial:20");
  session::SurfaceBuildOptions smooth;
  smooth.dataEdgeCells = true;
  const Mesh mesh = session::buildSurface(spec, in.carrier, ScalarVolume(in.carrier.grid, 1), smooth);

  constexpr int kSize = 768;
  render::FabricRenderer r;
  r.resize(kSize, kSize);
  r.setField(in.carrier);
  r.setFibres(in.fibres.set);
  r.setMesh(mesh);
  glm::vec3 lo, hi;
  mesh.bounds(lo, hi);
  const render::Camera cam = render::Camera::standard(render::StandardView::Inferior, glm::dvec3(lo),
                                                      glm::dvec3(hi), 1.0);
  render::FabricParams p;
  p.look = render::Look::Plain;
  p.colour = render::ColourMode::Fibres;
  p.silhouette = false;
  p.stillMaxIterations = 10;
  r.renderStill(cam, p);
  int w = 0, h = 0;
  const auto c = coverage(r, w, h);
  const double voxelPx = 3.0 / r.frameView().pixelMm;
  const Outline o = outline(c, w, h, static_cast<int>(0.8 * voxelPx));
  const auto surface = test::readTexture(r.projection().surface(), 4);
  const auto lambda = test::readTexture(r.projection().lambda(), 4);
  long partial = 0;
  for (std::size_t i = 0; i < lambda.size() / 4; ++i)
    if (surface[i * 4 + 3] > 0.5f && lambda[i * 4 + 3] > 0.02f && lambda[i * 4 + 3] < 0.98f) ++partial;
  std::printf("fibre set: outline edges in axis-aligned runs %.3f (%ld edges), partially covered pixels %ld\n",
              o.fraction(), o.edges, partial);
  ASSERT_GT(o.edges, 1000);
  EXPECT_LT(o.fraction(), 0.35);
  EXPECT_GT(partial, o.edges / 3); // a ramp about a pixel wide, not a 0/1 cover
  EXPECT_LT(partial, 2 * o.edges);
}
