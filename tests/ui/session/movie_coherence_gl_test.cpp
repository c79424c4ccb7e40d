// SPDX-License-Identifier: GPL-3.0-or-later
// Movie frames stay coherent: with the advection state carried from frame to frame (reprojected into the new
// view), consecutive turntable frames a quarter degree apart differ far less than frames re-seeded per frame,
// and each carried frame stays close to the converged still of its view, unlike frames restarted from the
// noise with as many iterations. Also the turntable's cameras and the sweep's slice range.
#include "support/gl_test.h"

#include "io/formats/fibre_io.h"
#include "io/phantoms.h"
#include "support/test_env.h"
#include "ui/session/movie_job.h"

#include <cmath>
#include <cstdio>

namespace fs = std::filesystem;

namespace {

const fs::path kPhantom = dtf::test::sourceDir() / "sample_data" / "brain_phantom.nii.gz";

// Mean absolute RGB difference (0..255) over the pixels where either image is not the background.
double meanAbsDiff(const dtf::Image& a, const dtf::Image& b) {
  double sum = 0;
  std::size_t n = 0;
  for (std::size_t p = 0; p < a.rgba.size(); p += 4) {
    const bool lit = (a.rgba[p] | a.rgba[p + 1] | a.rgba[p + 2] | b.rgba[p] | b.rgba[p + 1] | b.rgba[p + 2]) != 0;
    if (!lit) continue;
    for (int c = 0; c < 3; ++c) sum += std::abs(int(a.rgba[p + c]) - int(b.rgba[p + c]));
    n += 3;
  }
  return n ? sum / double(n) : 0;
}

dtf::session::RenderRequest phantomRequest(int size) {
  dtf::session::RenderRequest r;
  r.input = kPhantom.string();
  r.surface = dtf::session::parseSurfaceSpec("fa=0.25");
  r.width = r.height = size;
  return r;
}

} // namespace

TEST(MovieCoherence, CarriedTurntableFramesDifferLessThanReseededOnes) {
  DTF_GL_TEST_SETUP();
  dtf::session::FrameSession session(phantomRequest(160));
  glm::vec3 lo, hi;
  session.surface().bounds(lo, hi);
  const int steps = 1440, used = 8; // a quarter of a degree per frame: the image moves by well under a pixel
  const auto cams = dtf::session::turntableCameras(dtf::render::StandardView::Anterior, glm::dvec3(lo), glm::dvec3(hi),
                                               1.0, steps, 20, false, true);
  const dtf::render::FabricParams base = session.params();
  std::vector<dtf::Image> carried, stills, restarted, reseeded;
  for (int i = 0; i < used; ++i) carried.push_back(session.frame(cams[std::size_t(i)], i == 0));
  for (int i = 0; i < used; ++i) stills.push_back(session.frame(cams[std::size_t(i)], true));
  // What a frame is without the carried state: the noise advected by this frame's iterations only.
  session.params().stillMaxIterations = base.iterations;
  for (int i = 0; i < used; ++i) restarted.push_back(session.frame(cams[std::size_t(i)], true));
  session.params() = base;
  for (int i = 0; i < used; ++i) {
    session.params().seed = base.seed + 1 + i;
    reseeded.push_back(session.frame(cams[std::size_t(i)], true));
  }
  double mCarried = 0, mStill = 0, mReseeded = 0, mToStill = 0, mRestartedToStill = 0;
  for (int i = 1; i < used; ++i) {
    const auto k = std::size_t(i);
    mCarried += meanAbsDiff(carried[k - 1], carried[k]) / (used - 1);
    mStill += meanAbsDiff(stills[k - 1], stills[k]) / (used - 1);
    mReseeded += meanAbsDiff(reseeded[k - 1], reseeded[k]) / (used - 1);
    mToStill += meanAbsDiff(carried[k], stills[k]) / (used - 1);
    mRestartedToStill += meanAbsDiff(restarted[k], stills[k]) / (used - 1);
  }
  std::printf("consecutive turntable frames 0.25 deg apart, mean |dRGB| (0..255): carried %.2f, converged stills "
              "%.2f, re-seeded stills %.2f; to the converged still of the same view: carried %.2f, restarted from "
              "the noise with %d iterations %.2f\n",
              mCarried, mStill, mReseeded, mToStill, base.iterations, mRestartedToStill);
  EXPECT_GT(mReseeded, 0.0);
  EXPECT_LT(mCarried, 0.5 * mReseeded);
  // Carrying the state keeps each frame nearer to what a converged still of its view shows than restarting
  // every frame with the same few iterations (measured: about 3.0 against 4.7).
  EXPECT_LT(mToStill, 0.8 * mRestartedToStill);
  EXPECT_LT(mToStill, 0.5 * mReseeded);
}

TEST(MovieCoherence, FaSweepFramesStayCoherent) {
  DTF_GL_TEST_SETUP();
  dtf::session::FrameSession session(phantomRequest(128));
  glm::dvec3 lo, hi;
  session.field().grid.worldBounds(lo, hi);
  const auto camera = dtf::render::Camera::standard(dtf::render::StandardView::Superior, lo, hi, 1.0);
  const int used = 6;
  const int seed = session.params().seed;
  std::vector<dtf::Image> carried, reseeded;
  std::vector<dtf::Mesh> meshes;
  for (int i = 0; i < used; ++i) meshes.push_back(session.build(dtf::session::parseSurfaceSpec("fa=" + std::to_string(0.25 + 0.005 * i))));
  for (int i = 0; i < used; ++i) {
    session.setMesh(meshes[std::size_t(i)]);
    carried.push_back(session.frame(camera, i == 0));
  }
  for (int i = 0; i < used; ++i) {
    session.params().seed = seed + 1 + i;
    session.setMesh(meshes[std::size_t(i)]);
    reseeded.push_back(session.frame(camera, true));
  }
  double mCarried = 0, mReseeded = 0;
  for (int i = 1; i < used; ++i) {
    mCarried += meanAbsDiff(carried[std::size_t(i - 1)], carried[std::size_t(i)]) / (used - 1);
    mReseeded += meanAbsDiff(reseeded[std::size_t(i - 1)], reseeded[std::size_t(i)]) / (used - 1);
  }
  std::printf("FA sweep, consecutive frames 0.005 apart, mean |dRGB|: carried %.2f, re-seeded %.2f\n", mCarried,
              mReseeded);
  EXPECT_LT(mCarried, 0.5 * mReseeded);
}

TEST(MovieCameras, TurntableTurnsAboutTheSuperiorAxis) {
  const glm::dvec3 lo(-50, -60, -40), hi(50, 60, 40);
  const int n = 12;
  const auto cams = dtf::session::turntableCameras(dtf::render::StandardView::Anterior, lo, hi, 1.0, n, 20, false, true);
  ASSERT_EQ(cams.size(), std::size_t(n));
  const double radius = 0.5 * glm::length(hi - lo);
  for (int i = 0; i < n; ++i) {
    const auto& c = cams[std::size_t(i)];
    EXPECT_NEAR(glm::length(c.target), 0.0, 1e-9);
    const glm::dvec3 d = glm::normalize(c.eye - c.target);
    EXPECT_NEAR(std::asin(d.z) * 180 / M_PI, 20.0, 1e-6) << i; // elevation kept
    EXPECT_GE(c.orthoHalfHeight, radius);                     // the bounding sphere stays in the image
    const glm::dvec3 dn = glm::normalize(cams[std::size_t((i + 1) % n)].eye - c.target);
    const double turn = std::atan2(d.x * dn.y - d.y * dn.x, d.x * dn.x + d.y * dn.y) * 180 / M_PI;
    EXPECT_NEAR(turn, 360.0 / n, 1e-6) << i;
  }
  // Anterior start: the camera in front of the patient (+y), looking back.
  EXPECT_GT(cams[0].eye.y, 0.0);
  EXPECT_NEAR(cams[0].eye.x, 0.0, 1e-9);
}

TEST(MovieCameras, SweepCoversTheSlicesWithData) {
  dtf::Grid g;
  g.dims = {4, 5, 10};
  dtf::ScalarVolume fa(g, 1, 0.0f);
  for (int k = 3; k <= 7; ++k) fa.data[fa.grid.index(1, 2, k)] = 0.5f;
  const auto idx = dtf::session::sweepIndices(fa, "axial", 5);
  EXPECT_EQ(idx, (std::vector<int>{3, 4, 5, 6, 7}));
  const auto two = dtf::session::sweepIndices(fa, "axial", 3);
  EXPECT_EQ(two, (std::vector<int>{3, 5, 7}));
}

// An automatic mask's end slices hold a few scattered noise voxels; the sweep starts and ends where the
// slices hold a real share of the data (here 1 voxel of 400 against 5 % of the fullest slice).
TEST(MovieCameras, SweepSkipsEndSlicesOfScatteredVoxels) {
  dtf::Grid g;
  g.dims = {20, 20, 12};
  dtf::ScalarVolume fa(g, 1, 0.0f);
  for (int k = 2; k <= 9; ++k)
    for (int j = 0; j < 20; ++j)
      for (int i = 0; i < 20; ++i)
        if (k > 2 && k < 9 ? (i - 10) * (i - 10) + (j - 10) * (j - 10) < 64 : i < 5 && j < 5)
          fa.data[fa.grid.index(i, j, k)] = 0.4f; // slices 3..8 a disc of ~200; 2 and 9 a corner of 25
  fa.data[fa.grid.index(3, 3, 0)] = fa.data[fa.grid.index(17, 2, 11)] = 0.3f; // noise
  EXPECT_EQ(dtf::session::sweepIndices(fa, "axial", 4), (std::vector<int>{2, 4, 7, 9}));
  fa.data[fa.grid.index(0, 0, 2)] = 0.0f; // slice 2 now 24 voxels, 9 keeps 25: both above 5 % of 197
  EXPECT_EQ(dtf::session::sweepIndices(fa, "axial", 2), (std::vector<int>{2, 9}));
  for (int k : {2, 9})
    for (int j = 0; j < 5; ++j)
      for (int i = 0; i < 5; ++i)
        fa.data[fa.grid.index(i, j, k)] = (i + j) == 0 ? 0.4f : 0.0f; // one voxel left: below 5 %
  EXPECT_EQ(dtf::session::sweepIndices(fa, "axial", 2), (std::vector<int>{3, 8}));
}

namespace {

// Consecutive turntable frames 0.25 degrees apart: carried (as the movie runs) against re-seeded stills.
void fibreTurntableCoherence(const std::string& input, const std::string& surface, double& carried,
                             double& reseeded) {
  dtf::session::RenderRequest r;
  r.input = input;
  r.surface = dtf::session::parseSurfaceSpec(surface);
  r.width = r.height = 128;
  dtf::session::FrameSession session(r);
  ASSERT_EQ(session.params().colour, dtf::render::ColourMode::Fibres);
  glm::vec3 lo, hi;
  session.surface().bounds(lo, hi);
  const auto cams = dtf::session::turntableCameras(dtf::render::StandardView::Superior, glm::dvec3(lo),
                                                   glm::dvec3(hi), 1.0, 1440, 20, false, true);
  const int used = 5, seed = session.params().seed;
  std::vector<dtf::Image> a, b;
  for (int i = 0; i < used; ++i) a.push_back(session.frame(cams[std::size_t(i)], i == 0));
  for (int i = 0; i < used; ++i) {
    session.params().seed = seed + 1 + i;
    b.push_back(session.frame(cams[std::size_t(i)], true));
  }
  carried = reseeded = 0;
  for (int i = 1; i < used; ++i) {
    carried += meanAbsDiff(a[std::size_t(i - 1)], a[std::size_t(i)]) / (used - 1);
    reseeded += meanAbsDiff(b[std::size_t(i - 1)], b[std::size_t(i)]) / (used - 1);
  }
}

} // namespace

TEST(MovieCoherence, FibreSetMoviesStayCoherent) {
  DTF_GL_TEST_SETUP();
  // Two populations (a crossing phantom written as MRtrix peaks): the state is reprojected as for tensors.
  const auto dir = dtf::test::scratchDir();
  const std::string crossing = (dir / "crossing_peaks.nii.gz").string();
  dtf::io::PhantomOptions o;
  o.size = 32;
  dtf::io::writeFibres(crossing, dtf::io::makeFibrePhantom("crossing", o), dtf::io::FibreLayout::MrtrixPeaks);
  double carried2 = 0, reseeded2 = 0;
  fibreTurntableCoherence(crossing, "slice=axial", carried2, reseeded2);
  // Three populations (the real brain's peaks): every frame converges from the world-anchored noise.
  DTF_SHARED_FILE(peaks, "iu_prisma_dwi/derived/fibres/peaks_mrtrix.nii.gz");
  double carried3 = 0, reseeded3 = 0;
  fibreTurntableCoherence(peaks.string(), "slice=axial:22", carried3, reseeded3);
  std::printf("fibre-set turntable, consecutive frames 0.25 deg apart, mean |dRGB|: two populations carried "
              "%.2f, re-seeded %.2f; three populations (converged per frame) %.2f, re-seeded %.2f\n",
              carried2, reseeded2, carried3, reseeded3);
  EXPECT_LT(carried2, 0.5 * reseeded2);
  EXPECT_LT(carried3, 0.5 * reseeded3);
}

TEST(MovieFrames, AFibreSetSweepsThroughItsSlicesWithFibres) {
  DTF_GL_TEST_SETUP();
  DTF_SHARED_FILE(peaks, "iu_prisma_dwi/derived/fibres/peaks_mrtrix.nii.gz");
  dtf::session::MovieRequest m;
  m.render.input = peaks.string();
  m.render.width = m.render.height = 64;
  m.kind = dtf::session::MovieRequest::Kind::Sweep;
  m.axis = "axial";
  m.frames = 4;
  int frames = 0;
  std::size_t lit = 0;
  dtf::session::runMovie(m, [&](int i, const dtf::Image& img) {
    EXPECT_EQ(i, frames++);
    EXPECT_EQ(img.width, 64);
    for (std::size_t p = 0; p < img.rgba.size(); p += 4) lit += img.rgba[p] + img.rgba[p + 1] + img.rgba[p + 2] > 60;
  });
  EXPECT_EQ(frames, 4);
  EXPECT_GT(lit, 4u * 64 * 64 / 20) << "the frames show fibres";
}
