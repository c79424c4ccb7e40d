// SPDX-License-Identifier: GPL-3.0-or-later
// `dtfabric view` under Xvfb with the roi script lines, on the real tracts of the shared data: two spheres on
// the right corticospinal tract select exactly the streamlines `dtfabric select` keeps with the same
// spheres, and the region set the viewer saves replays with `dtfabric select --roi` to the same streamlines.
// The ortho layout with the spheres is written as ortho.png in the scratch folder.
#include "io/formats/tracts.h"
#include "support/cli.h"
#include "support/test_env.h"
#include "support/window.h"

#include <gtest/gtest.h>

namespace fs = std::filesystem;

namespace {

std::string q(const fs::path& p) {
  return "'" + p.string() + "'";
}

// The streamlines of two .tck files are the same, in the same order, point for point.
void expectSameLines(const fs::path& a, const fs::path& b, const std::string& what) {
  const dtf::Polylines x = dtf::io::readTck(a.string()), y = dtf::io::readTck(b.string());
  ASSERT_EQ(x.lineCount(), y.lineCount()) << what;
  ASSERT_EQ(x.points.size(), y.points.size()) << what;
  EXPECT_EQ(x.offsets, y.offsets) << what;
  EXPECT_TRUE(x.points == y.points) << what;
}

// The right corticospinal tract low (voxel 30,34,15 of the bundled brain) and higher in the corona radiata,
// as the select tests take them.
const std::string kCstLow = "18,3.7,21.6,6", kCstHigh = "20,0,45,10";

} // namespace

TEST(ViewRoiWindow, ScriptRegionsSelectWhatSelectKeepsAndTheSavedSetReplays) {
  DTF_XVFB_SETUP();
  DTF_SHARED_FILE(tensor, "iu_prisma_dwi/derived/dti_tensor.nii.gz");
  DTF_SHARED_FILE(tracks, "iu_prisma_dwi/derived/tracks_det.tck");
  const auto dir = dtf::test::scratchDir();
  const auto r = dtf::test::runViewerScript(
      dir,
      "tracts " + tracks.string() + "\nroi add include " + kCstLow + "\nroi add include " + kCstHigh +
          "\ntracts-save --selected " + (dir / "viewer.tck").string() + "\nroi save " +
          (dir / "set.json").string() + "\nlayout ortho\ncrosshair 18 3.7 21.6\nscreenshot-scene " +
          (dir / "ortho.png").string() + "\nquit\n",
      q(tensor));
  DTF_SKIP_WITHOUT_WINDOW_GL(r);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.err.find("ROI selection: "), std::string::npos) << r.err;

  const auto sel = dtf::test::runDtfabric("select " + q(tracks) + " -o " + q(dir / "select.tck") + " --include " +
                                              kCstLow + " --include " + kCstHigh,
                                          dir);
  ASSERT_EQ(sel.exitCode, 0) << sel.err;
  const std::size_t kept = dtf::io::readTck((dir / "select.tck").string()).lineCount();
  EXPECT_GE(kept, 20u) << "a selection too small to mean anything";
  expectSameLines(dir / "viewer.tck", dir / "select.tck", "the viewer's selection against `select`");

  const auto replay = dtf::test::runDtfabric(
      "select " + q(tracks) + " -o " + q(dir / "replay.tck") + " --roi " + q(dir / "set.json"), dir);
  ASSERT_EQ(replay.exitCode, 0) << replay.err;
  expectSameLines(dir / "replay.tck", dir / "select.tck", "the saved set replayed by `select --roi`");
}
