// Dependencies point down only: a module may include headers of the modules it links and nothing above.
#include "support/test_env.h"

#include <fstream>
#include <map>
#include <regex>
#include <vector>

namespace fs = std::filesystem;

namespace {
// Module -> modules whose headers it may include (besides its own).
const std::map<std::string, std::vector<std::string>> kAllowed = {
    {"io/model", {}},
    {"io", {"io/model"}},
    {"shaders", {}},
    {"surfaces", {"io/model"}},
    {"render", {"io/model", "shaders"}},
    {"ui/session", {"io/model", "io", "shaders", "surfaces", "render"}},
    {"ui/panels", {"render", "io/model", "ui/session"}},
    {"app/viewer", {"io/model", "io", "shaders", "surfaces", "render", "ui/panels", "ui/session"}},
    {"app/cli",
     {"io/model", "io", "shaders", "surfaces", "render", "ui/panels", "ui/session", "app/viewer",
      "app/bench"}},
    {"app/bench",
     {"io/model", "io", "shaders", "surfaces", "render", "ui/panels", "ui/session", "app/viewer", "app/cli"}},
    {"app/python", {"io/model", "io", "shaders", "surfaces", "render", "ui/panels", "ui/session"}},
};

std::string moduleOf(const std::string& rel) {
  if (rel.rfind("io/model/", 0) == 0) return "io/model";
  for (const std::string top : {"app/", "ui/"})
    if (rel.rfind(top, 0) == 0) {
      auto slash = rel.find('/', top.size());
      return slash == std::string::npos ? top.substr(0, top.size() - 1) : rel.substr(0, slash);
    }
  auto slash = rel.find('/');
  return slash == std::string::npos ? "" : rel.substr(0, slash);
}
} // namespace

TEST(Layering, ModulesIncludeOnlyWhatTheyLink) {
  const fs::path root = dtf::test::sourceDir();
  const std::regex inc(R"(^\s*#\s*include\s*\"([^\"]+)\")");
  int checked = 0;
  for (const auto& [module, allowed] : kAllowed) {
    for (const auto& entry : fs::recursive_directory_iterator(root / module)) {
      if (!entry.is_regular_file()) continue;
      auto ext = entry.path().extension().string();
      if (ext != ".h" && ext != ".cpp") continue;
      std::string rel = fs::relative(entry.path(), root).string();
      if (moduleOf(rel) != module) continue; // io/model files belong to io/model, not io
      std::ifstream in(entry.path());
      std::string line;
      while (std::getline(in, line)) {
        std::smatch m;
        if (!std::regex_search(line, m, inc)) continue;
        std::string target = m[1];
        std::string tmod = moduleOf(target);
        if (!kAllowed.count(tmod)) continue; // generated or same-directory headers
        bool ok = tmod == module || std::find(allowed.begin(), allowed.end(), tmod) != allowed.end();
        EXPECT_TRUE(ok) << rel << " includes " << target << " from module " << tmod;
        ++checked;
      }
    }
  }
  EXPECT_GT(checked, 10) << "the scan found almost no includes: is the source tree where expected?";
}

// Private headers live in a module's detail/ folder and may use them.
TEST(Layering, HeavyLibrariesStayOutOfPublicHeaders) {
  const fs::path root = dtf::test::sourceDir();
  const std::regex heavy(R"(#\s*include\s*[<\"](vtk|CGAL/|nifti|EGL/|GLFW/|imgui))");
  for (const char* module : {"io/model", "io", "surfaces", "render"}) {
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

// Each source file under app/ belongs to one of its front ends.
TEST(Layering, AppSourcesLiveInTheirFolders) {
  const fs::path root = dtf::test::sourceDir();
  int seen = 0;
  for (const auto& entry : fs::recursive_directory_iterator(root / "app")) {
    auto ext = entry.path().extension().string();
    if (!entry.is_regular_file() || (ext != ".h" && ext != ".cpp")) continue;
    const std::string rel = fs::relative(entry.path(), root).string();
    EXPECT_TRUE(kAllowed.count(moduleOf(rel)))
        << rel << " is not in app/cli, app/viewer, app/bench or app/python";
    ++seen;
  }
  EXPECT_GT(seen, 20);
}

// GLFW appears only in the viewer; the session needs neither a window, ImGui nor a GL loader; the panels draw
// through ImGui only (no epoxy).
TEST(Layering, WindowAndGlLoaderStayInTheirModules) {
  const fs::path root = dtf::test::sourceDir();
  const std::regex glfw(R"(#\s*include\s*[<\"]GLFW/)"), imgui(R"(#\s*include\s*[<\"]imgui)"),
      epoxy(R"(#\s*include\s*[<\"]epoxy/)");
  int scanned = 0;
  for (const char* module : {"io", "surfaces", "render", "ui", "shaders", "app"}) {
    for (const auto& entry : fs::recursive_directory_iterator(root / module)) {
      auto ext = entry.path().extension().string();
      if (!entry.is_regular_file() || (ext != ".h" && ext != ".cpp")) continue;
      const std::string rel = fs::relative(entry.path(), root).string();
      const std::string mod = moduleOf(rel);
      std::ifstream in(entry.path());
      std::string line;
      while (std::getline(in, line)) {
        const bool glfwHere = std::regex_search(line, glfw), imguiHere = std::regex_search(line, imgui),
                   epoxyHere = std::regex_search(line, epoxy);
        EXPECT_FALSE(glfwHere && mod != "app/viewer") << rel << ": " << line;
        EXPECT_FALSE(imguiHere && mod == "ui/session") << rel << ": " << line;
        EXPECT_FALSE(epoxyHere && (mod == "ui/session" || mod == "ui/panels")) << rel << ": " << line;
      }
      ++scanned;
    }
  }
  EXPECT_GT(scanned, 50);
}
