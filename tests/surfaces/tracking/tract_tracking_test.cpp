// SPDX-License-Identifier: GPL-3.0-or-later
// Deterministic tensor tracking: exact behaviour on closed-form fields (constant direction, FA boundary,
// a 90-degree turn, length limits), seed generators, determinism across thread counts, progress and
// cancellation, and reproduction of MRtrix's reference tracks on the real brain.
#include "io/model/error.h"
#include "io/phantoms.h"
#include "io/formats/tensor_io.h"
#include "io/formats/tracts.h"
#include "support/test_env.h"
#include "surfaces/slices.h"
#include "surfaces/tracking/tracking.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <unordered_map>

using dtf::Polylines;
using dtf::TensorField;
using dtf::surfaces::TrackingOptions;

namespace {

const double kPi = 3.14159265358979323846;

glm::dvec3 dirOf(double azimuthDeg, double elevationDeg) {
  double az = azimuthDeg * kPi / 180, el = elevationDeg * kPi / 180;
  return {std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el)};
}

TensorField constantField(int size, double az, double el) {
  dtf::io::PhantomOptions po;
  po.size = size;
  po.angleDeg = az;
  po.elevationDeg = el;
  return dtf::io::makePhantom("constant", po).tensors;
}

bool insideCentres(const dtf::Grid& g, const glm::dvec3& world) {
  glm::dvec3 v = g.toVoxel(world);
  for (int a = 0; a < 3; ++a)
    if (v[a] < -1e-6 || v[a] > g.dims[a] - 1 + 1e-6) return false;
  return true;
}

double faAt(const TensorField& f, const glm::dvec3& world) {
  return dtf::fractionalAnisotropy(dtf::eigenDecompose(f.sampleWorld(world)).values);
}

} // namespace

// In a constant field RK4 and Euler follow the direction exactly and stop at the edge of the data.
TEST(Tracking, ConstantFieldIsFollowedExactlyToTheEdge) {
  const TensorField f = constantField(40, 30, 20);
  const glm::dvec3 d = dirOf(30, 20);
  for (bool rk4 : {true, false}) {
    TrackingOptions o;
    o.rk4 = rk4;
    o.stepMm = 0.7;
    o.minLengthMm = 0;
    auto line = dtf::surfaces::trackOne(f, glm::dvec3(0.3, -0.2, 0.1), o);
    ASSERT_GT(line.size(), 20u);
    for (std::size_t i = 1; i < line.size(); ++i) {
      glm::dvec3 s = glm::dvec3(line[i]) - glm::dvec3(line[i - 1]);
      EXPECT_NEAR(glm::length(s), 0.7, 1e-5);
      EXPECT_NEAR(std::abs(glm::dot(glm::normalize(s), d)), 1.0, 1e-9) << "step " << i;
      EXPECT_GT(glm::dot(s, glm::dvec3(line[1]) - glm::dvec3(line[0])), 0)
          << "direction flipped at step " << i;
    }
    // Both ends are inside the grid and one more step would leave it.
    const glm::dvec3 a(line.front()), b(line.back());
    const glm::dvec3 out = glm::normalize(b - a);
    EXPECT_TRUE(insideCentres(f.grid, a));
    EXPECT_TRUE(insideCentres(f.grid, b));
    EXPECT_FALSE(insideCentres(f.grid, b + 0.7 * out));
    EXPECT_FALSE(insideCentres(f.grid, a - 0.7 * out));
  }
}

// The streamline ends at the last point whose interpolated FA is >= the stop, before an isotropic region.
TEST(Tracking, StopsAtTheFaBoundary) {
  TensorField f = constantField(32, 0, 0); // along +x
  for (int k = 0; k < 32; ++k)
    for (int j = 0; j < 32; ++j)
      for (int i = 0; i < 32; ++i)
        if (f.grid.toWorld(glm::dvec3(i, j, k)).x > 5.0) {
          f.at(i, j, k) = dtf::SymTensor{1e-3f, 0, 0, 1e-3f, 0, 1e-3f}; // FA 0
        }
  TrackingOptions o;
  o.minLengthMm = 0;
  o.stepMm = 0.5;
  auto line = dtf::surfaces::trackOne(f, glm::dvec3(-3.2, 0.1, 0.2), o);
  ASSERT_GT(line.size(), 3u);
  glm::dvec3 last(line.back()), first(line.front());
  if (last.x < first.x) std::swap(last, first);
  EXPECT_GE(faAt(f, last), 0.15);
  EXPECT_LT(faAt(f, last + glm::dvec3(0.5, 0, 0)), 0.15);
  EXPECT_LT(last.x, 5.5);
  EXPECT_GT(last.x, 3.5);
  // The other end runs to the grid edge (x = -15.5).
  EXPECT_LT(first.x, -15.0);
}

TEST(Tracking, LengthLimits) {
  const TensorField f = constantField(40, 10, 5);
  TrackingOptions o;
  o.stepMm = 1;
  o.minLengthMm = 0;
  o.maxLengthMm = 10;
  auto line = dtf::surfaces::trackOne(f, glm::dvec3(0, 0, 0), o);
  ASSERT_EQ(line.size(), 11u); // exactly 10 steps: far from the edges, the length limit ends it
  EXPECT_NEAR(glm::length(glm::dvec3(line.back()) - glm::dvec3(line.front())), 10.0, 1e-4);
  o.maxLengthMm = 250;
  o.minLengthMm = 60; // the chord through a 40 mm box along this direction is about 40 mm
  EXPECT_TRUE(dtf::surfaces::trackOne(f, glm::dvec3(0, 0, 0), o).empty());
}

// x-aligned tensors for x < 0, y-aligned for x > 0 (voxel boundary at x = 0). Euler steps from x = -10.3 land
// at x = -0.3 (e1 = x) and 0.7 (e1 = y): a 90-degree turn that a 89-degree limit stops and a 91-degree
// limit lets through.
TEST(Tracking, AngleLimitStopsSharpTurns) {
  TensorField f = constantField(40, 0, 0);
  const dtf::SymTensor ty = dtf::SymTensor::fromMat(
      0.3e-3 * glm::dmat3(1.0) + 1.4e-3 * glm::outerProduct(glm::dvec3(0, 1, 0), glm::dvec3(0, 1, 0)));
  for (int k = 0; k < 40; ++k)
    for (int j = 0; j < 40; ++j)
      for (int i = 0; i < 40; ++i)
        if (f.grid.toWorld(glm::dvec3(i, j, k)).x > 0) f.at(i, j, k) = ty;
  TrackingOptions o;
  o.rk4 = false;
  o.minLengthMm = 0;
  o.maxLengthMm = 40;
  o.maxAngleDeg = 89;
  auto stopped = dtf::surfaces::trackOne(f, glm::dvec3(-10.3, 0, 0), o);
  double maxX = -100, maxY = 0;
  for (const auto& p : stopped)
    maxX = std::max(maxX, static_cast<double>(p.x)),
    maxY = std::max(maxY, std::abs(static_cast<double>(p.y)));
  EXPECT_NEAR(maxX, 0.7, 1e-5);
  EXPECT_LT(maxY, 1e-6);
  o.maxAngleDeg = 91;
  auto turned = dtf::surfaces::trackOne(f, glm::dvec3(-10.3, 0, 0), o);
  maxY = 0;
  for (const auto& p : turned)
    maxY = std::max(maxY, std::abs(static_cast<double>(p.y)));
  EXPECT_GT(maxY, 10.0);
}

TEST(Tracking, SeedGenerators) {
  auto sphere = dtf::surfaces::seedsInSphere(glm::dvec3(1, 2, 3), 4.0, 11);
  glm::dvec3 mean(0.0);
  for (std::uint64_t i = 0; i < 2000; ++i) {
    glm::dvec3 p = sphere.at(i);
    EXPECT_LE(glm::length(p - glm::dvec3(1, 2, 3)), 4.0 + 1e-9);
    mean += p / 2000.0;
    EXPECT_EQ(p, sphere.at(i)); // a pure function of the index
  }
  EXPECT_LT(glm::length(mean - glm::dvec3(1, 2, 3)), 0.3);
  EXPECT_NE(sphere.at(0), dtf::surfaces::seedsInSphere(glm::dvec3(1, 2, 3), 4.0, 12).at(0));

  dtf::io::PhantomOptions po;
  po.size = 24;
  const TensorField f = dtf::io::makePhantom("constant", po).tensors;
  dtf::Mesh plane = dtf::surfaces::makeSlice(f.grid, dtf::surfaces::SliceAxis::Axial, 5);
  auto onSurface = dtf::surfaces::seedsOnSurface(plane, 3);
  const double z = f.grid.toWorld(glm::dvec3(0, 0, 5)).z;
  for (std::uint64_t i = 0; i < 500; ++i)
    EXPECT_NEAR(onSurface.at(i).z, z, 1e-5);

  auto slice = dtf::surfaces::seedsOnSlice(f, 1, 7, nullptr, 5);
  for (std::uint64_t i = 0; i < 500; ++i) {
    glm::dvec3 v = f.grid.toVoxel(slice.at(i));
    EXPECT_NEAR(v.y, 7.0, 1e-9);
    EXPECT_GE(v.x, -0.5);
    EXPECT_LE(v.x, 23.5);
  }
  EXPECT_THROW(dtf::surfaces::seedsOnSlice(f, 1, 24, nullptr, 5), dtf::InputError);

  dtf::MaskVolume mask(f.grid, 1);
  mask.at(3, 4, 5) = 1;
  mask.at(10, 11, 12) = 1;
  auto perVoxel = dtf::surfaces::seedsFromMask(mask, 3, 9);
  ASSERT_EQ(perVoxel.count, 6u);
  for (std::uint64_t i = 0; i < 6; ++i) {
    glm::dvec3 v = f.grid.toVoxel(perVoxel.at(i));
    glm::dvec3 expect = i < 3 ? glm::dvec3(3, 4, 5) : glm::dvec3(10, 11, 12);
    for (int a = 0; a < 3; ++a)
      EXPECT_LE(std::abs(v[a] - expect[a]), 0.5 + 1e-9);
  }
  EXPECT_THROW(dtf::surfaces::seedsFromMask(dtf::MaskVolume(f.grid, 1), 1, 1), dtf::InputError);
}

// The output depends on the seed only: 1, 2 and 5 threads give the same streamlines in the same order.
TEST(Tracking, OutputIsIndependentOfThreadCount) {
  dtf::io::PhantomOptions po;
  po.size = 48;
  const TensorField f = dtf::io::makePhantom("brain", po).tensors;
  dtf::MaskVolume valid(f.grid, 1);
  valid.data = f.valid;
  auto seeds = dtf::surfaces::seedsFromMask(valid, 0, 42);
  TrackingOptions o;
  o.stepMm = 0.5;
  o.minLengthMm = 10;
  std::vector<dtf::surfaces::TrackingResult> runs;
  for (int t : {1, 2, 5}) {
    o.threads = t;
    runs.push_back(dtf::surfaces::trackSelect(f, seeds, 300, o));
  }
  ASSERT_EQ(runs[0].lines.lineCount(), 300u);
  for (int r = 1; r < 3; ++r) {
    EXPECT_EQ(runs[r].lines.offsets, runs[0].lines.offsets);
    EXPECT_EQ(runs[r].seedIndex, runs[0].seedIndex);
    EXPECT_TRUE(runs[r].lines.points == runs[0].lines.points);
    EXPECT_EQ(runs[r].seedsTried, runs[0].seedsTried);
  }
  // Seeds are emitted in increasing order and trackSeeds agrees with trackSelect on the same seeds.
  EXPECT_TRUE(std::is_sorted(runs[0].seedIndex.begin(), runs[0].seedIndex.end()));
  auto fixed = dtf::surfaces::trackSeeds(f, seeds, runs[0].seedIndex.back() + 1, o);
  EXPECT_EQ(fixed.lines.offsets, runs[0].lines.offsets);
  EXPECT_EQ(fixed.seedsTried, runs[0].seedsTried);
}

TEST(Tracking, ProgressAndCancellation) {
  const TensorField f = constantField(32, 20, 10);
  auto seeds = dtf::surfaces::seedsInSphere(glm::dvec3(0.0), 5, 1);
  TrackingOptions o;
  o.minLengthMm = 0;
  std::size_t lastDone = 0, lastPlanned = 0, calls = 0;
  o.progress = [&](std::size_t done, std::size_t planned) {
    EXPECT_GE(done, lastDone);
    lastDone = done, lastPlanned = planned;
    ++calls;
  };
  auto r = dtf::surfaces::trackSeeds(f, seeds, 5000, o);
  EXPECT_GE(calls, 1u);
  EXPECT_EQ(lastDone, 5000u);
  EXPECT_EQ(lastPlanned, 5000u);
  EXPECT_EQ(r.lines.lineCount(), 5000u);
  EXPECT_FALSE(r.cancelled);
  std::atomic<bool> cancel{true};
  o.cancel = &cancel;
  o.progress = nullptr;
  auto c = dtf::surfaces::trackSeeds(f, seeds, 5000, o);
  EXPECT_TRUE(c.cancelled);
  EXPECT_EQ(c.lines.lineCount(), 0u);
  TrackingOptions bad;
  bad.stepMm = 0;
  EXPECT_THROW(dtf::surfaces::trackSeeds(f, seeds, 1, bad), dtf::UsageError);
  bad = TrackingOptions{};
  bad.minLengthMm = 300;
  EXPECT_THROW(dtf::surfaces::validate(bad), dtf::UsageError);
}

namespace {

// Spatial hash of streamline points in cells of `cell` mm.
class PointHash {
public:
  PointHash(const Polylines& l, double cell) : cell_(cell) {
    for (std::size_t line = 0; line < l.lineCount(); ++line)
      for (std::uint32_t i = l.offsets[line]; i < l.offsets[line + 1]; ++i)
        cells_[key(glm::dvec3(l.points[i]))].push_back(static_cast<std::uint32_t>(line));
  }
  // Lines with a point in the 27 cells around p (with repeats).
  template <typename Fn> void near(const glm::dvec3& p, Fn fn) const {
    glm::ivec3 c = glm::ivec3(glm::floor(p / cell_));
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          auto it = cells_.find(pack(c + glm::ivec3(dx, dy, dz)));
          if (it != cells_.end())
            for (auto l : it->second)
              fn(l);
        }
  }

private:
  static std::int64_t pack(const glm::ivec3& c) {
    return (static_cast<std::int64_t>(c.x + 4096) << 26) | (static_cast<std::int64_t>(c.y + 4096) << 13) |
           (c.z + 4096);
  }
  std::int64_t key(const glm::dvec3& p) const { return pack(glm::ivec3(glm::floor(p / cell_))); }
  double cell_;
  std::unordered_map<std::int64_t, std::vector<std::uint32_t>> cells_;
};

// Mean over the points of `a`'s line la of the distance to the closest point of `b`'s line lb.
double meanClosest(const Polylines& a, std::size_t la, const Polylines& b, std::size_t lb) {
  double sum = 0;
  for (std::uint32_t i = a.offsets[la]; i < a.offsets[la + 1]; ++i) {
    float best = 1e30f;
    for (std::uint32_t j = b.offsets[lb]; j < b.offsets[lb + 1]; ++j) {
      const glm::vec3 d = a.points[i] - b.points[j];
      best = std::min(best, glm::dot(d, d));
    }
    sum += std::sqrt(static_cast<double>(best));
  }
  return sum / (a.offsets[la + 1] - a.offsets[la]);
}

// For each streamline of `a`: the mean closest-point distance to the nearest streamline of `b`, the minimum
// taken over the 12 lines of `b` that pass within one 4 mm hash cell of the most of its points.
std::vector<double> nearestStreamlineDistances(const Polylines& a, const Polylines& b) {
  PointHash hash(b, 4.0);
  std::vector<double> out(a.lineCount());
  std::vector<int> hits(b.lineCount(), 0);
  std::vector<std::uint32_t> stamp(b.lineCount(), 0), touched;
  std::uint32_t now = 0;
  for (std::size_t la = 0; la < a.lineCount(); ++la) {
    touched.clear();
    for (std::uint32_t i = a.offsets[la]; i < a.offsets[la + 1]; ++i) {
      ++now; // counts each line of b once per point of a
      hash.near(glm::dvec3(a.points[i]), [&](std::uint32_t l) {
        if (stamp[l] == now) return;
        stamp[l] = now;
        if (hits[l]++ == 0) touched.push_back(l);
      });
    }
    std::vector<std::pair<int, std::uint32_t>> ranked;
    for (auto l : touched)
      ranked.emplace_back(-hits[l], l), hits[l] = 0;
    std::sort(ranked.begin(), ranked.end());
    double best = 1e30;
    for (std::size_t c = 0; c < std::min<std::size_t>(12, ranked.size()); ++c)
      best = std::min(best, meanClosest(a, la, b, ranked[c].second));
    out[la] = best;
  }
  return out;
}

} // namespace

// MRtrix tckgen -algorithm Tensor_Det (Euler, step 1 mm, FA 0.15, 60 deg, min length 30 mm, max 300 mm, seeds
// and stop mask from mask.nii.gz) made tracks_det.tck; the same settings here (on DIPY's WLS tensors rather
// than MRtrix's internal fit) with 2000 different random seeds must reproduce its bundles. Measure: for each
// reference streamline, the mean closest-point distance to our nearest streamline (a one-sided mean of
// closest distances, as in MDF/Hausdorff-type bundle comparisons). With 3 mm voxels, 4 mm is a bit more than
// one voxel.
TEST(TrackingRealData, ReproducesTheMrtrixReferenceBundles) {
  DTF_SHARED_FILE(tensorPath, "iu_prisma_dwi/derived/dti_tensor.nii.gz");
  DTF_SHARED_FILE(maskPath, "iu_prisma_dwi/derived/mask.nii.gz");
  DTF_SHARED_FILE(tckPath, "iu_prisma_dwi/derived/tracks_det.tck");
  const TensorField field = dtf::io::readTensorVolume(tensorPath.string()).field;
  const dtf::ScalarVolume m = dtf::io::readScalarVolume(maskPath.string());
  dtf::MaskVolume mask(m.grid, 1);
  for (std::size_t i = 0; i < m.data.size(); ++i)
    mask.data[i] = m.data[i] > 0;
  const Polylines reference = dtf::io::readTck(tckPath.string());

  auto fractionBelow = [](const std::vector<double>& d, double t) {
    return static_cast<double>(std::count_if(d.begin(), d.end(), [t](double x) { return x < t; })) / d.size();
  };
  auto medianOf = [](std::vector<double> d) {
    std::nth_element(d.begin(), d.begin() + d.size() / 2, d.end());
    return d[d.size() / 2];
  };
  // Euler as tckgen ran; RK4 (our default) must reproduce the bundles as well.
  for (bool rk4 : {false, true}) {
    SCOPED_TRACE(rk4 ? "RK4" : "Euler");
    TrackingOptions o;
    o.stepMm = 1;
    o.faStop = 0.15;
    o.maxAngleDeg = 60;
    o.minLengthMm = 30;
    o.maxLengthMm = 300;
    o.rk4 = rk4;
    o.mask = &mask;
    auto ours = dtf::surfaces::trackSelect(field, dtf::surfaces::seedsFromMask(mask, 0, 20240601), 2000, o);
    ASSERT_EQ(ours.lines.lineCount(), 2000u);

    std::vector<double> refToOurs = nearestStreamlineDistances(reference, ours.lines);
    std::vector<double> oursToRef = nearestStreamlineDistances(ours.lines, reference);
    const double refFrac = fractionBelow(refToOurs, 4.0), ourFrac = fractionBelow(oursToRef, 4.0);
    std::printf("%s: reference -> ours: median %.2f mm, %.1f%% < 3 mm, %.1f%% < 4 mm; ours -> reference: "
                "median %.2f mm, %.1f%% < 4 mm\n",
                rk4 ? "RK4" : "Euler", medianOf(refToOurs), 100 * fractionBelow(refToOurs, 3.0),
                100 * refFrac, medianOf(oursToRef), 100 * ourFrac);
    EXPECT_GE(refFrac, 0.8);
    EXPECT_GE(ourFrac, 0.8); // and we do not invent bundles MRtrix does not have
    EXPECT_LT(medianOf(refToOurs), 3.0);

    // Length distribution: the README gives a median of 66 mm for the reference.
    std::vector<double> lengths;
    for (std::size_t l = 0; l < ours.lines.lineCount(); ++l)
      lengths.push_back(static_cast<double>(ours.lines.offsets[l + 1] - ours.lines.offsets[l] - 1) *
                        o.stepMm);
    EXPECT_NEAR(medianOf(lengths), 66.0, 8.0);
  }
  // Negative control: the frame mistake the README warns about (the LAS x flip not applied to the tensor, so
  // Dxy and Dxz have the wrong sign) must fail this measure.
  {
    TensorField wrong = field;
    for (auto& t : wrong.tensors)
      t.xy = -t.xy, t.xz = -t.xz;
    TrackingOptions o;
    o.rk4 = false;
    o.maxLengthMm = 300;
    o.mask = &mask;
    auto bad = dtf::surfaces::trackSelect(wrong, dtf::surfaces::seedsFromMask(mask, 0, 20240601), 2000, o);
    const double frac = fractionBelow(nearestStreamlineDistances(reference, bad.lines), 4.0);
    std::printf("unrotated tensors: reference -> ours %.1f%% < 4 mm\n", 100 * frac);
    EXPECT_LT(frac, 0.6);
  }
}
