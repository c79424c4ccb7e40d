// SPDX-License-Identifier: GPL-3.0-or-later
// Test helpers: where the shared real data lives, and skip-or-fail rules. A test that needs a resource
// skips when it is missing, unless the matching DTF_REQUIRE_* variable is set (CI sets both), then fails.
#pragma once

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

namespace dtf::test {

inline bool envFlag(const char* name) {
  const char* v = std::getenv(name);
  return v && *v && std::string(v) != "0";
}

// ../shared/data beside the checkout, or $DTF_SHARED_DATA.
inline std::filesystem::path sharedDataDir() {
  if (const char* v = std::getenv("DTF_SHARED_DATA"); v && *v) return v;
  return std::filesystem::path(DTF_SOURCE_DIR) / ".." / "shared" / "data";
}

inline std::filesystem::path sourceDir() { return DTF_SOURCE_DIR; }
inline std::filesystem::path binaryDir() { return DTF_BINARY_DIR; }

// A scratch directory unique to the running test, created empty.
inline std::filesystem::path scratchDir() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  auto dir = std::filesystem::path(DTF_BINARY_DIR) / "test_scratch" /
             (std::string(info->test_suite_name()) + "." + info->name());
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

} // namespace dtf::test

// Returns the path of a shared data file, or skips/fails the test when it is missing.
#define DTF_SHARED_FILE(var, relpath)                                                                       \
  const std::filesystem::path var = dtf::test::sharedDataDir() / (relpath);                                \
  if (!std::filesystem::exists(var)) {                                                                      \
    if (dtf::test::envFlag("DTF_REQUIRE_SHARED_DATA")) FAIL() << "shared data missing: " << var;             \
    GTEST_SKIP() << "shared data missing: " << var;                                                         \
  }
