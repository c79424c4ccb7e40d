// SPDX-License-Identifier: GPL-3.0-or-later
// The session library stands below the panels: dtf_session links neither dtf_ui, ImGui nor GLFW, directly or
// through any library it links, while dtf_ui links dtf_session (the actions and state it draws). Read from
// the build's own declarations (every CMakeLists.txt's add_library and target_link_libraries), so a new
// link anywhere below dtf_session is seen.
#include "support/test_env.h"

#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

// Target -> the targets and packages it links (all of PUBLIC, PRIVATE and INTERFACE).
std::map<std::string, std::set<std::string>> linkGraph() {
  std::map<std::string, std::set<std::string>> links;
  const std::regex call(R"(target_link_libraries\s*\(\s*([A-Za-z0-9_]+)([^)]*)\))");
  const fs::path root = dtf::test::sourceDir();
  for (const char* dir : {"io", "surfaces", "render", "shaders", "ui", "app"})
    for (const auto& entry : fs::recursive_directory_iterator(root / dir)) {
      if (entry.path().filename() != "CMakeLists.txt") continue;
      std::ifstream in(entry.path());
      std::stringstream text;
      text << in.rdbuf();
      const std::string s = text.str();
      for (std::sregex_iterator it(s.begin(), s.end(), call), end; it != end; ++it) {
        std::istringstream words((*it)[2].str());
        std::string w;
        while (words >> w)
          if (w != "PUBLIC" && w != "PRIVATE" && w != "INTERFACE") links[(*it)[1].str()].insert(w);
      }
    }
  return links;
}

std::set<std::string> closure(const std::map<std::string, std::set<std::string>>& links,
                              const std::string& from) {
  std::set<std::string> seen;
  std::vector<std::string> todo{from};
  while (!todo.empty()) {
    const std::string t = todo.back();
    todo.pop_back();
    auto it = links.find(t);
    if (it == links.end()) continue;
    for (const auto& next : it->second)
      if (seen.insert(next).second) todo.push_back(next);
  }
  return seen;
}

bool heavyUi(const std::string& target) {
  return target == "dtf_ui" || target == "dtf_viewer" || target.find("IMGUI") != std::string::npos ||
         target.find("imgui") != std::string::npos || target.find("glfw") != std::string::npos;
}

} // namespace

TEST(SessionLayering, TheSessionLibraryLinksNoPanelsImGuiOrWindow) {
  const auto links = linkGraph();
  ASSERT_TRUE(links.count("dtf_session")) << "no target_link_libraries(dtf_session ...) found";
  const std::set<std::string> below = closure(links, "dtf_session");
  EXPECT_TRUE(below.count("dtf_render")) << "the scan should see dtf_session's own links";
  for (const auto& t : below)
    EXPECT_FALSE(heavyUi(t)) << "dtf_session links " << t << " (directly or through a library it links)";
}

TEST(SessionLayering, ThePanelsLinkTheSessionLibraryForItsActionsAndState) {
  const auto links = linkGraph();
  const std::set<std::string> ui = closure(links, "dtf_ui");
  EXPECT_TRUE(ui.count("dtf_session"));
  EXPECT_FALSE(ui.count("glfw")) << "GLFW stays in the viewer";
  // The viewer links both: the window draws the panels over the session.
  const std::set<std::string> viewer = closure(links, "dtf_viewer");
  EXPECT_TRUE(viewer.count("dtf_ui"));
  EXPECT_TRUE(viewer.count("dtf_session"));
}

// No source of ui/session includes a panel, a front end, ImGui or GLFW (the include scan of layering_test.cpp
// per module; here the reason stated once more for the session's own files).
TEST(SessionLayering, SessionSourcesIncludeNoPanelsFrontEndsOrImGui) {
  const std::regex inc(R"(^\s*#\s*include\s*[<"](ui/panels/|app/|imgui|GLFW/))");
  int files = 0;
  for (const auto& entry : fs::directory_iterator(dtf::test::sourceDir() / "ui" / "session")) {
    const auto ext = entry.path().extension();
    if (ext != ".h" && ext != ".cpp") continue;
    std::ifstream in(entry.path());
    std::string line;
    while (std::getline(in, line))
      EXPECT_FALSE(std::regex_search(line, inc)) << entry.path() << ": " << line;
    ++files;
  }
  EXPECT_GT(files, 20);
}
