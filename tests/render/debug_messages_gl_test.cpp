// SPDX-License-Identifier: GPL-3.0-or-later
// GL debug output: misuse is collected (checkGl turns it into an error), driver hints are not.
#include "render/gl_context.h"
#include "support/gl_test.h"

#include <string>

using namespace dtf::render;

namespace {

class DebugMessagesTest : public GlTest {};

void insert(GLenum type, GLenum severity, const std::string& text) {
  glDebugMessageInsert(GL_DEBUG_SOURCE_APPLICATION, type, 7, severity, static_cast<GLsizei>(text.size()),
                       text.c_str());
}

} // namespace

TEST_F(DebugMessagesTest, PerformanceHintsAreNotErrors) {
  takeDebugMessages();
  insert(GL_DEBUG_TYPE_PERFORMANCE, GL_DEBUG_SEVERITY_MEDIUM, "shader recompiled based on GL state");
  insert(GL_DEBUG_TYPE_OTHER, GL_DEBUG_SEVERITY_MEDIUM, "buffer placed in video memory");
  insert(GL_DEBUG_TYPE_PORTABILITY, GL_DEBUG_SEVERITY_HIGH, "not portable");
  glFinish();
  EXPECT_TRUE(takeDebugMessages().empty());
}

TEST_F(DebugMessagesTest, MisuseIsCollected) {
  takeDebugMessages();
  insert(GL_DEBUG_TYPE_ERROR, GL_DEBUG_SEVERITY_HIGH, "invalid operation");
  insert(GL_DEBUG_TYPE_UNDEFINED_BEHAVIOR, GL_DEBUG_SEVERITY_MEDIUM, "undefined");
  insert(GL_DEBUG_TYPE_ERROR, GL_DEBUG_SEVERITY_LOW, "low severity is ignored");
  glFinish();
  auto messages = takeDebugMessages();
  ASSERT_EQ(messages.size(), 2u);
  EXPECT_NE(messages[0].find("invalid operation"), std::string::npos);
  EXPECT_NE(messages[1].find("undefined"), std::string::npos);
}
