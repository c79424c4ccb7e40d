#include "render/noise.h"

#include "io/model/error.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <mutex>
#include <random>
#include <thread>
#include <tuple>

namespace dtf::render {

NoiseTile makeReactionDiffusion(const NoiseOptions& o) {
  if (o.size < 8 || o.size > 4096) throw UsageError("noise tile size must be in [8, 4096]");
  const int n = o.size;
  const std::size_t cells = static_cast<std::size_t>(n) * n;
  const float da = 0.125f, db = 0.031f, s = static_cast<float>(o.spotScale);
  // Turk 1991: a = b = 4 everywhere, beta = 12 +- 0.1 random; the instability of the uniform state grows
  // the spots. Single precision, rows with wrapped neighbours (periodic boundaries = seamless tile).
  std::mt19937 rng(o.seed);
  std::uniform_real_distribution<float> jitter(-0.1f, 0.1f);
  std::vector<float> a(cells, 4.0f), b(cells, 4.0f), beta(cells), na(cells), nb(cells);
  for (auto& v : beta) v = 12.0f + jitter(rng);
  auto rows = [&](int y0, int y1) {
    for (int y = y0; y < y1; ++y) {
      const float* ar = &a[static_cast<std::size_t>(y) * n];
      const float* br = &b[static_cast<std::size_t>(y) * n];
      const float* ad = &a[static_cast<std::size_t>((y + n - 1) % n) * n];
      const float* bd = &b[static_cast<std::size_t>((y + n - 1) % n) * n];
      const float* au = &a[static_cast<std::size_t>((y + 1) % n) * n];
      const float* bu = &b[static_cast<std::size_t>((y + 1) % n) * n];
      const float* betar = &beta[static_cast<std::size_t>(y) * n];
      float* nar = &na[static_cast<std::size_t>(y) * n];
      float* nbr = &nb[static_cast<std::size_t>(y) * n];
      auto cell = [&](int x, int xl, int xr) {
        float ai = ar[x], bi = br[x];
        float lapA = ar[xl] + ar[xr] + ad[x] + au[x] - 4.0f * ai;
        float lapB = br[xl] + br[xr] + bd[x] + bu[x] - 4.0f * bi;
        nar[x] = ai + s * (16.0f - ai * bi) + da * lapA;
        nbr[x] = std::max(0.0f, bi + s * (ai * bi - bi - betar[x]) + db * lapB);
      };
      cell(0, n - 1, 1);
      for (int x = 1; x < n - 1; ++x) cell(x, x - 1, x + 1);
      cell(n - 1, n - 2, 0);
    }
  };
  // Rows are independent within a step: split them over two threads (the result does not depend on it).
  for (int it = 0; it < o.iterations; ++it) {
    std::thread other(rows, n / 2, n);
    rows(0, n / 2);
    other.join();
    a.swap(na);
    b.swap(nb);
  }
  NoiseTile t;
  t.size = n;
  t.values.resize(cells);
  // Rank normalisation: uniform distribution on [0, 1], so the fabric's contrast does not depend on s.
  std::vector<std::uint32_t> order(cells);
  for (std::size_t i = 0; i < cells; ++i) order[i] = static_cast<std::uint32_t>(i);
  std::stable_sort(order.begin(), order.end(), [&](std::uint32_t x, std::uint32_t y) { return a[x] < a[y]; });
  for (std::size_t r = 0; r < cells; ++r) t.values[order[r]] = static_cast<float>(r) / static_cast<float>(cells - 1);
  return t;
}

std::shared_ptr<const NoiseTile> cachedReactionDiffusion(const NoiseOptions& o) {
  static std::mutex mutex;
  static std::map<std::tuple<int, double, std::uint32_t, int>, std::shared_ptr<const NoiseTile>> cache;
  auto key = std::make_tuple(o.size, o.spotScale, o.seed, o.iterations);
  {
    std::lock_guard lock(mutex);
    if (auto it = cache.find(key); it != cache.end()) return it->second;
  }
  auto tile = std::make_shared<const NoiseTile>(makeReactionDiffusion(o));
  std::lock_guard lock(mutex);
  return cache.emplace(key, tile).first->second;
}

} // namespace dtf::render
