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
    {"ui", {"render", "io/model"}},
    {"app", {"io/model", "io", "shaders", "surfaces", "render", "ui"}},
};

std::string moduleOf(const std::string& rel) {
  if (rel.rfind("io/model/", 0) == 0) return "io/model";
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
