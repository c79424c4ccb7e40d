// SPDX-License-Identifier: GPL-3.0-or-later
// The BIDS participant figures show the anatomy a DWI gives: its mean b=0 image beneath the fabric. On the
// real DWI the axial figure's grey pixels (isotropic tissue and the grid outside the data) follow the b=0
// image computed here independently from the DWI file, sampled at each pixel's world point.
#include "support/gl_test.h"
#include "support/test_env.h"

#include "io/bids/bids.h"
#include "io/diffusion/dwi.h"
#include "io/formats/tensor_io.h"
#include "io/formats/png_io.h"
#include "render/camera.h"
#include "ui/session/bids_participant.h"
#include "ui/session/surface_spec.h"
#include "ui/session/tensor_input.h"

#include <cmath>
#include <fstream>
#include <sstream>

using namespace dtf;

namespace {

class BidsFigure : public GlTest {};

double correlation(const std::vector<double>& a, const std::vector<double>& b) {
  double ma = 0, mb = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    ma += a[i];
    mb += b[i];
  }
  ma /= a.size();
  mb /= b.size();
  double sab = 0, saa = 0, sbb = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    sab += (a[i] - ma) * (b[i] - mb);
    saa += (a[i] - ma) * (a[i] - ma);
    sbb += (b[i] - mb) * (b[i] - mb);
  }
  return sab / std::sqrt(saa * sbb);
}

} // namespace

TEST_F(BidsFigure, TheAxialFigureShowsTheDwisMeanB0Beneath) {
  DTF_SHARED_FILE(dwi, "iu_prisma_dwi/dwi.nii.gz");
  const auto dir = test::scratchDir();
  io::BidsRun run;
  run.subject = "01";
  run.relDir = "sub-01/dwi";
  run.stem = "sub-01";
  run.dwi = dwi.string();
  run.bval = (dwi.parent_path() / "dwi.bval").string();
  run.bvec = (dwi.parent_path() / "dwi.bvec").string();
  session::ParticipantOptions o;
  o.figurePx = 256;
  o.version = "test";
  const session::RunOutcome out = session::processRun(run, dir.string(), o);
  ASSERT_TRUE(out.ok) << out.message;
  const Image img = io::readPng((dir / "sub-01/dwi/sub-01_desc-fabricAxial_dwi.png").string());

  // The mean b=0 image, independently: the volumes with b <= 50.
  const ScalarVolume signal = io::readScalarVolume(run.dwi);
  const std::vector<double> bvals = io::readBvals(run.bval);
  ScalarVolume b0(signal.grid, 1);
  int used = 0;
  for (int v = 0; v < signal.components; ++v) {
    if (bvals[static_cast<std::size_t>(v)] > 50) continue;
    ++used;
    for (std::size_t i = 0; i < b0.data.size(); ++i)
      b0.data[i] += signal.data[i * static_cast<std::size_t>(signal.components) + static_cast<std::size_t>(v)];
  }
  ASSERT_GT(used, 0);

  // The figure's slice and camera as the participant level chooses them (slice index in the metrics).
  std::ifstream metrics(dir / "sub-01/dwi/sub-01_desc-fabricMetrics_dwi.json");
  std::stringstream text;
  text << metrics.rdbuf();
  const std::string json = text.str();
  const auto at = json.find("\"slice_axial\": ");
  ASSERT_NE(at, std::string::npos);
  const int slice = std::stoi(json.substr(at + 15));
  session::SurfaceSpec spec;
  spec.kind = session::SurfaceSpec::Kind::Slice;
  spec.axis = "axial";
  spec.index = slice;
  session::SurfaceBuildOptions whole;
  whole.clipToData = false;
  whole.dataEdgeCells = true;
  const io::LoadedTensors t = session::loadTensorInput(run.dwi, {});
  const Mesh mesh = session::buildSurface(spec, t.field, computeFaMap(t.field), whole);
  glm::vec3 lo, hi;
  mesh.bounds(lo, hi);
  const render::Camera cam = render::Camera::standard(render::StandardView::Axial, glm::dvec3(lo), glm::dvec3(hi),
                                                      1.0, false, true);
  const glm::dvec3 right = cam.right(), up = glm::normalize(glm::cross(right, cam.forward()));
  const double mm = 2.0 * cam.orthoHalfHeight / img.height;

  // Unsaturated pixels away from the figure's furniture (letters, legend, scale bar at the edges).
  std::vector<double> figureGrey, b0Grey;
  for (int y = img.height / 8; y < img.height * 7 / 8; ++y)
    for (int x = img.width / 8; x < img.width * 7 / 8; ++x) {
      const auto* c = img.pixel(x, y);
      if (std::max({c[0], c[1], c[2]}) - std::min({c[0], c[1], c[2]}) > 3) continue;
      const glm::dvec3 w =
          cam.target + right * ((x + 0.5 - 0.5 * img.width) * mm) - up * ((y + 0.5 - 0.5 * img.height) * mm);
      glm::dvec3 ijk = b0.grid.toVoxel(w);
      const glm::ivec3 v(std::lround(ijk.x), std::lround(ijk.y), slice);
      if (glm::any(glm::lessThan(v, glm::ivec3(0))) || glm::any(glm::greaterThanEqual(v, b0.grid.dims))) continue;
      figureGrey.push_back(c[0]);
      b0Grey.push_back(b0.data[b0.grid.index(v.x, v.y, v.z)]);
    }
  // Grey covers much of the slice: CSF, grey matter and the grid around the brain.
  ASSERT_GT(figureGrey.size(), std::size_t(256 * 256 / 8)) << "too few grey pixels";
  const double r = correlation(figureGrey, b0Grey);
  std::printf("grey pixels %zu, correlation with the mean b=0 image %.3f\n", figureGrey.size(), r);
  EXPECT_GT(r, 0.85);
}
