// SPDX-License-Identifier: GPL-3.0-or-later
// Fibre sets from other tools' native files (../shared/data): a DSI Studio FIB (three GQI populations, its
// dti_fa paired) and an FSL dtifit set with V1 and FA but no eigenvalues (one population), both detected by
// readFibres(Auto), rendered on an axial slice through the corpus callosum: the callosum is red with threads
// running left-right, checked at voxels found in each file (dti_fa/FA > 0.45 with a left-right first fibre
// on the midline) and against 256x256 baselines.
#include "io/formats/fibre_io.h"
#include "render/fabric_renderer.h"
#include "support/baseline.h"
#include "support/gl_test.h"
#include "surfaces/slices.h"

using namespace dtf;
using namespace dtf::render;

namespace {

class FibreTools : public GlTest {};

constexpr int kSize = 256;

Image renderAxial(const io::LoadedFibres& f, int k, Camera* camera) {
  const TensorField carrier = fibreCarrierField(f.set);
  ScalarVolume valid(carrier.grid, 1);
  for (std::size_t i = 0; i < valid.data.size(); ++i)
    valid.data[i] = carrier.valid[i] ? 1.0f : 0.0f;
  surfaces::SliceOptions so;
  so.clip = &valid;
  const Mesh mesh = surfaces::makeSlice(f.set.grid, surfaces::SliceAxis::Axial, k, so);
  glm::vec3 lo, hi;
  mesh.bounds(lo, hi);
  *camera = Camera::standard(StandardView::Axial, lo, hi, 1.0);
  FabricRenderer r;
  r.setMesh(mesh);
  r.setFibres(f.set, f.fa.data.empty() ? nullptr : &f.fa);
  r.resize(kSize, kSize);
  FabricParams p;
  p.colour = ColourMode::Fibres;
  p.look = Look::Plain; // the paper's look: the fibres' fabric in every tissue
  return r.renderStill(*camera, p);
}

glm::ivec2 pixelOf(const Camera& cam, const glm::dvec3& world) {
  glm::dvec4 clip = glm::dmat4(cam.projection(1.0)) * cam.view() * glm::dvec4(world, 1.0);
  return {static_cast<int>((clip.x / clip.w * 0.5 + 0.5) * kSize),
          static_cast<int>((0.5 - clip.y / clip.w * 0.5) * kSize)};
}

// The corpus callosum at `ijk` (a voxel on the midline whose first fibre runs left-right): red, and the
// threads in a window around it horizontal (image x is left-right in the axial view).
void expectRedLeftRight(const Image& img, const Camera& cam, const Grid& g, const glm::dvec3& ijk, int half) {
  const glm::ivec2 c = pixelOf(cam, g.toWorld(ijk));
  glm::dvec3 sum(0.0);
  int n = 0;
  for (int y = c.y - half; y <= c.y + half; ++y)
    for (int x = c.x - half; x <= c.x + half; ++x) {
      const auto* p = img.pixel(x, y);
      sum += glm::dvec3(p[0], p[1], p[2]);
      ++n;
    }
  const glm::dvec3 m = sum / double(n);
  EXPECT_GT(m.x, 1.5 * m.y) << "CC at pixel " << c.x << "," << c.y << ": " << m.x << " " << m.y << " " << m.z;
  EXPECT_GT(m.x, 1.5 * m.z) << "CC at pixel " << c.x << "," << c.y;
  EXPECT_GT(m.x, 60.0) << "CC at pixel " << c.x << "," << c.y << " is dark";
  double coherence = 0;
  const double o =
      test::dominantOrientation(img, c.x - half, c.y - half, c.x + half + 1, c.y + half + 1, &coherence);
  EXPECT_LT(test::orientationDiff(o, 0.0), 25.0) << "threads at " << o << " degrees, coherence " << coherence;
  EXPECT_GT(coherence, 0.2);
  std::printf("CC at pixel %d,%d: mean RGB %.0f %.0f %.0f, threads %.1f deg (coherence %.2f)\n", c.x, c.y,
              m.x, m.y, m.z, o, coherence);
}

// The first midline voxel (|i - nx/2| < 2) of slice k whose FA exceeds 0.45 and whose first fibre is
// within 25 degrees of the world x axis, nearest the slice's centre in j.
glm::dvec3 midlineCallosum(const io::LoadedFibres& f, int k) {
  const Grid& g = f.set.grid;
  glm::dvec3 best(-1);
  double bestDist = 1e9;
  for (int j = 0; j < g.dims.y; ++j)
    for (int i = g.dims.x / 2 - 1; i <= g.dims.x / 2 + 1; ++i) {
      const Fibre* fb = f.set.at(i, j, k);
      if (!(fb[0].amplitude > 0) || f.fa.data[g.index(i, j, k)] < 0.45f) continue;
      if (std::abs(fb[0].direction.x) < std::cos(25 * M_PI / 180)) continue;
      const double d = std::abs(j - g.dims.y / 2.0);
      if (d < bestDist) bestDist = d, best = glm::dvec3(i, j, k);
    }
  return best;
}

} // namespace

TEST_F(FibreTools, DsiStudioFibAxialSliceShowsTheCallosumRedLeftRight) {
  DTF_SHARED_FILE(fib, "niivue_other_tools/dsistudio.fib.gz");
  std::string why;
  ASSERT_TRUE(io::looksLikeFibres(fib.string(), &why)) << why;
  const io::LoadedFibres f = io::readFibres(fib.string());
  EXPECT_EQ(f.layout, io::FibreLayout::DsiStudio);
  ASSERT_EQ(f.set.maxFibres, 3);
  ASSERT_EQ(f.fa.grid.dims, f.set.grid.dims) << "dti_fa paired";
  EXPECT_EQ(f.set.grid.orientationCode(), "LPS");
  // Axial slice 17 (k grows superior): the body of the callosum.
  const glm::dvec3 cc = midlineCallosum(f, 17);
  ASSERT_GE(cc.x, 0) << "no left-right midline voxel with FA > 0.45 in slice 17";
  Camera cam;
  const Image img = renderAxial(f, 17, &cam);
  expectRedLeftRight(img, cam, f.set.grid, cc, 6);
  test::compareToBaseline("dsistudio_axial17_fibres", img);
}

TEST_F(FibreTools, DtifitV1SetAxialSliceShowsTheCallosumRedLeftRight) {
  DTF_SHARED_FILE(v1, "niivue_fsl_dtifit/V1.nii.gz");
  std::string why;
  ASSERT_TRUE(io::looksLikeFibres(v1.string(), &why)) << why;
  const io::LoadedFibres f = io::readFibres(v1.string());
  EXPECT_EQ(f.layout, io::FibreLayout::DtifitV1);
  ASSERT_EQ(f.set.maxFibres, 1);
  EXPECT_FLOAT_EQ(f.set.maxAmplitude(), 1.0f);
  ASSERT_EQ(f.fa.grid.dims, f.set.grid.dims) << "FA.nii.gz paired";
  ASSERT_EQ(f.files.size(), 2u);
  for (const char* s : {"found V1", "FA", "no L1-L3"})
    EXPECT_NE(f.layoutReason.find(s), std::string::npos) << s << " missing from: " << f.layoutReason;
  // Axial slice 28: genu, body and splenium of the callosum.
  const glm::dvec3 cc = midlineCallosum(f, 28);
  ASSERT_GE(cc.x, 0) << "no left-right midline voxel with FA > 0.45 in slice 28";
  Camera cam;
  const Image img = renderAxial(f, 28, &cam);
  expectRedLeftRight(img, cam, f.set.grid, cc, 6);
  test::compareToBaseline("dtifit_v1_axial28_fibres", img);
}
