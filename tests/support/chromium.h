// SPDX-License-Identifier: GPL-3.0-or-later
// Headless Chromium for tests of the static pages (the BIDS group report, the web page): a page's self-check
// read from --dump-dom, and screenshots.
#pragma once

#include "support/cli.h"
#include "support/test_env.h"

#include <cstdlib>
#include <filesystem>
#include <gtest/gtest.h>
#include <regex>
#include <string>
#include <utility>
#include <vector>

// Tools the tests run: skipped when absent, failed when DTF_REQUIRE_TOOLS is set (CI installs them).
#define DTF_REQUIRE_TOOL(name)                                                                               \
  if (std::system("command -v " name " >/dev/null 2>&1") != 0) {                                             \
    if (dtf::test::envFlag("DTF_REQUIRE_TOOLS")) FAIL() << name " is not installed (.ci/setup installs it)"; \
    GTEST_SKIP() << name " is not installed (Debian package " name "; CI requires it)";                      \
  }

namespace dtf::test {

inline std::string shellQuoted(const std::filesystem::path& p) {
  return "'" + p.string() + "'";
}

// The JSON a page writes into <pre id="dtf-selfcheck"> when opened from file:// with `hash` (e.g.
// "selfcheck"), unescaped; "" when it wrote none. `log` receives Chromium's stderr (console messages). With
// `netLog`, Chromium records its network events there (--log-net-log).
inline std::string chromiumSelfCheck(const std::filesystem::path& html, const std::filesystem::path& scratch,
                                     std::string& log, const std::string& hash = "selfcheck",
                                     const std::filesystem::path& netLog = {}) {
  const std::filesystem::path dom = scratch / "dom.html", err = scratch / "chromium.log";
  const std::string cmd = "chromium --headless --no-sandbox --disable-gpu --enable-logging=stderr --v=0 " +
                          (netLog.empty() ? std::string() : "--log-net-log=" + shellQuoted(netLog) + " ") +
                          "--virtual-time-budget=20000 --dump-dom 'file://" + html.string() + "#" + hash +
                          "' >" + shellQuoted(dom) + " 2>" + shellQuoted(err);
  EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
  log = readText(err);
  std::string text = readText(dom);
  std::smatch m;
  if (!std::regex_search(text, m, std::regex("<pre id=\"dtf-selfcheck\">([^<]*)</pre>"))) return "";
  std::string json = m[1];
  for (const auto& [from, to] : std::vector<std::pair<std::string, std::string>>{
           {"&quot;", "\""}, {"&lt;", "<"}, {"&gt;", ">"}, {"&amp;", "&"}}) {
    for (std::size_t p = json.find(from); p != std::string::npos; p = json.find(from, p + to.size()))
      json.replace(p, from.size(), to);
  }
  return json;
}

// A screenshot of `url` (file://... with its hash) at width x height; true when Chromium exited cleanly.
inline bool chromiumScreenshot(const std::string& url, const std::filesystem::path& png, int width,
                               int height, int budgetMs = 10000) {
  const std::string cmd = "chromium --headless --no-sandbox --disable-gpu --hide-scrollbars --window-size=" +
                          std::to_string(width) + "," + std::to_string(height) +
                          " --virtual-time-budget=" + std::to_string(budgetMs) +
                          " --screenshot=" + shellQuoted(png) + " '" + url + "' >/dev/null 2>&1";
  return std::system(cmd.c_str()) == 0;
}

} // namespace dtf::test
