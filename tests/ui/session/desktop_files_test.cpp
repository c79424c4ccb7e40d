// SPDX-License-Identifier: GPL-3.0-or-later
// The viewer's files without a window: a folder listed for the in-window browser (subfolders first, only
// the names the target reads), a dropped file's kind (volumes, tractograms, meshes told from VTK lines or
// polygons, region sets), a drop of several files turned into the actions of each kind or refused whole,
// and the remembered settings read, written and merged with the command line.
#include "io/model/error.h"
#include "support/test_env.h"
#include "ui/session/file_kinds.h"
#include "ui/session/region_spec.h"
#include "ui/session/viewer_config.h"

#include <fstream>
#include <gtest/gtest.h>

using namespace dtf;
using namespace dtf::session;
namespace fs = std::filesystem;

namespace {

const fs::path kPhantom = test::sourceDir() / "sample_data" / "brain_phantom.nii.gz";

void touch(const fs::path& p, const std::string& text = "x") {
  std::ofstream(p) << text;
}

// A legacy ASCII VTK file of two points joined by a line (streamlines) or three points in a triangle (mesh).
std::string vtk(bool polygons) {
  return polygons
             ? "# vtk DataFile Version 3.0\nmesh\nASCII\nDATASET POLYDATA\nPOINTS 3 float\n0 0 0 1 0 0 0 1 "
               "0\n"
               "POLYGONS 1 4\n3 0 1 2\n"
             : "# vtk DataFile Version 3.0\nlines\nASCII\nDATASET POLYDATA\nPOINTS 2 float\n0 0 0 1 0 0\n"
               "LINES 1 3\n2 0 1\n";
}

} // namespace

TEST(DesktopFiles, FolderListingShowsSubfoldersThenTheFilesTheTargetReads) {
  const auto dir = test::scratchDir();
  fs::create_directories(dir / "sub-02");
  fs::create_directories(dir / "Anat");
  fs::create_directories(dir / ".hidden");
  touch(dir / "b_tensor.nii.gz");
  touch(dir / "A_dwi.NII");
  touch(dir / "notes.txt");
  touch(dir / "tracts.tck");
  touch(dir / ".secret.nii");
  const FolderListing data = listFolder(dir.string(), FileTarget::Data);
  EXPECT_TRUE(data.error.empty()) << data.error;
  EXPECT_EQ(data.folder, fs::absolute(dir).lexically_normal().string());
  std::vector<std::string> names;
  for (const auto& e : data.entries)
    names.push_back(e.name + (e.folder ? "/" : ""));
  EXPECT_EQ(names, (std::vector<std::string>{"Anat/", "sub-02/", "A_dwi.NII", "b_tensor.nii.gz"}));
  const FolderListing tracts = listFolder(dir.string(), FileTarget::Tracts);
  ASSERT_EQ(tracts.entries.size(), 3u);
  EXPECT_EQ(tracts.entries[2].name, "tracts.tck");
  EXPECT_EQ(tracts.entries[2].bytes, 1u);
  const FolderListing missing = listFolder((dir / "nowhere").string(), FileTarget::Data);
  EXPECT_TRUE(missing.entries.empty());
  EXPECT_NE(missing.error.find("nowhere"), std::string::npos) << missing.error;
  EXPECT_TRUE(fileTargetAccepts(FileTarget::SessionSave, "my.dtfview"));
  EXPECT_FALSE(fileTargetAccepts(FileTarget::Screenshot, "shot.jpg"));
  EXPECT_EQ(parseFileTarget("tracts-save"), FileTarget::TractsSave);
  EXPECT_FALSE(parseFileTarget("nonsense").has_value());
}

TEST(DesktopFiles, DroppedFilesAreToldApartByKind) {
  const auto dir = test::scratchDir();
  touch(dir / "lines.vtk", vtk(false));
  touch(dir / "mesh.vtk", vtk(true));
  touch(dir / "mesh.ply", "ply\nformat ascii 1.0\nend_header\n");
  touch(dir / "regions.json", "{}");
  touch(dir / "empty.vtk", "# vtk DataFile Version 3.0\nnothing\nASCII\nDATASET POLYDATA\nPOINTS 0 float\n");
  EXPECT_EQ(classifyDrop(kPhantom.string()), DropKind::Data);
  EXPECT_EQ(classifyDrop((dir / "lines.vtk").string()), DropKind::Tracts);
  EXPECT_EQ(classifyDrop((dir / "mesh.vtk").string()), DropKind::Mesh);
  EXPECT_EQ(classifyDrop((dir / "mesh.ply").string()), DropKind::Mesh);
  EXPECT_EQ(classifyDrop((dir / "regions.json").string()), DropKind::Regions);
  try {
    classifyDrop((dir / "empty.vtk").string());
    ADD_FAILURE() << "a VTK file without cells has no kind";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("empty.vtk"), std::string::npos) << e.what();
  }
  try {
    classifyDrop((dir / "gone.nii.gz").string());
    ADD_FAILURE() << "a missing file has no kind";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("gone.nii.gz: no such file"), std::string::npos) << e.what();
  }
}

TEST(DesktopFiles, ADropOfThreeKindsOpensEachAsItsKindMeshFirst) {
  const auto dir = test::scratchDir();
  touch(dir / "lines.vtk", vtk(false));
  touch(dir / "mesh.ply", "ply\nformat ascii 1.0\nend_header\n");
  const ActionList a =
      dropActions({(dir / "lines.vtk").string(), kPhantom.string(), (dir / "mesh.ply").string()});
  ASSERT_EQ(a.size(), 3u);
  // The mesh first (the data's first surface), then the data, then the tracts.
  ASSERT_TRUE(std::holds_alternative<SetSurfaceSpec>(a[0]));
  EXPECT_EQ(std::get<SetSurfaceSpec>(a[0]).text, "mesh=" + (dir / "mesh.ply").string());
  ASSERT_TRUE(std::holds_alternative<LoadFile>(a[1]));
  EXPECT_EQ(std::get<LoadFile>(a[1]).path, kPhantom.string());
  EXPECT_EQ(std::get<LoadFile>(a[1]).layout, "auto");
  ASSERT_TRUE(std::holds_alternative<LoadTracts>(a[2]));
  EXPECT_EQ(std::get<LoadTracts>(a[2]).path, (dir / "lines.vtk").string());
}

TEST(DesktopFiles, ABadDropOpensNothingAndNamesTheFile) {
  const auto dir = test::scratchDir();
  touch(dir / "lines.vtk", vtk(false));
  touch(dir / "regions.json", "{}");
  auto message = [](const std::vector<std::string>& paths) {
    try {
      const ActionList a = dropActions(paths);
      ADD_FAILURE() << "the drop was taken: " << a.size() << " actions";
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  const std::string missing = message({(dir / "lines.vtk").string(), (dir / "missing.nii.gz").string()});
  EXPECT_NE(missing.find((dir / "missing.nii.gz").string() + ": no such file"), std::string::npos) << missing;
  const std::string two = message({(dir / "lines.vtk").string(), (dir / "lines.vtk").string()});
  EXPECT_NE(two.find("two tractograms"), std::string::npos) << two;
  // A region set is read first: a bad one says why and nothing opens.
  const std::string badRegions = message({(dir / "regions.json").string()});
  EXPECT_NE(badRegions.find("regions.json"), std::string::npos) << badRegions;
  const fs::path set = dir / "set.json";
  surfaces::RegionSet regionSet;
  surfaces::Region sphere;
  sphere.centre = glm::dvec3(10, -20, 5);
  sphere.radius = 5;
  regionSet.regions.push_back(sphere);
  writeRegionSetFile(set.string(), regionSet); // as `dtfabric select` reads it
  // A good one becomes the ROI selection's regions, after the tracts.
  const ActionList regions = dropActions({set.string(), (dir / "lines.vtk").string()});
  ASSERT_EQ(regions.size(), 2u);
  EXPECT_TRUE(std::holds_alternative<LoadTracts>(regions[0]));
  ASSERT_TRUE(std::holds_alternative<LoadRegions>(regions[1]));
  EXPECT_EQ(std::get<LoadRegions>(regions[1]).path, set.string());
  const std::string notData = message({(dir / "lines.vtk").string(), (dir / "regions.json").string()});
  EXPECT_NE(notData.find("regions.json"), std::string::npos) << notData;
}

TEST(DesktopFiles, RememberedSettingsRoundTripAndFlagsWin) {
  ViewerConfig c;
  c.width = 1600;
  c.height = 1000;
  c.uiScale = 1.5;
  c.lastFolder = "/data/sub 01";
  c.recentFiles = {"/data/sub 01/dti.nii.gz", "/data/b.tck"};
  c.recentFolders = {"/data/sub 01"};
  c.panelsOpen = {{"Tracts", true}, {"Fabric", false}};
  const auto dir = test::scratchDir();
  const std::string path = (dir / "cfg" / "dtfabric" / "viewer.conf").string();
  writeViewerConfig(path, c);
  std::vector<std::string> warnings;
  const ViewerConfig r = readViewerConfig(path, &warnings);
  EXPECT_TRUE(warnings.empty());
  EXPECT_EQ(r.width, 1600);
  EXPECT_EQ(r.height, 1000);
  EXPECT_EQ(r.uiScale, 1.5);
  EXPECT_EQ(r.lastFolder, c.lastFolder);
  EXPECT_EQ(r.recentFiles, c.recentFiles);
  EXPECT_EQ(r.recentFolders, c.recentFolders);
  EXPECT_EQ(r.panelsOpen, c.panelsOpen);

  // Flags win; what they leave out comes from the file; without either, the defaults.
  StartSettings s = mergeConfig(r, 800, 600, std::nullopt);
  EXPECT_EQ(s.width, 800);
  EXPECT_EQ(s.uiScale, 1.5);
  s = mergeConfig(r, std::nullopt, std::nullopt, 2.0);
  EXPECT_EQ(s.width, 1600);
  EXPECT_EQ(s.height, 1000);
  EXPECT_EQ(s.uiScale, 2.0);
  s = mergeConfig(ViewerConfig{}, std::nullopt, std::nullopt, std::nullopt);
  EXPECT_EQ(s.width, 1280);
  EXPECT_FALSE(s.uiScale.has_value());

  // A bad line is skipped and named; the rest is read.
  const ViewerConfig bad =
      parseViewerConfig("size 10 10\nui-scale 9\nwhatever 1\nlast-folder /x\n", &warnings);
  EXPECT_EQ(warnings.size(), 3u);
  EXPECT_FALSE(bad.width.has_value());
  EXPECT_FALSE(bad.uiScale.has_value());
  EXPECT_EQ(bad.lastFolder, "/x");
  // A missing file is the defaults, silently.
  warnings.clear();
  EXPECT_FALSE(readViewerConfig((dir / "none.conf").string(), &warnings).width.has_value());
  EXPECT_TRUE(warnings.empty());
}

TEST(DesktopFiles, ConfigFollowsXdgConfigHome) {
  const auto dir = test::scratchDir();
  ::setenv("XDG_CONFIG_HOME", dir.c_str(), 1);
  EXPECT_EQ(viewerConfigPath(), (dir / "dtfabric" / "viewer.conf").string());
  ::setenv("XDG_CONFIG_HOME", "relative/not/allowed", 1);
  ::setenv("HOME", dir.c_str(), 1);
  EXPECT_EQ(viewerConfigPath(), (dir / ".config" / "dtfabric" / "viewer.conf").string());
}
