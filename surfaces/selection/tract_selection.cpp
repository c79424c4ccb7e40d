// SPDX-License-Identifier: GPL-3.0-or-later
#include "surfaces/selection/tract_selection.h"

#include "io/model/error.h"

#include <algorithm>
#include <atomic>
#include <iterator>
#include <memory>
#include <cmath>
#include <limits>
#include <thread>

namespace dtf::surfaces {

namespace {

int threadCount(int threads) {
  const int n = threads > 0 ? threads : static_cast<int>(std::thread::hardware_concurrency());
  return std::clamp(n, 1, 256);
}

// Runs fn(begin, end, worker) over [0, n) in `threads` contiguous blocks (the calling thread takes one).
template <typename F> void parallelBlocks(std::size_t n, int threads, F&& fn) {
  const std::size_t t = std::min<std::size_t>(static_cast<std::size_t>(threadCount(threads)),
                                              std::max<std::size_t>(1, n / 4096));
  if (t <= 1) {
    fn(std::size_t{0}, n, 0);
    return;
  }
  std::vector<std::thread> pool;
  for (std::size_t w = 1; w < t; ++w)
    pool.emplace_back([&, w] { fn(n * w / t, n * (w + 1) / t, static_cast<int>(w)); });
  fn(0, n / t, 0);
  for (auto& th : pool)
    th.join();
}

constexpr double kInf = std::numeric_limits<double>::infinity();

} // namespace

std::uint64_t TractView::pointCount() const {
  if (lineCount == 0) return 0;
  return start(lineCount) - start(0) - static_cast<std::uint64_t>(gap) * lineCount;
}

TractView viewOf(const Polylines& lines) {
  TractView v;
  v.points = lines.points.data();
  v.starts32 = lines.offsets.data();
  v.lineCount = lines.lineCount();
  return v;
}

double lineLength(const TractView& v, std::size_t i) {
  double s = 0;
  const std::uint64_t b = v.begin(i), e = v.end(i);
  for (std::uint64_t p = b + 1; p < e; ++p)
    s += glm::length(glm::dvec3(v.points[p]) - glm::dvec3(v.points[p - 1]));
  return s;
}

// ---- region tests

struct RegionTester::Impl {
  struct Compiled {
    RegionShape shape;
    RegionKind kind;
    glm::vec3 c{0.0f}; // sphere, single precision as tckedit
    float r2 = 0;
    glm::dvec3 cd{0.0}; // sphere, for segments
    double rd = 0;
    glm::vec3 lo{0.0f}, hi{0.0f}; // box
    glm::dvec3 boundsLo{0.0}, boundsHi{0.0}; // world bounds of everything inside (a mask's, found once)
    glm::dmat4 toVoxel{1.0};      // mask
    glm::ivec3 dims{0};
    const unsigned char* data = nullptr;
    std::size_t stride = 1;
  };
  RegionSet set;
  std::vector<Compiled> regions;
  std::vector<std::size_t> includes, excludes, ordered; // indices into regions

  bool maskAt(const Compiled& c, int i, int j, int k) const {
    if (i < 0 || j < 0 || k < 0 || i >= c.dims.x || j >= c.dims.y || k >= c.dims.z) return false;
    const std::size_t idx = static_cast<std::size_t>(i) +
                            static_cast<std::size_t>(c.dims.x) *
                                (static_cast<std::size_t>(j) + static_cast<std::size_t>(c.dims.y) * k);
    return c.data[idx * c.stride] != 0;
  }

  bool contains(const Compiled& c, const glm::vec3& p) const {
    switch (c.shape) {
    case RegionShape::Sphere: {
      const glm::vec3 d = c.c - p;
      return glm::dot(d, d) <= c.r2;
    }
    case RegionShape::Box:
      return p.x >= c.lo.x && p.x <= c.hi.x && p.y >= c.lo.y && p.y <= c.hi.y && p.z >= c.lo.z &&
             p.z <= c.hi.z;
    case RegionShape::Mask: {
      const glm::dvec3 v(c.toVoxel * glm::dvec4(glm::dvec3(p), 1.0));
      return maskAt(c, static_cast<int>(std::lround(v.x)), static_cast<int>(std::lround(v.y)),
                    static_cast<int>(std::lround(v.z)));
    }
    }
    return false;
  }

  // The parameter t in [0, 1] at which the segment a->b first lies in the region, or a negative value
  // when it never does. Exact for spheres and boxes; a mask is walked voxel by voxel along the segment.
  double entry(const Compiled& c, const glm::vec3& a32, const glm::vec3& b32) const {
    const glm::dvec3 a(a32), b(b32), d = b - a;
    switch (c.shape) {
    case RegionShape::Sphere: {
      const glm::dvec3 m = a - c.cd;
      const double A = glm::dot(d, d), B = glm::dot(m, d), C = glm::dot(m, m) - c.rd * c.rd;
      if (C <= 0) return 0.0;
      if (A <= 0) return -1.0;
      const double disc = B * B - A * C;
      if (disc < 0) return -1.0;
      const double t = (-B - std::sqrt(disc)) / A;
      return (t >= 0 && t <= 1) ? t : -1.0;
    }
    case RegionShape::Box: {
      double t0 = 0, t1 = 1;
      for (int ax = 0; ax < 3; ++ax) {
        const double lo = c.lo[ax], hi = c.hi[ax];
        if (d[ax] == 0) {
          if (a[ax] < lo || a[ax] > hi) return -1.0;
          continue;
        }
        double ta = (lo - a[ax]) / d[ax], tb = (hi - a[ax]) / d[ax];
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
        if (t0 > t1) return -1.0;
      }
      return t0;
    }
    case RegionShape::Mask: {
      // Amanatides-Woo over the cells [v - 0.5, v + 0.5] that nearest-voxel rounding assigns.
      const glm::dvec3 va(c.toVoxel * glm::dvec4(a, 1.0)), vb(c.toVoxel * glm::dvec4(b, 1.0));
      const glm::dvec3 dv = vb - va;
      glm::ivec3 cell(static_cast<int>(std::lround(va.x)), static_cast<int>(std::lround(va.y)),
                      static_cast<int>(std::lround(va.z)));
      glm::ivec3 step(0);
      glm::dvec3 tMax(kInf), tDelta(kInf);
      for (int ax = 0; ax < 3; ++ax) {
        if (dv[ax] > 0) {
          step[ax] = 1;
          tMax[ax] = (cell[ax] + 0.5 - va[ax]) / dv[ax];
          tDelta[ax] = 1.0 / dv[ax];
        } else if (dv[ax] < 0) {
          step[ax] = -1;
          tMax[ax] = (cell[ax] - 0.5 - va[ax]) / dv[ax];
          tDelta[ax] = -1.0 / dv[ax];
        }
      }
      const double span = std::abs(dv.x) + std::abs(dv.y) + std::abs(dv.z);
      if (!std::isfinite(span)) return -1.0;
      const long long maxSteps = static_cast<long long>(span) + 4;
      double t = 0;
      for (long long s = 0; s <= maxSteps; ++s) {
        if (maskAt(c, cell.x, cell.y, cell.z)) return t;
        int ax = 0;
        if (tMax.y < tMax[ax]) ax = 1;
        if (tMax.z < tMax[ax]) ax = 2;
        if (tMax[ax] > 1.0) break;
        t = tMax[ax];
        cell[ax] += step[ax];
        tMax[ax] += tDelta[ax];
      }
      return -1.0;
    }
    }
    return -1.0;
  }
};

RegionTester::RegionTester(const RegionSet& set) : impl_(std::make_unique<Impl>()) {
  validate(set);
  impl_->set = set;
  for (std::size_t n = 0; n < set.regions.size(); ++n) {
    const Region& r = set.regions[n];
    Impl::Compiled c;
    c.shape = r.shape;
    c.kind = r.kind;
    c.c = glm::vec3(r.centre);
    c.r2 = static_cast<float>(r.radius) * static_cast<float>(r.radius);
    c.cd = r.centre;
    c.rd = r.radius;
    c.lo = glm::vec3(r.lo);
    c.hi = glm::vec3(r.hi);
    r.bounds(c.boundsLo, c.boundsHi);
    if (r.shape == RegionShape::Mask) {
      c.toVoxel = glm::inverse(r.mask->grid.voxelToWorld);
      c.dims = r.mask->grid.dims;
      c.data = r.mask->data.data();
      c.stride = static_cast<std::size_t>(r.mask->components);
    }
    impl_->regions.push_back(c);
    (r.kind == RegionKind::Include   ? impl_->includes
     : r.kind == RegionKind::Exclude ? impl_->excludes
                                     : impl_->ordered)
        .push_back(n);
  }
}

RegionTester::~RegionTester() = default;
RegionTester::RegionTester(RegionTester&&) noexcept = default;
RegionTester& RegionTester::operator=(RegionTester&&) noexcept = default;

const RegionSet& RegionTester::set() const {
  return impl_->set;
}

bool RegionTester::containsPoint(std::size_t r, const glm::vec3& p) const {
  return impl_->contains(impl_->regions[r], p);
}

bool RegionTester::segmentTouches(std::size_t r, const glm::vec3& a, const glm::vec3& b) const {
  return impl_->entry(impl_->regions[r], a, b) >= 0;
}

void RegionTester::bounds(std::size_t r, glm::dvec3& lo, glm::dvec3& hi) const {
  lo = impl_->regions[r].boundsLo;
  hi = impl_->regions[r].boundsHi;
}

int RegionTester::classifyBox(std::size_t r, const glm::dvec3& lo, const glm::dvec3& hi) const {
  const Impl::Compiled& c = impl_->regions[r];
  // Margins keep the answer on the safe side of contains()'s single-precision tests.
  switch (c.shape) {
  case RegionShape::Sphere: {
    const glm::dvec3 nearest = glm::clamp(c.cd, lo, hi);
    const glm::dvec3 far = glm::max(glm::abs(lo - c.cd), glm::abs(hi - c.cd));
    const double r2 = c.rd * c.rd, eps = 1e-5 * r2 + 1e-4;
    if (glm::dot(nearest - c.cd, nearest - c.cd) > r2 + eps) return 0;
    if (glm::dot(far, far) < r2 - eps) return 1;
    return 2;
  }
  case RegionShape::Box: {
    const glm::dvec3 rlo(c.lo), rhi(c.hi);
    const double eps = 1e-4;
    if (hi.x < rlo.x - eps || hi.y < rlo.y - eps || hi.z < rlo.z - eps || lo.x > rhi.x + eps ||
        lo.y > rhi.y + eps || lo.z > rhi.z + eps)
      return 0;
    if (lo.x > rlo.x + eps && lo.y > rlo.y + eps && lo.z > rlo.z + eps && hi.x < rhi.x - eps &&
        hi.y < rhi.y - eps && hi.z < rhi.z - eps)
      return 1;
    return 2;
  }
  case RegionShape::Mask: {
    const glm::dvec3 &mlo = c.boundsLo, &mhi = c.boundsHi;
    const double eps = 1e-3;
    if (hi.x < mlo.x - eps || hi.y < mlo.y - eps || hi.z < mlo.z - eps || lo.x > mhi.x + eps ||
        lo.y > mhi.y + eps || lo.z > mhi.z + eps)
      return 0;
    return 2;
  }
  }
  return 2;
}

bool RegionTester::touches(std::size_t r, const glm::vec3* p, std::size_t n) const {
  const Impl::Compiled& c = impl_->regions[r];
  for (std::size_t k = 0; k < n; ++k)
    if (impl_->contains(c, p[k])) return true;
  if (impl_->set.precise)
    for (std::size_t k = 0; k + 1 < n; ++k)
      if (impl_->entry(c, p[k], p[k + 1]) >= 0) return true;
  return false;
}

bool RegionTester::accepts(const glm::vec3* p, std::size_t n) const {
  const Impl& s = *impl_;
  const RegionSet& set = s.set;
  if (set.hasLengthRange()) {
    double len = 0;
    for (std::size_t k = 1; k < n; ++k)
      len += glm::length(glm::dvec3(p[k]) - glm::dvec3(p[k - 1]));
    if (len < set.minLengthMm || len > set.maxLengthMm) return false;
  }
  if (s.regions.empty()) return true;
  if (n == 0) return false;

  // tckedit's walk: every point marks the include regions it is in and advances the ordered includes
  // (the first ordered region holding it: entering the next one advances, staying in the current one is
  // allowed, anything else breaks the order); a point in an exclude region rejects the streamline.
  constexpr std::size_t kSmall = 32;
  bool visitedSmall[kSmall] = {};
  std::vector<char> visitedLarge;
  bool* visited = visitedSmall;
  if (s.includes.size() > kSmall) {
    visitedLarge.assign(s.includes.size(), 0);
    visited = reinterpret_cast<bool*>(visitedLarge.data());
  }
  std::size_t next = 0;
  bool orderValid = true;
  auto enterOrdered = [&](std::size_t idx) {
    if (idx == next)
      ++next;
    else if (idx + 1 != next)
      orderValid = false;
  };
  auto visit = [&](const glm::vec3& q) -> bool {
    for (std::size_t i = 0; i < s.includes.size(); ++i)
      if (!visited[i] && s.contains(s.regions[s.includes[i]], q)) visited[i] = true;
    if (orderValid)
      for (std::size_t o = 0; o < s.ordered.size(); ++o)
        if (s.contains(s.regions[s.ordered[o]], q)) {
          enterOrdered(o);
          break;
        }
    for (std::size_t e : s.excludes)
      if (s.contains(s.regions[e], q)) return false;
    return true;
  };
  // Between two vertices (precise): includes and excludes by an exact segment test, ordered regions entered
  // in the order the segment enters them.
  auto visitSegment = [&](const glm::vec3& a, const glm::vec3& b) -> bool {
    for (std::size_t e : s.excludes)
      if (s.entry(s.regions[e], a, b) >= 0) return false;
    for (std::size_t i = 0; i < s.includes.size(); ++i)
      if (!visited[i] && s.entry(s.regions[s.includes[i]], a, b) >= 0) visited[i] = true;
    if (orderValid && !s.ordered.empty()) {
      std::pair<double, std::size_t> events[kSmall];
      std::vector<std::pair<double, std::size_t>> many;
      std::size_t count = 0;
      for (std::size_t o = 0; o < s.ordered.size(); ++o) {
        const double t = s.entry(s.regions[s.ordered[o]], a, b);
        if (t <= 0) continue; // not entered, or already in it at the vertex (the vertex counted it)
        if (count < kSmall)
          events[count] = {t, o};
        else
          many.emplace_back(t, o);
        ++count;
      }
      if (count > kSmall) {
        many.insert(many.begin(), events, events + kSmall);
        std::sort(many.begin(), many.end());
        for (const auto& ev : many)
          enterOrdered(ev.second);
      } else {
        std::sort(events, events + count);
        for (std::size_t k = 0; k < count; ++k)
          enterOrdered(events[k].second);
      }
    }
    return true;
  };

  if (set.endsOnly) {
    if (!visit(p[0]) || !visit(p[n - 1])) return false;
  } else {
    for (std::size_t k = 0; k < n; ++k) {
      if (!visit(p[k])) return false;
      if (set.precise && k + 1 < n && !visitSegment(p[k], p[k + 1])) return false;
    }
  }
  for (std::size_t i = 0; i < s.includes.size(); ++i)
    if (!visited[i]) return false;
  return orderValid && next == s.ordered.size();
}

// ---- the index

TractIndex::TractIndex(const TractView& view, double cellMm, int threads) : view_(view) {
  const std::size_t L = view.lineCount;
  if (L >= std::numeric_limits<std::uint32_t>::max())
    throw InputError("a tractogram of " + std::to_string(L) + " streamlines is more than the index holds");
  auto chunksOf = [&](std::size_t i) -> std::uint64_t {
    const std::uint64_t n = view.size(i);
    return n == 0 ? 0 : n == 1 ? 1 : (n - 2) / kChunkPoints + 1;
  };

  // The data's extent, per worker then merged.
  const int T = threadCount(threads);
  std::vector<glm::vec3> los(static_cast<std::size_t>(T), glm::vec3(std::numeric_limits<float>::max())),
      his(static_cast<std::size_t>(T), glm::vec3(std::numeric_limits<float>::lowest()));
  parallelBlocks(L, T, [&](std::size_t b, std::size_t e, int w) {
    glm::vec3 lo = los[static_cast<std::size_t>(w)], hi = his[static_cast<std::size_t>(w)];
    for (std::size_t i = b; i < e; ++i)
      for (std::uint64_t p = view.begin(i); p < view.end(i); ++p) {
        lo = glm::min(lo, view.points[p]);
        hi = glm::max(hi, view.points[p]);
      }
    los[static_cast<std::size_t>(w)] = lo;
    his[static_cast<std::size_t>(w)] = hi;
  });
  glm::vec3 lo = los[0], hi = his[0];
  for (int w = 1; w < T; ++w) {
    lo = glm::min(lo, los[static_cast<std::size_t>(w)]);
    hi = glm::max(hi, his[static_cast<std::size_t>(w)]);
  }
  if (!(lo.x <= hi.x)) lo = hi = glm::vec3(0.0f);
  const glm::dvec3 extent = glm::dvec3(hi) - glm::dvec3(lo);
  const double longest = std::max({extent.x, extent.y, extent.z, 1.0});
  // The cell: about the length of a chunk (its half-extent must fit a cell, or it is tested by every query),
  // from the median step of up to 4096 streamlines; at least 4 mm, and at most 256 cells along the data.
  std::vector<double> steps;
  for (std::size_t i = 0; i < L && steps.size() < 65536; i += std::max<std::size_t>(1, L / 4096))
    for (std::uint64_t p = view.begin(i) + 1; p < view.end(i); ++p)
      steps.push_back(glm::length(glm::dvec3(view.points[p]) - glm::dvec3(view.points[p - 1])));
  double step = 2.0;
  if (!steps.empty()) {
    std::nth_element(steps.begin(), steps.begin() + static_cast<std::ptrdiff_t>(steps.size() / 2), steps.end());
    step = steps[steps.size() / 2];
  }
  cell_ = cellMm > 0 ? cellMm : std::max({4.0, 0.6 * kChunkPoints * step, longest / 256.0});
  origin_ = glm::dvec3(lo);
  dims_ = glm::ivec3(glm::floor(extent / cell_)) + 1;
  const std::size_t cells = static_cast<std::size_t>(dims_.x) * dims_.y * dims_.z;
  const float cellF = static_cast<float>(cell_);

  // A chunk's centre cell and its box, or -1 when it is longer than a cell or its part does not fit 16 bits
  // (kept aside and tested by every query).
  auto chunkCell = [&](std::size_t line, std::uint64_t j, glm::vec3& a, glm::vec3& b) -> std::int64_t {
    const std::uint64_t first = view.begin(line) + j * kChunkPoints;
    const std::uint64_t last = std::min<std::uint64_t>(first + kChunkPoints, view.end(line) - 1);
    a = b = view.points[first];
    for (std::uint64_t p = first + 1; p <= last; ++p) {
      a = glm::min(a, view.points[p]);
      b = glm::max(b, view.points[p]);
    }
    const glm::vec3 half = 0.5f * (b - a);
    if (half.x > cellF || half.y > cellF || half.z > cellF || j > 0xFFFF) return -1;
    const glm::dvec3 c = (0.5 * (glm::dvec3(a) + glm::dvec3(b)) - origin_) / cell_;
    const glm::ivec3 q = glm::clamp(glm::ivec3(glm::floor(c)), glm::ivec3(0), dims_ - 1);
    return static_cast<std::int64_t>(q.x) +
           static_cast<std::int64_t>(dims_.x) * (q.y + static_cast<std::int64_t>(dims_.y) * q.z);
  };

  // Counting sort of the chunks by cell: count per worker, then place.
  std::vector<std::vector<std::uint64_t>> counts(static_cast<std::size_t>(T));
  std::vector<std::vector<Oversized>> big(static_cast<std::size_t>(T));
  parallelBlocks(L, T, [&](std::size_t b, std::size_t e, int w) {
    auto& cnt = counts[static_cast<std::size_t>(w)];
    cnt.assign(cells, 0);
    glm::vec3 lo3, hi3;
    for (std::size_t i = b; i < e; ++i)
      for (std::uint64_t j = 0; j < chunksOf(i); ++j) {
        const std::int64_t c = chunkCell(i, j, lo3, hi3);
        if (c < 0)
          big[static_cast<std::size_t>(w)].push_back({static_cast<std::uint32_t>(i), view.begin(i) + j * kChunkPoints});
        else
          ++cnt[static_cast<std::size_t>(c)];
      }
  });
  for (const auto& v : big)
    oversized_.insert(oversized_.end(), v.begin(), v.end());
  std::vector<std::size_t> ran;
  for (std::size_t w = 0; w < static_cast<std::size_t>(T); ++w)
    if (!counts[w].empty()) ran.push_back(w);
  cellStart_.assign(cells + 1, 0);
  std::uint64_t total = 0;
  for (std::size_t c = 0; c < cells; ++c) {
    cellStart_[c] = total;
    for (std::size_t w : ran) {
      const std::uint64_t n = counts[w][c];
      counts[w][c] = total;
      total += n;
    }
  }
  cellStart_[cells] = total;
  if (total >= std::numeric_limits<std::uint32_t>::max())
    throw InputError("a tractogram of " + std::to_string(total * kChunkPoints) + " points is more than the index holds");
  chunks_.resize(total);
  parallelBlocks(L, T, [&](std::size_t b, std::size_t e, int w) {
    auto& at = counts[static_cast<std::size_t>(w)];
    glm::vec3 a, bb;
    for (std::size_t i = b; i < e; ++i)
      for (std::uint64_t j = 0; j < chunksOf(i); ++j) {
        const std::int64_t c = chunkCell(i, j, a, bb);
        if (c < 0) continue;
        const auto cu = static_cast<std::uint64_t>(c);
        const glm::ivec3 q(static_cast<int>(cu % static_cast<std::uint64_t>(dims_.x)),
                           static_cast<int>((cu / static_cast<std::uint64_t>(dims_.x)) % static_cast<std::uint64_t>(dims_.y)),
                           static_cast<int>(cu / (static_cast<std::uint64_t>(dims_.x) * static_cast<std::uint64_t>(dims_.y))));
        // The box in 1/255 of three cells from the cell's corner minus one cell, rounded outwards.
        const glm::dvec3 base = origin_ + (glm::dvec3(q) - 1.0) * cell_;
        const double unit = 3.0 * cell_ / 255.0;
        Chunk& k = chunks_[at[cu]++];
        k.line = static_cast<std::uint32_t>(i);
        k.part = static_cast<std::uint16_t>(j);
        for (int ax = 0; ax < 3; ++ax) {
          k.box[ax] = static_cast<std::uint8_t>(std::clamp(std::floor((a[ax] - base[ax]) / unit), 0.0, 255.0));
          k.box[3 + ax] = static_cast<std::uint8_t>(std::clamp(std::ceil((bb[ax] - base[ax]) / unit), 0.0, 255.0));
        }
      }
  });
}

std::size_t TractIndex::bytes() const {
  return cellStart_.capacity() * sizeof(std::uint64_t) + chunks_.capacity() * sizeof(Chunk) +
         oversized_.capacity() * sizeof(Oversized);
}

std::vector<std::uint32_t> TractIndex::linesTouching(const RegionTester& tester, std::size_t r,
                                                     int threads) const {
  glm::dvec3 lo, hi;
  tester.bounds(r, lo, hi);
  // A chunk's centre lies within a cell of its box, so the cells a region can touch reach one cell further.
  lo -= glm::dvec3(cell_);
  hi += glm::dvec3(cell_);
  const glm::ivec3 a = glm::clamp(glm::ivec3(glm::floor((lo - origin_) / cell_)), glm::ivec3(0), dims_ - 1);
  const glm::ivec3 b = glm::clamp(glm::ivec3(glm::floor((hi - origin_) / cell_)), glm::ivec3(0), dims_ - 1);
  const glm::dvec3 gridHi = origin_ + glm::dvec3(dims_) * cell_;
  const bool overlaps = !(lo.x > gridHi.x || lo.y > gridHi.y || lo.z > gridHi.z || hi.x < origin_.x ||
                          hi.y < origin_.y || hi.z < origin_.z);
  // The cells to read, one run of chunks_ per row.
  struct Run {
    std::uint64_t s, e;
    glm::ivec3 cell; // the run's first cell
  };
  std::vector<Run> runs;
  std::uint64_t work = 0;
  if (overlaps)
    for (int z = a.z; z <= b.z; ++z)
      for (int y = a.y; y <= b.y; ++y) {
        const std::size_t row = static_cast<std::size_t>(dims_.x) * (y + static_cast<std::size_t>(dims_.y) * z);
        const std::uint64_t s = cellStart_[row + a.x], e = cellStart_[row + b.x + 1];
        if (e > s) {
          runs.push_back({s, e, glm::ivec3(a.x, y, z)});
          work += e - s;
        }
      }
  const bool precise = tester.set().precise;
  auto testPoints = [&](std::uint32_t line, std::uint64_t first) {
    const std::uint64_t last = std::min<std::uint64_t>(first + kChunkPoints, view_.end(line) - 1);
    for (std::uint64_t p = first; p <= last; ++p)
      if (tester.containsPoint(r, view_.points[p])) return true;
    if (precise)
      for (std::uint64_t p = first; p < last; ++p)
        if (tester.segmentTouches(r, view_.points[p], view_.points[p + 1])) return true;
    return false;
  };
  // Lines found so far, shared by the workers as a hint (a stale read only costs a second test).
  const std::size_t words = (view_.lineCount + 63) / 64;
  std::unique_ptr<std::atomic<std::uint64_t>[]> seen(new std::atomic<std::uint64_t>[std::max<std::size_t>(words, 1)]);
  for (std::size_t i = 0; i < words; ++i)
    seen[i].store(0, std::memory_order_relaxed);
  auto known = [&](std::uint32_t line) {
    return (seen[line >> 6].load(std::memory_order_relaxed) >> (line & 63)) & 1u;
  };
  auto mark = [&](std::uint32_t line) { seen[line >> 6].fetch_or(std::uint64_t{1} << (line & 63), std::memory_order_relaxed); };

  const int T = threadCount(threads);
  std::vector<std::vector<std::uint32_t>> local(static_cast<std::size_t>(T));
  const double unit = 3.0 * cell_ / 255.0;
  // Each worker takes an equal share of the chunks; a run's cell is found from the chunk's place in it.
  parallelBlocks(static_cast<std::size_t>(work), work < 65536 ? 1 : T, [&](std::size_t wb, std::size_t we, int w) {
    auto& out = local[static_cast<std::size_t>(w)];
    std::vector<std::uint64_t> undecided; // line << 16 | part
    std::uint64_t before = 0;
    for (const Run& run : runs) {
      const std::uint64_t len = run.e - run.s;
      const std::uint64_t from = std::max<std::uint64_t>(wb, before), to = std::min<std::uint64_t>(we, before + len);
      if (from < to) {
        std::uint64_t k = run.s + (from - before);
        const std::uint64_t kEnd = run.s + (to - before);
        // The cells of this row, in order: cellStart_ tells where each begins.
        const std::size_t row = static_cast<std::size_t>(dims_.x) *
                                (run.cell.y + static_cast<std::size_t>(dims_.y) * run.cell.z);
        int x = run.cell.x;
        while (cellStart_[row + x + 1] <= k)
          ++x;
        for (; k < kEnd; ++k) {
          while (cellStart_[row + x + 1] <= k)
            ++x;
          const Chunk& c = chunks_[k];
          if (known(c.line)) continue;
          const glm::dvec3 base = origin_ + (glm::dvec3(x, run.cell.y, run.cell.z) - 1.0) * cell_;
          const glm::dvec3 blo = base + glm::dvec3(c.box[0], c.box[1], c.box[2]) * unit;
          const glm::dvec3 bhi = base + glm::dvec3(c.box[3], c.box[4], c.box[5]) * unit;
          const int where = tester.classifyBox(r, blo, bhi);
          if (where == 1) {
            mark(c.line);
            out.push_back(c.line);
          } else if (where == 2) {
            undecided.push_back((static_cast<std::uint64_t>(c.line) << 16) | c.part);
          }
        }
      }
      before += len;
      if (before >= we) break;
    }
    // The chunks their boxes left undecided, in the order of their positions in memory (the lines' order),
    // skipping lines already found: the point tests read the positions forwards instead of at random.
    std::sort(undecided.begin(), undecided.end());
    for (const std::uint64_t u : undecided) {
      const auto line = static_cast<std::uint32_t>(u >> 16);
      if (known(line)) continue;
      if (testPoints(line, view_.begin(line) + (u & 0xFFFF) * kChunkPoints)) {
        mark(line);
        out.push_back(line);
      }
    }
  });
  std::vector<std::uint32_t> found;
  for (const Oversized& o : oversized_)
    if (testPoints(o.line, o.first)) found.push_back(o.line);
  for (const auto& l : local)
    found.insert(found.end(), l.begin(), l.end());
  std::sort(found.begin(), found.end());
  found.erase(std::unique(found.begin(), found.end()), found.end());
  return found;
}

// ---- selection

std::vector<std::uint32_t> selectLines(const TractView& view, const RegionTester& tester, const TractIndex* index,
                                       int threads, SelectionStats* stats) {
  const RegionSet& set = tester.set();
  SelectionStats st;
  const int T = threadCount(threads);
  auto walk = [&](std::size_t n, auto&& lineAt) {
    std::vector<std::vector<std::uint32_t>> local(static_cast<std::size_t>(T));
    parallelBlocks(n, T, [&](std::size_t b, std::size_t e, int w) {
      auto& out = local[static_cast<std::size_t>(w)];
      for (std::size_t k = b; k < e; ++k) {
        const std::uint32_t i = lineAt(k);
        const std::uint64_t first = view.begin(i);
        if (tester.accepts(view.points + first, view.end(i) - first)) out.push_back(i);
      }
    });
    std::vector<std::uint32_t> kept;
    for (const auto& l : local) // worker w holds a later block than w - 1: the order is kept
      kept.insert(kept.end(), l.begin(), l.end());
    st.walked += n;
    return kept;
  };

  std::size_t includeCount = 0, orderedCount = 0;
  for (const Region& r : set.regions) {
    includeCount += r.kind != RegionKind::Exclude;
    orderedCount += r.kind == RegionKind::IncludeOrdered;
  }
  std::vector<std::uint32_t> kept;
  if (!index || set.endsOnly || set.regions.empty()) {
    st.candidates = view.lineCount;
    kept = walk(view.lineCount, [](std::size_t k) { return static_cast<std::uint32_t>(k); });
  } else {
    // Each region's lines from the index (exact): includes intersected, excludes removed. Only the order of
    // ordered includes and the length range need the survivors' vertices.
    st.indexed = true;
    std::vector<std::uint32_t> cand;
    if (includeCount == 0) {
      cand.resize(view.lineCount);
      for (std::size_t i = 0; i < view.lineCount; ++i)
        cand[i] = static_cast<std::uint32_t>(i);
    } else {
      bool first = true;
      for (std::size_t r = 0; r < set.regions.size(); ++r) {
        if (set.regions[r].kind == RegionKind::Exclude) continue;
        std::vector<std::uint32_t> hits = index->linesTouching(tester, r, threads);
        if (first) {
          cand = std::move(hits);
          first = false;
        } else {
          std::vector<std::uint32_t> both;
          std::set_intersection(cand.begin(), cand.end(), hits.begin(), hits.end(), std::back_inserter(both));
          cand = std::move(both);
        }
        if (cand.empty()) break;
      }
    }
    for (std::size_t r = 0; r < set.regions.size() && !cand.empty(); ++r) {
      if (set.regions[r].kind != RegionKind::Exclude) continue;
      const std::vector<std::uint32_t> hits = index->linesTouching(tester, r, threads);
      std::vector<std::uint32_t> rest;
      std::set_difference(cand.begin(), cand.end(), hits.begin(), hits.end(), std::back_inserter(rest));
      cand = std::move(rest);
    }
    st.candidates = cand.size();
    if (orderedCount > 0 || set.hasLengthRange())
      kept = walk(cand.size(), [&](std::size_t k) { return cand[k]; });
    else
      kept = std::move(cand);
  }
  if (stats) *stats = st;
  return kept;
}

Polylines subsetWithGroups(const Polylines& lines, const std::vector<std::uint32_t>& keep) {
  Polylines out = lines.subset(keep);
  for (const TractGroup& g : lines.groups) {
    TractGroup ng;
    ng.name = g.name;
    for (std::uint32_t i : g.lines) {
      auto it = std::lower_bound(keep.begin(), keep.end(), i);
      if (it != keep.end() && *it == i) ng.lines.push_back(static_cast<std::uint32_t>(it - keep.begin()));
    }
    std::sort(ng.lines.begin(), ng.lines.end());
    out.groups.push_back(std::move(ng));
  }
  return out;
}

} // namespace dtf::surfaces
