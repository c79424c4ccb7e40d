// SPDX-License-Identifier: GPL-3.0-or-later
// One version everywhere: `project(dtfabric VERSION X.Y.Z)` in CMakeLists.txt is what `dtfabric --version`
// prints, what the Debian package's changelog (and so the package) names, and the newest numbered release
// of CHANGELOG.md. (The Python module's dtfabric.__version__ is checked in tests/python/test_version.py.)
#include "support/cli.h"
#include "support/test_env.h"

#include <gtest/gtest.h>
#include <regex>

namespace {

// X.Y.Z of `project(dtfabric VERSION X.Y.Z ...)` in the top CMakeLists.txt; "" when there is none.
std::string projectVersion() {
  const std::string text = dtf::test::readText(dtf::test::sourceDir() / "CMakeLists.txt");
  std::smatch m;
  static const std::regex re(R"(\nproject\(dtfabric VERSION ([0-9]+\.[0-9]+\.[0-9]+)[ )])");
  return std::regex_search(text, m, re) ? m[1].str() : "";
}

// The versions of CHANGELOG.md's `## [X.Y.Z]` headings, newest (topmost) first.
std::vector<std::string> changelogVersions() {
  const std::string text = dtf::test::readText(dtf::test::sourceDir() / "CHANGELOG.md");
  static const std::regex re(R"((^|\n)## \[([0-9]+\.[0-9]+\.[0-9]+)\])");
  std::vector<std::string> out;
  for (auto it = std::sregex_iterator(text.begin(), text.end(), re); it != std::sregex_iterator(); ++it)
    out.push_back((*it)[2].str());
  return out;
}

std::tuple<int, int, int> parts(const std::string& v) {
  int a = 0, b = 0, c = 0;
  std::sscanf(v.c_str(), "%d.%d.%d", &a, &b, &c);
  return {a, b, c};
}

} // namespace

TEST(Version, TheCommandPrintsTheProjectVersion) {
  const std::string version = projectVersion();
  ASSERT_FALSE(version.empty()) << "no `project(dtfabric VERSION X.Y.Z` in CMakeLists.txt";
  const auto r = dtf::test::runDtfabric("--version", dtf::test::scratchDir());
  EXPECT_EQ(r.exitCode, 0) << r.err;
  EXPECT_EQ(r.out, "dtfabric " + version + "\n");
  EXPECT_EQ(r.err, "");
}

TEST(Version, TheChangelogsNewestReleaseIsTheProjectVersion) {
  const std::string version = projectVersion();
  const auto versions = changelogVersions();
  ASSERT_FALSE(versions.empty()) << "CHANGELOG.md has no `## [X.Y.Z]` heading";
  EXPECT_EQ(versions.front(), version) << "CHANGELOG.md's newest release is not the project's version";
  EXPECT_NE(std::find(versions.begin(), versions.end(), "0.1.0"), versions.end()) << "0.1.0 is missing";
  for (size_t i = 1; i < versions.size(); ++i)
    EXPECT_GT(parts(versions[i - 1]), parts(versions[i])) << versions[i - 1] << " above " << versions[i];
}

// The package's version is CPack's, the project's; its changelog's first entry must name the same.
TEST(Version, TheDebianChangelogNamesTheProjectVersion) {
  const auto changelog = dtf::test::binaryDir() / "debian" / "changelog";
  ASSERT_TRUE(std::filesystem::exists(changelog)) << changelog << " was not configured";
  const std::string text = dtf::test::readText(changelog);
  EXPECT_EQ(text.rfind("dtfabric (" + projectVersion() + ") unstable; urgency=medium\n", 0), 0u)
      << text.substr(0, 80);
}
