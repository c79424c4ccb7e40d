// SPDX-License-Identifier: GPL-3.0-or-later
// Dependencies point down only. The modules stand in an ordered table, lowest first; a module may include its
// own headers and those of the lower modules it names, nothing above or beside. No two files include each
// other through any chain, and inside each of io/, ui/ and app/ no two folders do. The rules are functions
// of a tree (support/layering.h): the last tests run them on small trees made to break each rule.
#include "support/layering.h"
#include "support/test_env.h"

#include <fstream>
#include <regex>

namespace fs = std::filesystem;
using namespace dtf::test::layering;

namespace {

// The top-level folders that hold sources.
const std::vector<std::string> kTops = {"io", "shaders", "surfaces", "render", "ui", "app"};

// Lowest first. A new sub-folder of io/ belongs to "io" (its folders are kept acyclic by the folder rule
// below); a new module elsewhere gets its own row.
const std::vector<Layer> kLayers = {
    {"io/model", {}},
    {"io", {"io/model"}},
    {"shaders", {}},
    {"surfaces", {"io/model"}},
    {"render", {"io/model", "shaders"}},
    // The session every front end drives, and the panels that draw it.
    {"ui/session", {"io/model", "io", "shaders", "surfaces", "render"}},
    {"ui/panels", {"io/model", "surfaces", "render", "ui/session"}},
    // The front ends: the command base (option tables, parsing, the command type), the viewer, the
    // benchmarks, the command line above them, and the Python module.
    {"app/command", {"io/model", "io", "render"}},
    {"app/viewer", {"io/model", "io", "shaders", "surfaces", "render", "ui/session", "ui/panels"}},
    {"app/bench",
     {"io/model", "io", "shaders", "surfaces", "render", "ui/session", "ui/panels", "app/command",
      "app/viewer"}},
    {"app/cli",
     {"io/model", "io", "shaders", "surfaces", "render", "ui/session", "ui/panels", "app/command",
      "app/viewer", "app/bench"}},
    {"app/python", {"io/model", "io", "shaders", "surfaces", "render", "ui/session"}},
};

// Writes `text` to root/rel, creating its folders.
void writeFile(const fs::path& root, const std::string& rel, const std::string& text) {
  fs::create_directories((root / rel).parent_path());
  std::ofstream(root / rel) << text;
}

} // namespace

TEST(Layering, TheLayerTableNamesOnlyLowerModules) {
  for (const auto& e : tableOrderErrors(kLayers))
    ADD_FAILURE() << e;
}

TEST(Layering, ModulesIncludeOnlyLowerModulesTheyName) {
  const auto edges = scanIncludes(dtf::test::sourceDir(), kTops);
  EXPECT_GT(edges.size(), 500u) << "the scan found almost no includes: is the source tree where expected?";
  for (const auto& e : forbiddenIncludes(edges, kLayers))
    ADD_FAILURE() << e;
}

TEST(Layering, NoIncludeCycleBetweenFiles) {
  for (const auto& c : cycles(fileGraph(scanIncludes(dtf::test::sourceDir(), kTops))))
    ADD_FAILURE() << "include cycle: " << joined(c);
}

// Inside io/, ui/ and app/, each folder is a layer of its own: the folders' include graph has no cycle.
TEST(Layering, NoIncludeCycleBetweenFoldersOfIoUiAndApp) {
  const auto edges = scanIncludes(dtf::test::sourceDir(), kTops);
  for (const char* top : {"io", "ui", "app"})
    for (const auto& c : cycles(folderGraph(edges, top)))
      ADD_FAILURE() << "folders include each other: " << joined(c);
}

// Every source file belongs to a module of the table (a new folder is placed in the order on purpose).
TEST(Layering, EverySourceBelongsToAModule) {
  const fs::path root = dtf::test::sourceDir();
  int seen = 0;
  for (const auto& top : kTops)
    for (const auto& entry : fs::recursive_directory_iterator(root / top)) {
      if (!entry.is_regular_file() || !isSource(entry.path())) continue;
      const std::string rel = fs::relative(entry.path(), root).generic_string();
      EXPECT_FALSE(moduleOf(rel, kLayers).empty()) << rel << " is in no module of the layer table";
      ++seen;
    }
  EXPECT_GT(seen, 100);
}

// Private headers live in a module's detail/ folder and may use them.
TEST(Layering, HeavyLibrariesStayOutOfPublicHeaders) {
  const fs::path root = dtf::test::sourceDir();
  const std::regex heavy(R"(#\s*include\s*[<\"](vtk|CGAL/|nifti|EGL/|GLFW/|imgui))");
  for (const char* module : {"io", "surfaces", "render"}) {
    for (const auto& entry : fs::recursive_directory_iterator(root / module)) {
      if (entry.path().extension() != ".h") continue;
      if (entry.path().parent_path().filename() == "detail") continue; // private to its module
      std::ifstream in(entry.path());
      std::string line;
      while (std::getline(in, line))
        EXPECT_FALSE(std::regex_search(line, heavy)) << entry.path() << ": " << line;
    }
  }
}

// GLFW appears only in the viewer; the session needs neither a window, ImGui nor a GL loader; the panels draw
// through ImGui only (no epoxy); the command base is plain text (no GL, no ImGui).
TEST(Layering, WindowAndGlLoaderStayInTheirModules) {
  const fs::path root = dtf::test::sourceDir();
  const std::regex glfw(R"(#\s*include\s*[<\"]GLFW/)"), imgui(R"(#\s*include\s*[<\"]imgui)"),
      epoxy(R"(#\s*include\s*[<\"]epoxy/)");
  int scanned = 0;
  for (const auto& top : kTops) {
    for (const auto& entry : fs::recursive_directory_iterator(root / top)) {
      if (!entry.is_regular_file() || !isSource(entry.path())) continue;
      const std::string rel = fs::relative(entry.path(), root).generic_string();
      const std::string mod = moduleOf(rel, kLayers);
      std::ifstream in(entry.path());
      std::string line;
      while (std::getline(in, line)) {
        const bool glfwHere = std::regex_search(line, glfw), imguiHere = std::regex_search(line, imgui),
                   epoxyHere = std::regex_search(line, epoxy);
        EXPECT_FALSE(glfwHere && mod != "app/viewer") << rel << ": " << line;
        EXPECT_FALSE(imguiHere && (mod == "ui/session" || mod == "app/command")) << rel << ": " << line;
        EXPECT_FALSE(epoxyHere && (mod == "ui/session" || mod == "ui/panels" || mod == "app/command"))
            << rel << ": " << line;
      }
      ++scanned;
    }
  }
  EXPECT_GT(scanned, 50);
}

// The panels' vocabulary and the fabric options table are plain values: through every header they include,
// directly or not, they reach no GL loader (render/fabric_params.h, not render/fabric_renderer.h).
TEST(Layering, VocabularyHeadersReachNoGlLoader) {
  const fs::path root = dtf::test::sourceDir();
  const auto graph = fileGraph(scanIncludes(root, kTops));
  const std::regex gl(R"(#\s*include\s*[<\"](epoxy/|EGL/|GL/))");
  for (const char* header : {"ui/session/actions.h", "ui/session/viewer_state.h", "ui/session/keymap.h",
                             "render/fabric_options.h", "render/fabric_params.h"}) {
    ASSERT_TRUE(fs::exists(root / header)) << header;
    std::set<std::string> files = reachable(graph, header);
    files.insert(header);
    EXPECT_FALSE(files.count("render/fabric_renderer.h")) << header << " reaches render/fabric_renderer.h";
    for (const auto& f : files) {
      std::ifstream in(root / f);
      for (std::string line; std::getline(in, line);)
        EXPECT_FALSE(std::regex_search(line, gl)) << header << " reaches " << f << ": " << line;
    }
  }
}

// The checker itself, on a small tree in a scratch folder: clean, it reports nothing; each wrong include
// added to it is reported.
TEST(Layering, TheCheckerReportsAWrongIncludeInASyntheticTree) {
  const fs::path root = dtf::test::scratchDir() / "tree";
  const std::vector<Layer> table = {{"io/model", {}},
                                    {"io", {"io/model"}},
                                    {"render", {"io/model"}},
                                    {"app/cli", {"io/model", "io", "render"}}};
  writeFile(root, "io/model/grid.h", "#pragma once\n");
  writeFile(root, "io/formats/nifti.h", "#pragma once\n#include \"io/model/grid.h\"\n");
  writeFile(root, "io/dwi/fit.h", "#pragma once\n#include \"io/formats/nifti.h\"\n");
  writeFile(root, "render/fabric.h", "#pragma once\n#include \"io/model/grid.h\"\n#include <vector>\n");
  writeFile(root, "app/cli/cli.cpp", "#include \"render/fabric.h\"\n#include \"io/dwi/fit.h\"\n");
  const std::vector<std::string> tops = {"io", "render", "app"};
  const auto clean = scanIncludes(root, tops);
  EXPECT_EQ(clean.size(), 5u);
  EXPECT_TRUE(tableOrderErrors(table).empty());
  EXPECT_TRUE(forbiddenIncludes(clean, table).empty());
  EXPECT_TRUE(cycles(fileGraph(clean)).empty());
  EXPECT_TRUE(cycles(folderGraph(clean, "io")).empty());

  // Upward: render includes the command line.
  writeFile(root, "render/fabric.cpp", "#include \"render/fabric.h\"\n#include \"app/cli/cli.h\"\n");
  writeFile(root, "app/cli/cli.h", "#pragma once\n");
  const auto upward = forbiddenIncludes(scanIncludes(root, tops), table);
  ASSERT_EQ(upward.size(), 1u);
  EXPECT_EQ(upward[0], "render/fabric.cpp includes app/cli/cli.h (render -> app/cli)");
  fs::remove(root / "render/fabric.cpp");

  // Sideways, between two modules neither of which names the other; and a table that lets both include
  // each other.
  EXPECT_EQ(tableOrderErrors({{"app/cli", {"app/bench"}}, {"app/bench", {"app/cli"}}}).size(), 1u);

  // Two headers including each other (inside one module, so only the cycle rule sees it).
  writeFile(root, "io/formats/nifti.h",
            "#pragma once\n#include \"io/model/grid.h\"\n#include \"io/dwi/fit.h\"\n");
  const auto cyclic = scanIncludes(root, tops);
  EXPECT_TRUE(forbiddenIncludes(cyclic, table).empty()) << "io/formats and io/dwi are one module";
  const auto fileCycles = cycles(fileGraph(cyclic));
  ASSERT_EQ(fileCycles.size(), 1u);
  EXPECT_EQ(joined(fileCycles[0]), "io/dwi/fit.h <-> io/formats/nifti.h");
  const auto folderCycles = cycles(folderGraph(cyclic, "io"));
  ASSERT_EQ(folderCycles.size(), 1u);
  EXPECT_EQ(joined(folderCycles[0]), "io/dwi <-> io/formats");

  // Folders in a cycle through .cpp files only (no file cycle).
  writeFile(root, "io/formats/nifti.h", "#pragma once\n#include \"io/model/grid.h\"\n");
  writeFile(root, "io/formats/nifti.cpp", "#include \"io/formats/nifti.h\"\n#include \"io/dwi/fit.h\"\n");
  const auto viaSources = scanIncludes(root, tops);
  EXPECT_TRUE(cycles(fileGraph(viaSources)).empty());
  EXPECT_EQ(cycles(folderGraph(viaSources, "io")).size(), 1u);
}
