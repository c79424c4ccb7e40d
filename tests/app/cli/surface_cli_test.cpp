// SPDX-License-Identifier: GPL-3.0-or-later
// `dtfabric surface` end to end on the real brain and on bad input.
#include "support/cli.h"
#include "support/test_env.h"

#include <fstream>
#include <regex>

using dtf::test::jsonNumber;
using dtf::test::runDtfabric;

TEST(SurfaceCli, FibreSurfaceAlongCorticospinalTractBeatsTheAxialSlice) {
  DTF_SHARED_FILE(tensor, "iu_prisma_dwi/derived/dti_tensor.nii.gz");
  auto dir = dtf::test::scratchDir();
  // A left-right seed line across the right corticospinal tract (voxel (30,34,15), e1 superior-inferior).
  auto r = runDtfabric("surface '" + tensor.string() + "' --fibre-surface-voxel 27,34,15:33,34,15 -o '" +
                           (dir / "cst.ply").string() + "' --json",
                       dir);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const double fibre = jsonNumber(r.out, "e1_dot_n"), flat = jsonNumber(r.out, "flat_e1_dot_n");
  EXPECT_GE(fibre, 0.0) << r.out;
  EXPECT_LT(fibre, 0.05) << r.out;
  EXPECT_GT(flat, 0.3) << r.out;
  EXPECT_NE(r.out.find("\"flat_slice\": \"axial\""), std::string::npos) << r.out;
  EXPECT_GT(jsonNumber(r.out, "triangles"), 300);
  EXPECT_TRUE(std::filesystem::exists(dir / "cst.ply"));
}

TEST(SurfaceCli, FaIsosurfaceAndSliceWriteMeshes) {
  DTF_SHARED_FILE(tensor, "iu_prisma_dwi/derived/dti_tensor.nii.gz");
  auto dir = dtf::test::scratchDir();
  auto r = runDtfabric("surface '" + tensor.string() + "' --fa 0.3 -o '" + (dir / "fa.vtp").string() + "'", dir);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("FA isosurface at 0.3"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("quality:"), std::string::npos);
  r = runDtfabric("surface '" + tensor.string() + "' --slice axial:22 -o '" + (dir / "ax.obj").string() + "' --json", dir);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_GT(jsonNumber(r.out, "triangles"), 1000);
}

TEST(SurfaceCli, BadInputIsReportedWithExitCodes) {
  DTF_SHARED_FILE(tensor, "iu_prisma_dwi/derived/dti_tensor.nii.gz");
  auto dir = dtf::test::scratchDir();
  const std::string in = "'" + tensor.string() + "'";
  const std::string out = "'" + (dir / "m.ply").string() + "'";
  auto r = runDtfabric("surface " + in + " --fa 0.99 -o " + out, dir);
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("yields no surface"), std::string::npos) << r.err;
  r = runDtfabric("surface " + in + " --fibre-surface 500,500,500:510,500,500 -o " + out, dir);
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("outside the data"), std::string::npos) << r.err;
  r = runDtfabric("surface " + in + " --slice axial:99 -o " + out, dir);
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("outside the volume"), std::string::npos) << r.err;
  r = runDtfabric("surface " + in + " --surface bogus=1 -o " + out, dir);
  EXPECT_EQ(r.exitCode, 1);
  r = runDtfabric("surface " + in + " --fa 0.3 --slice axial -o " + out, dir);
  EXPECT_EQ(r.exitCode, 1) << "two surfaces at once";
  EXPECT_FALSE(std::filesystem::exists(dir / "m.ply"));
  // An existing output is kept unless --force; the input is never overwritten.
  std::ofstream(dir / "keep.ply") << "precious";
  r = runDtfabric("surface " + in + " --fa 0.3 -o '" + (dir / "keep.ply").string() + "'", dir);
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_EQ(dtf::test::readText(dir / "keep.ply"), "precious");
  r = runDtfabric("surface " + in + " --fa 0.3 --force -o " + in, dir);
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("input"), std::string::npos) << r.err;
}

TEST(SurfaceCli, RenderAcceptsTheSameSurfaceShorthands) {
  DTF_SHARED_FILE(tensor, "iu_prisma_dwi/derived/dti_tensor.nii.gz");
  auto dir = dtf::test::scratchDir();
  const std::string in = "'" + tensor.string() + "'";
  auto a = runDtfabric("render " + in + " --slice axial:20 --size 128x128 -o '" + (dir / "a.png").string() + "'", dir);
  ASSERT_EQ(a.exitCode, 0) << a.err;
  auto b = runDtfabric("render " + in + " --surface slice=axial:20 --size 128x128 -o '" + (dir / "b.png").string() + "'",
                       dir);
  ASSERT_EQ(b.exitCode, 0) << b.err;
  EXPECT_EQ(dtf::test::readText(dir / "a.png"), dtf::test::readText(dir / "b.png"));
  auto c = runDtfabric("render " + in + " --fa 0.3 --slice axial -o '" + (dir / "c.png").string() + "'", dir);
  EXPECT_EQ(c.exitCode, 1) << "two surfaces at once";
}

// A mesh that lies outside the data measures nothing: the score is absent (null, "not measured"), not
// 0, which would read as a perfect fit for the surface and as perfect agreement for the tracts. The same
// mesh moved into the data is scored, so the null comes from the position alone.
TEST(SurfaceCli, AMeshOutsideTheDataHasNoScore) {
  auto dir = dtf::test::scratchDir();
  const std::string t = "'" + (dir / "t.nii.gz").string() + "'";
  ASSERT_EQ(runDtfabric("phantom constant --size 48 -o " + t, dir).exitCode, 0);
  ASSERT_EQ(runDtfabric("track " + t + " -o '" + (dir / "t.tck").string() + "'", dir).exitCode, 0);
  auto writeObj = [&](const std::string& name, double at) {
    std::ofstream(dir / name) << "v " << at << " " << at << " " << at << "\nv " << at + 4 << " " << at << " "
                              << at << "\nv " << at << " " << at + 4 << " " << at + 2 << "\nf 1 2 3\n";
  };
  writeObj("far.obj", 1000);
  writeObj("in.obj", -2);
  for (const std::string mesh : {"far.obj", "in.obj"}) {
    const bool far = mesh == "far.obj";
    const std::string surf = " --surface mesh='" + (dir / mesh).string() + "'";
    auto r =
        runDtfabric("surface " + t + surf + " --force -o '" + (dir / "m.ply").string() + "' --json", dir);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    if (far) {
      EXPECT_NE(r.out.find("\"e1_dot_n\": null"), std::string::npos) << r.out;
    } else {
      EXPECT_GT(jsonNumber(r.out, "e1_dot_n"), 0.0) << r.out; // the constant e1 is oblique to this triangle
    }
    r = runDtfabric("surface " + t + surf + " --force -o '" + (dir / "m.ply").string() + "'", dir);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(r.out.find("not measured") != std::string::npos, far) << r.out;
    EXPECT_EQ(r.out.find("mean |e1 . n|") == std::string::npos, far) << r.out;
  }
  auto r = runDtfabric("compare " + t + " --surface mesh='" + (dir / "far.obj").string() + "' --tracts '" +
                           (dir / "t.tck").string() + "' --json",
                       dir);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_EQ(jsonNumber(r.out, "points"), 0) << r.out;
  for (const char* key : {"\"mean_deg\": null", "\"median_deg\": null", "\"frac_below_15\": null"})
    EXPECT_NE(r.out.find(key), std::string::npos) << key << " in " << r.out;
}
