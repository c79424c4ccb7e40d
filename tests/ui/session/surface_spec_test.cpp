// SPDX-License-Identifier: GPL-3.0-or-later
// Surface specs as written on the command line: parsing, errors, and joined surfaces.
#include "io/model/error.h"
#include "surfaces/slices.h"
#include "ui/session/surface_spec.h"

#include <gtest/gtest.h>

using namespace dtf;
using session::SurfaceSpec;

TEST(SurfaceSpec, ParsesEachKind) {
  EXPECT_EQ(session::parseSurfaceSpec("fa=0.3").kind, SurfaceSpec::Kind::Fa);
  EXPECT_DOUBLE_EQ(session::parseSurfaceSpec("fa=0.3").value, 0.3);
  SurfaceSpec s = session::parseSurfaceSpec("slice=coronal:12");
  EXPECT_EQ(s.axis, "coronal");
  EXPECT_EQ(s.index, 12);
  EXPECT_EQ(session::parseSurfaceSpec("slice=axial").index, -1);
  s = session::parseSurfaceSpec("fibre-voxel=1,2,3:4,5,6");
  EXPECT_TRUE(s.voxelCoords);
  EXPECT_EQ(s.b, glm::dvec3(4, 5, 6));
  s = session::parseSurfaceSpec("iso=/data/x+y.nii.gz:0.5");
  EXPECT_EQ(s.kind, SurfaceSpec::Kind::Iso) << "a '+' inside a file name does not split";
  EXPECT_EQ(s.file, "/data/x+y.nii.gz");
  for (const char* bad : {"fa=1.5", "fa=abc", "slice=upward:3", "slice=axial:-1", "slice=axial:2.5",
                          "plane=0,0,0:0,0,0", "fibre=1,2:3,4,5", "bogus=1", "nothing", "mesh="})
    EXPECT_THROW(session::parseSurfaceSpec(bad), UsageError) << bad;
}

TEST(SurfaceSpec, JoinedSlicesBuildOneMesh) {
  Grid g = Grid::fromAffine({10, 12, 8}, glm::dmat4(1.0));
  TensorField f = makeTensorField(g);
  for (std::size_t i = 0; i < f.tensors.size(); ++i) {
    f.tensors[i] = SymTensor{1.7e-3f, 0, 0, 3e-4f, 0, 3e-4f};
    f.valid[i] = 1;
  }
  ScalarVolume fa = computeFaMap(f);
  SurfaceSpec s = session::parseSurfaceSpec("slice=axial:3+slice=coronal:5+slice=sagittal:4");
  ASSERT_EQ(s.kind, SurfaceSpec::Kind::Combined);
  ASSERT_EQ(s.parts.size(), 3u);
  Mesh m = session::buildSurface(s, f, fa);
  EXPECT_EQ(m.triangleCount(), 2u * (9 * 11 + 9 * 7 + 11 * 7));
  EXPECT_EQ(m.normals.size(), m.positions.size());
  EXPECT_EQ(session::describeSurface(s), "axial slice 3 + coronal slice 5 + sagittal slice 4");
  EXPECT_THROW(session::buildSurface(session::parseSurfaceSpec("slice=axial:3+slice=axial:30"), f, fa),
               InputError);
}
