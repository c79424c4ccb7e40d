// SPDX-License-Identifier: GPL-3.0-or-later
// The viewer in a real window under Xvfb, driven by a script, and the image measures its tests share.
#pragma once

#include "io/model/image.h"
#include "support/cli.h"
#include "support/test_env.h"

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <gtest/gtest.h>
#include <string>

namespace dtf::test {

inline bool haveXvfb() {
  return std::system("command -v xvfb-run >/dev/null 2>&1") == 0;
}

// Runs `dtfabric view ARGS --size 640x480 --script scratch/script.txt` under Xvfb. The exit code is
// dtfabric's, written by a wrapper: xvfb-run's own can be 5 when removing its temporary folder fails
// beside parallel runs, after dtfabric exited normally.
inline CliResult runViewerScript(const std::filesystem::path& scratch, const std::string& script,
                                 const std::string& args = "") {
  const std::filesystem::path scriptFile = scratch / "script.txt", runner = scratch / "run.sh",
                              rcFile = scratch / "rc.txt";
  std::ofstream(scriptFile) << script;
  const auto outFile = scratch / "stdout.txt", errFile = scratch / "stderr.txt",
             xvfbErr = scratch / "xvfb.txt";
  std::filesystem::remove(rcFile);
  std::ofstream(runner) << "'" << DTF_EXE << "' view " << args << " --size 640x480 --script '"
                        << scriptFile.string() << "' >'" << outFile.string() << "' 2>'" << errFile.string()
                        << "'\necho $? >'" << rcFile.string() << "'\n";
  const std::string cmd = "timeout 180 xvfb-run -a -s '-screen 0 1280x1024x24' sh '" + runner.string() +
                          "' >/dev/null 2>'" + xvfbErr.string() + "'";
  const int status = std::system(cmd.c_str());
  CliResult r;
  r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : 128;
  const std::string rc = readText(rcFile);
  if (!rc.empty()) r.exitCode = std::atoi(rc.c_str());
  r.out = readText(outFile);
  r.err = readText(errFile) + readText(xvfbErr);
  return r;
}

// Fraction of pixels in which some channel differs by more than 40 (a failure when the sizes differ).
inline double differingFraction(const Image& a, const Image& b) {
  if (a.width != b.width || a.height != b.height || a.rgba.empty()) {
    ADD_FAILURE() << "compared images of " << a.width << "x" << a.height << " and " << b.width << "x"
                  << b.height;
    return 1;
  }
  std::size_t n = 0;
  for (std::size_t i = 0; i < a.rgba.size(); i += 4)
    for (int c = 0; c < 3; ++c)
      if (std::abs(int(a.rgba[i + c]) - int(b.rgba[i + c])) > 40) {
        ++n;
        break;
      }
  return double(n) / double(a.rgba.size() / 4);
}

// Changed pixels of `with` against `without` that look like a tract: one saturated DEC channel clearly
// above the others.
inline std::size_t tractPixels(const Image& with, const Image& without) {
  std::size_t n = 0;
  for (int y = 0; y < with.height; ++y)
    for (int x = 0; x < with.width; ++x) {
      const auto *p = with.pixel(x, y), *q = without.pixel(x, y);
      if (std::abs(p[0] - q[0]) + std::abs(p[1] - q[1]) + std::abs(p[2] - q[2]) < 60) continue;
      const int hi = std::max({p[0], p[1], p[2]}), lo = std::min({p[0], p[1], p[2]});
      n += hi > 120 && hi - lo > 80;
    }
  return n;
}

// Pixels where the left and right halves of a split image differ (summed RGB difference above 60).
inline std::size_t paneDifference(const Image& split) {
  std::size_t n = 0;
  for (int y = 0; y < split.height; ++y)
    for (int x = 0; x < split.width / 2; ++x) {
      const auto *l = split.pixel(x, y), *r = split.pixel(x + split.width / 2, y);
      n += std::abs(l[0] - r[0]) + std::abs(l[1] - r[1]) + std::abs(l[2] - r[2]) > 60;
    }
  return n;
}

} // namespace dtf::test

// Skips a window test without xvfb-run, or fails when DTF_REQUIRE_GL=1.
#define DTF_XVFB_SETUP()                                                                                     \
  do {                                                                                                       \
    if (!dtf::test::haveXvfb()) {                                                                            \
      if (dtf::test::envFlag("DTF_REQUIRE_GL")) FAIL() << "xvfb-run is missing";                             \
      GTEST_SKIP() << "xvfb-run is missing";                                                                 \
    }                                                                                                        \
  } while (0)

// Exit code 3 from GLFW: no GL 4.5 window in the Xvfb display (e.g. no GLX); skipped unless DTF_REQUIRE_GL=1.
// Other GL failures (exit 3 for texture limits) are the tests' to judge.
#define DTF_SKIP_WITHOUT_WINDOW_GL(result)                                                                   \
  do {                                                                                                       \
    if ((result).exitCode == 3 && (result).err.find("GLFW") != std::string::npos &&                          \
        !dtf::test::envFlag("DTF_REQUIRE_GL"))                                                               \
      GTEST_SKIP() << "no GL window: " << (result).err;                                                      \
  } while (0)
