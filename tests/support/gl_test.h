// SPDX-License-Identifier: GPL-3.0-or-later
// GL test support: one headless EGL context per test process. DTF_GL_TEST_SETUP() at the start of a test
// makes the context current, or skips the test when none can be made (fails instead when
// DTF_REQUIRE_GL=1, as CI sets). GlTest fixtures check the GL debug output after each test: misuse
// reported at high or medium severity fails the test (driver performance hints do not).
#pragma once

#include "support/orientation_histogram.h"
#include "support/test_env.h"

#include "io/model/error.h"
#include "render/gl_context.h"
#include "render/gl_objects.h"

#include "io/model/image.h"

#include <cmath>
#include <gtest/gtest.h>
#include <vector>

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

// Textures from CPU arrays, readback to floats, and the image structure tensor that measures thread
// orientation.
namespace dtf::test {

inline render::Texture textureFrom(GLenum internalFormat, GLenum format, int w, int h, const std::vector<float>& data) {
  render::Texture t = render::Texture::create2D(internalFormat, w, h);
  t.setFilter(GL_NEAREST, GL_NEAREST);
  glTextureSubImage2D(t.id(), 0, 0, 0, w, h, format, GL_FLOAT, data.data());
  return t;
}

// All texels as floats, `channels` per texel (GL row order: row 0 at the bottom).
inline std::vector<float> readTexture(const render::Texture& t, int channels) {
  GLenum format = channels == 1 ? GL_RED : channels == 2 ? GL_RG : channels == 3 ? GL_RGB : GL_RGBA;
  std::vector<float> out(static_cast<std::size_t>(t.width()) * t.height() * channels);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glGetTextureImage(t.id(), 0, format, GL_FLOAT, static_cast<GLsizei>(out.size() * sizeof(float)), out.data());
  return out;
}

// Dominant line orientation (degrees in [0, 180), counter-clockwise from image +x with y UP) of the
// luminance of `img` inside [x0, x1) x [y0, y1) (image rows, row 0 at top), from the structure tensor:
// lines run perpendicular to the dominant gradient. `coherence` in [0, 1] says how strongly oriented.
inline double dominantOrientation(const Image& img, int x0, int y0, int x1, int y1, double* coherence = nullptr) {
  auto lum = [&](int x, int y) {
    const auto* p = img.pixel(x, y);
    return 0.299 * p[0] + 0.587 * p[1] + 0.114 * p[2];
  };
  double jxx = 0, jxy = 0, jyy = 0;
  for (int y = y0 + 1; y < y1 - 1; ++y)
    for (int x = x0 + 1; x < x1 - 1; ++x) {
      double gx = 0.5 * (lum(x + 1, y) - lum(x - 1, y));
      double gy = -0.5 * (lum(x, y + 1) - lum(x, y - 1)); // y up
      jxx += gx * gx;
      jxy += gx * gy;
      jyy += gy * gy;
    }
  double gradAngle = 0.5 * std::atan2(2 * jxy, jxx - jyy);
  if (coherence) {
    double tr = jxx + jyy, det = jxx * jyy - jxy * jxy;
    double disc = std::sqrt(std::max(0.0, tr * tr / 4 - det));
    double l1 = tr / 2 + disc, l2 = tr / 2 - disc;
    *coherence = l1 + l2 > 0 ? (l1 - l2) / (l1 + l2) : 0;
  }
  double deg = gradAngle * 180.0 / M_PI + 90.0;
  deg = std::fmod(deg + 360.0, 180.0);
  return deg;
}


} // namespace dtf::test
