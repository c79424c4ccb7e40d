// SPDX-License-Identifier: GPL-3.0-or-later
// Compile logs name the embedded file and line whichever driver wrote them (no GL context needed).
#include "render/shader_program.h"

#include <gtest/gtest.h>

using dtf::render::mapShaderLog;

namespace {
const std::vector<std::string> kFiles = {"test/broken.frag", "common/eigen.glsl"};
}

TEST(ShaderLog, MesaLocationsNameTheFile) {
  const std::string mapped =
      mapShaderLog("0:6(3): error: `undefinedThing' undeclared\n1:40(9): warning: unused\n", kFiles);
  EXPECT_NE(mapped.find("test/broken.frag:6(3): error: `undefinedThing' undeclared"), std::string::npos) << mapped;
  EXPECT_NE(mapped.find("\ncommon/eigen.glsl:40(9): warning"), std::string::npos) << mapped;
  EXPECT_NE(mapped.find("1 = common/eigen.glsl"), std::string::npos) << mapped;
}

TEST(ShaderLog, NvidiaLocationsNameTheFile) {
  const std::string mapped = mapShaderLog(
      "0(6) : error C1503: undefined variable \"undefinedThing\"\n1(40) : warning C7050: unused\n", kFiles);
  EXPECT_NE(mapped.find("test/broken.frag:6 : error C1503"), std::string::npos) << mapped;
  EXPECT_NE(mapped.find("\ncommon/eigen.glsl:40 : warning C7050"), std::string::npos) << mapped;
}

TEST(ShaderLog, UnknownIndicesAndOtherTextStayAsTheyAre) {
  const std::string log = "7(2) : error C0000: syntax error\nlinker: 3 errors (0:1 is not a location here)\n";
  const std::string mapped = mapShaderLog(log, kFiles);
  EXPECT_EQ(mapped.rfind("7:2 : error C0000: syntax error\nlinker: 3 errors (0:1 is not a location here)\n", 0), 0u)
      << mapped;
}
