// GL test support: one headless EGL context per test process. DTF_GL_TEST_SETUP() at the start of a test
// makes the context current, or skips the test when none can be made (fails instead when
// DTF_REQUIRE_GL=1, as CI sets). GlTest fixtures check the GL debug output after each test: a high or
// medium severity message fails the test.
#pragma once

#include "support/test_env.h"

#include "io/model/error.h"
#include "render/gl_context.h"

#include <gtest/gtest.h>

namespace dtf::test {

// Returns an empty string when a context is current, else the reason it could not be made.
inline std::string ensureGlContext() {
  try {
    dtf::render::GlContext::headless();
    return {};
  } catch (const dtf::GlError& e) {
    return e.what();
  }
}

} // namespace dtf::test

#define DTF_GL_TEST_SETUP()                                                                                 \
  do {                                                                                                      \
    std::string why_ = dtf::test::ensureGlContext();                                                        \
    if (!why_.empty()) {                                                                                    \
      if (dtf::test::envFlag("DTF_REQUIRE_GL")) FAIL() << "no GL context: " << why_;                        \
      GTEST_SKIP() << "no GL context: " << why_;                                                            \
    }                                                                                                       \
    dtf::render::takeDebugMessages();                                                                       \
  } while (0)

// Fixture: sets up the context before and checks the debug output after every test.
class GlTest : public ::testing::Test {
protected:
  void SetUp() override { DTF_GL_TEST_SETUP(); }
  void TearDown() override {
    if (IsSkipped()) return;
    for (const auto& m : dtf::render::takeDebugMessages()) ADD_FAILURE() << "GL debug message: " << m;
  }
};
