// SPDX-License-Identifier: GPL-3.0-or-later
// Supersampled stills: the right size, and the same fabric as the plain render (noise cell, step and
// silhouette scale with N), where asking for a larger image and shrinking it gives finer threads. Measure:
// the correlation of the luminance with the 1x render's, inside the data.
#include "support/gl_test.h"
#include "support/test_env.h"

#include "ui/session/render_job.h"

#include <cmath>
#include <cstdio>

using namespace dtf;

namespace {

class Supersample : public GlTest {};

Image box(const Image& big, int n) {
  Image out(big.width / n, big.height / n);
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x)
      for (int c = 0; c < 4; ++c) {
        int s = 0;
        for (int dy = 0; dy < n; ++dy)
          for (int dx = 0; dx < n; ++dx)
            s += big.pixel(x * n + dx, y * n + dy)[c];
        out.pixel(x, y)[c] = static_cast<std::uint8_t>((s + n * n / 2) / (n * n));
      }
  return out;
}

// Pearson correlation of the luminance of a and b over the pixels lit in both (inside the data).
double correlation(const Image& a, const Image& b) {
  double sa = 0, sb = 0, saa = 0, sbb = 0, sab = 0, n = 0;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x) {
      const auto *p = a.pixel(x, y), *q = b.pixel(x, y);
      const double la = p[0] + p[1] + p[2], lb = q[0] + q[1] + q[2];
      if (la < 30 || lb < 30) continue;
      sa += la, sb += lb, saa += la * la, sbb += lb * lb, sab += la * lb, ++n;
    }
  const double cov = sab / n - sa / n * sb / n;
  return cov / std::sqrt((saa / n - sa / n * sa / n) * (sbb / n - sb / n * sb / n));
}

} // namespace

TEST_F(Supersample, TheSupersampledStillIsTheSameFabricAntiAliased) {
  DTF_SHARED_FILE(tensor, "iu_prisma_dwi/derived/dti_tensor.nii.gz");
  session::RenderRequest r;
  r.input = tensor.string();
  r.tensorOptions.quiet = true;
  r.surface = session::parseSurfaceSpec("slice=axial:20");
  r.width = r.height = 256;
  r.params.look = render::Look::Plain; // the fabric everywhere in the data
  r.params.silhouette = false;
  r.furniture = {false, false, false};
  const Image one = session::runRender(r).image;

  r.supersample = 2;
  const Image two = session::runRender(r).image;
  ASSERT_EQ(two.width, 256);
  ASSERT_EQ(two.height, 256);

  r.supersample = 1;
  r.width = r.height = 512; // a larger image: finer threads, as before supersampling
  const Image larger = box(session::runRender(r).image, 2);

  const double cSuper = correlation(one, two), cLarger = correlation(one, larger);
  std::printf("luminance correlation with the 1x render: supersampled 2x %.3f, 512 px shrunk %.3f\n", cSuper,
              cLarger);
  EXPECT_GT(cSuper, 0.85);
  EXPECT_LT(cSuper, 0.999); // filtered from 4x the pixels, not the 1x image again
  EXPECT_GT(cSuper, cLarger + 0.3);
}

TEST_F(Supersample, ALargerImageShowsTheSameFabricSharper) {
  DTF_SHARED_FILE(tensor, "iu_prisma_dwi/derived/dti_tensor.nii.gz");
  session::RenderRequest r;
  r.input = tensor.string();
  r.tensorOptions.quiet = true;
  r.surface = session::parseSurfaceSpec("slice=axial:20");
  r.width = r.height = 768;
  r.params.look = render::Look::Plain;
  r.params.silhouette = false;
  r.furniture = {false, false, false};
  const Image base = session::runRender(r).image;
  r.width = r.height = 1536; // above 768: the noise cell and step scale with the size
  const Image big = session::runRender(r).image;
  ASSERT_EQ(big.width, 1536);
  const double c = correlation(base, box(big, 2));
  std::printf("luminance correlation of the 768 px render with the 1536 px one shrunk: %.3f\n", c);
  EXPECT_GT(c, 0.85);
}
