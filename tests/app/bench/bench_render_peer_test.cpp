// SPDX-License-Identifier: GPL-3.0-or-later
// The ParaView peer of `bench render` without ParaView: the generated pvbatch script carries the settings
// (paths quoted for Python), its output is parsed into figures or a failure note, and the vector it is fed
// is the principal in-surface eigenvector of the tensor.
#include "app/bench/bench.h"

#include <cmath>
#include <gtest/gtest.h>

using namespace dtf;

TEST(BenchRenderPeer, ScriptCarriesTheSettings) {
  app::RenderPeerOptions o;
  o.width = 320;
  o.height = 200;
  o.frames = 4;
  o.pngPath = "/tmp/it's\\here.png";
  const std::string s = app::renderPeerScript("/tmp/x/mesh.vtk", o);
  EXPECT_NE(s.find("MESH = '/tmp/x/mesh.vtk'\n"), std::string::npos) << s;
  EXPECT_NE(s.find("WIDTH, HEIGHT = 320, 200\n"), std::string::npos);
  EXPECT_NE(s.find("FRAMES = 4\n"), std::string::npos);
  EXPECT_NE(s.find("PNG = '/tmp/it\\'s\\\\here.png'\n"), std::string::npos)
      << "quotes and backslashes escaped";
  EXPECT_NE(s.find("'Surface LIC'"), std::string::npos);
  EXPECT_NE(s.find("NumberOfSteps = 1"), std::string::npos);
  EXPECT_NE(s.find("camera.Azimuth"), std::string::npos) << "the camera moves between timed frames";
  o.pngPath.clear();
  EXPECT_NE(app::renderPeerScript("m.vtk", o).find("PNG = ''\n"), std::string::npos);
}

TEST(BenchRenderPeer, ParsesFiguresAndFailures) {
  const std::string good =
      "noise\nDTF_PEER version 5.11.0\nDTF_PEER coverage 0.744\nDTF_PEER pixels 1024x768\n"
      "DTF_PEER surface_ms 59.25\nDTF_PEER surface_cpu_ms 80.5\nDTF_PEER lic_default_steps 40\nDTF_PEER "
      "lic_default_ms "
      "1900.5\nDTF_PEER png /tmp/a.png\nDTF_PEER lic_one_step_ms 201.00\n";
  app::RenderPeerResult r = app::parseRenderPeerOutput(good);
  EXPECT_TRUE(r.ran);
  EXPECT_EQ(r.name, "ParaView 5.11.0 Surface LIC");
  EXPECT_DOUBLE_EQ(r.surfaceMs, 59.25);
  EXPECT_DOUBLE_EQ(r.licDefaultMs, 1900.5);
  EXPECT_DOUBLE_EQ(r.licOneStepMs, 201.0);
  EXPECT_DOUBLE_EQ(r.surfaceCpuMs, 80.5);
  EXPECT_LT(r.licDefaultCpuMs, 0) << "not reported: -1";
  EXPECT_DOUBLE_EQ(r.coverage, 0.744);
  EXPECT_EQ(r.licDefaultSteps, 40);
  EXPECT_EQ(r.png, "/tmp/a.png");
  EXPECT_EQ(r.pixels, "1024x768");
  EXPECT_TRUE(r.note.empty());

  // A timing missing (the script died in the middle) is no result.
  r = app::parseRenderPeerOutput(
      "DTF_PEER version 5.11.0\nDTF_PEER surface_ms 59\nDTF_PEER lic_default_ms x\n");
  EXPECT_FALSE(r.ran);
  EXPECT_FALSE(r.note.empty());
  r = app::parseRenderPeerOutput(
      "DTF_PEER error cannot import paraview.simple (No module named 'paraview')\n");
  EXPECT_FALSE(r.ran);
  EXPECT_EQ(r.note, "cannot import paraview.simple (No module named 'paraview')");
  EXPECT_FALSE(app::parseRenderPeerOutput("").ran);
}

TEST(BenchRenderPeer, VectorIsThePrincipalInSurfaceEigenvector) {
  const glm::dvec3 n = glm::normalize(glm::dvec3(0.2, -0.3, 1.0));
  // A linear tensor along d: the projected principal direction is d's tangential part.
  const glm::dvec3 d = glm::normalize(glm::dvec3(1.0, 2.0, 0.5));
  const glm::dmat3 t = 1.5 * glm::outerProduct(d, d) + 0.2 * glm::dmat3(1.0);
  const glm::dvec3 e = app::principalInSurfaceDirection(t, n);
  const glm::dvec3 expect = glm::normalize(d - glm::dot(d, n) * n);
  EXPECT_NEAR(glm::length(e), 1.0, 1e-12);
  EXPECT_NEAR(std::abs(glm::dot(e, expect)), 1.0, 1e-9);
  EXPECT_NEAR(glm::dot(e, n), 0.0, 1e-12);
  // The larger in-plane eigenvalue wins even when the out-of-plane one is larger still or all are negative.
  const glm::dmat3 h = glm::dmat3(glm::dvec3(-3, 0, 0), glm::dvec3(0, -1, 0), glm::dvec3(0, 0, 5));
  EXPECT_NEAR(std::abs(app::principalInSurfaceDirection(h, {0, 0, 1}).y), 1.0, 1e-12);
  EXPECT_NEAR(std::abs(app::principalInSurfaceDirection(h, {1, 0, 0}).z), 1.0, 1e-12);
  // Isotropic: any unit tangent, never NaN.
  const glm::dvec3 iso = app::principalInSurfaceDirection(glm::dmat3(2.0), {1, 0, 0});
  EXPECT_NEAR(glm::length(iso), 1.0, 1e-12);
  EXPECT_NEAR(iso.x, 0.0, 1e-12);
}
