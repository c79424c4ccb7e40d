// SPDX-License-Identifier: GPL-3.0-or-later
// The projection's vectors target as the advection reads it, on the CPU: v1.xy as snorm16 (.x), v2.xy as
// snorm10 and beta as unorm12 (.y), the layout of packVectors in shaders/common/projection_pixel.glsl; and
// the three-field layout (the projection's vectors3 target, RGBA32UI): the same texel in .xy, the third
// population's direction, snorm16 v3.xy, in .z.
#pragma once

#include "render/gl_objects.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

namespace dtf::test {

// GLSL's packSnorm2x16 and one half of unpackSnorm2x16.
inline std::uint32_t packSnorm2x16(float x, float y) {
  auto q = [](float v) {
    return static_cast<std::uint32_t>(static_cast<std::uint16_t>(
        static_cast<std::int16_t>(std::lround(std::clamp(v, -1.0f, 1.0f) * 32767.0f))));
  };
  return q(x) | (q(y) << 16);
}
inline float unpackSnorm16(std::uint32_t bits) {
  return std::max(static_cast<float>(static_cast<std::int16_t>(static_cast<std::uint16_t>(bits))) / 32767.0f,
                  -1.0f);
}

inline std::array<std::uint32_t, 2> packVectorTexel(float v1x, float v1y, float v2x, float v2y, float beta) {
  auto q10 = [](float v) {
    return static_cast<std::uint32_t>(std::lround(std::clamp(v, -1.0f, 1.0f) * 511.0f)) & 0x3FFu;
  };
  const auto b = static_cast<std::uint32_t>(std::lround(std::clamp(beta, 0.0f, 1.0f) * 4095.0f));
  return {packSnorm2x16(v1x, v1y), q10(v2x) | (q10(v2y) << 10) | (b << 20)};
}

// v1.x, v1.y, v2.x, v2.y, beta of one texel.
inline std::array<float, 5> unpackVectorTexel(std::uint32_t x, std::uint32_t y) {
  auto s10 = [](std::uint32_t bits) {
    const int v = static_cast<int>(bits & 0x3FFu);
    return static_cast<float>(v >= 512 ? v - 1024 : v) / 511.0f;
  };
  return {unpackSnorm16(x), unpackSnorm16(x >> 16), s10(y), s10(y >> 10),
          static_cast<float>(y >> 20) / 4095.0f};
}

// The texels of an integer texture of 2 (RG32UI: the vectors) or 4 (RGBA32UI: vectors3, the fibre target)
// components, `components` per pixel.
inline std::vector<std::uint32_t> readUintTexels(const render::Texture& t, int components) {
  std::vector<std::uint32_t> raw(static_cast<std::size_t>(t.width()) * t.height() * components);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glGetTextureImage(t.id(), 0, components == 2 ? GL_RG_INTEGER : GL_RGBA_INTEGER, GL_UNSIGNED_INT,
                    static_cast<GLsizei>(raw.size() * 4), raw.data());
  return raw;
}

// The directions as floats, v1.x, v1.y, v2.x, v2.y per pixel.
inline std::vector<float> readVectors(const render::Texture& t) {
  const auto raw = readUintTexels(t, 2);
  std::vector<float> v(raw.size() * 2);
  for (std::size_t i = 0; i < raw.size() / 2; ++i) {
    const auto u = unpackVectorTexel(raw[i * 2], raw[i * 2 + 1]);
    std::copy(u.begin(), u.begin() + 4, v.begin() + static_cast<std::ptrdiff_t>(i * 4));
  }
  return v;
}

// Beta as the iterations read it, per pixel.
inline std::vector<float> readVectorBeta(const render::Texture& t) {
  const auto raw = readUintTexels(t, 2);
  std::vector<float> b(raw.size() / 2);
  for (std::size_t i = 0; i < b.size(); ++i)
    b[i] = unpackVectorTexel(raw[i * 2], raw[i * 2 + 1])[4];
  return b;
}

// A vectors texture from v1.x, v1.y, v2.x, v2.y per pixel (max-norm scaled) and beta per pixel.
inline render::Texture vectorTexture(const std::vector<float>& v, const std::vector<float>& beta, int w,
                                     int h) {
  std::vector<std::uint32_t> raw(static_cast<std::size_t>(w) * h * 2, 0u);
  for (std::size_t i = 0; i < raw.size() / 2; ++i) {
    const auto q = packVectorTexel(v[i * 4], v[i * 4 + 1], v[i * 4 + 2], v[i * 4 + 3], beta[i]);
    raw[i * 2] = q[0];
    raw[i * 2 + 1] = q[1];
  }
  render::Texture t = render::Texture::create2D(GL_RG32UI, w, h);
  t.setFilter(GL_NEAREST, GL_NEAREST);
  glTextureSubImage2D(t.id(), 0, 0, 0, w, h, GL_RG_INTEGER, GL_UNSIGNED_INT, raw.data());
  return t;
}

// A three-field vectors texture (the projection's vectors3 target, RGBA32UI): the vectors texel of v1.x,
// v1.y, v2.x, v2.y and beta per pixel in .xy, and v3.x, v3.y per pixel in .z.
inline render::Texture vectors3Texture(const std::vector<float>& v, const std::vector<float>& beta,
                                       const std::vector<float>& v3, int w, int h) {
  std::vector<std::uint32_t> raw(static_cast<std::size_t>(w) * h * 4, 0u);
  for (std::size_t i = 0; i < raw.size() / 4; ++i) {
    const auto q = packVectorTexel(v[i * 4], v[i * 4 + 1], v[i * 4 + 2], v[i * 4 + 3], beta[i]);
    raw[i * 4] = q[0];
    raw[i * 4 + 1] = q[1];
    raw[i * 4 + 2] = packSnorm2x16(v3[i * 2], v3[i * 2 + 1]);
  }
  render::Texture t = render::Texture::create2D(GL_RGBA32UI, w, h);
  t.setFilter(GL_NEAREST, GL_NEAREST);
  glTextureSubImage2D(t.id(), 0, 0, 0, w, h, GL_RGBA_INTEGER, GL_UNSIGNED_INT, raw.data());
  return t;
}

} // namespace dtf::test
