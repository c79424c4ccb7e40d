// SPDX-License-Identifier: GPL-3.0-or-later
// Analytic phantoms. Every grid is RAS, axis-aligned, centred at the world origin with isotropic spacing.
#include "io/phantoms.h"

#include "io/model/error.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>

namespace dtf::io {

namespace {

constexpr double kPi = 3.14159265358979323846;
// Prolate "fibre" tensor eigenvalues (mm^2/s): FA 0.80, MD 7.7e-4, typical of white matter.
constexpr double kAxial = 1.7e-3, kRadial = 0.3e-3;

// RAS, or with las the x index running towards the patient's left (same world positions, mirrored indices).
Grid centredGrid(glm::ivec3 dims, double spacing, bool las) {
  glm::dmat4 a(1.0);
  for (int c = 0; c < 3; ++c) {
    a[c][c] = spacing;
    a[3][c] = -0.5 * (dims[c] - 1) * spacing;
  }
  if (las) {
    a[0][0] = -spacing;
    a[3][0] = 0.5 * (dims[0] - 1) * spacing;
  }
  return Grid::fromAffine(dims, a);
}

glm::dmat3 prolate(const glm::dvec3& dir, double axial = kAxial, double radial = kRadial) {
  glm::dvec3 e = glm::normalize(dir);
  return radial * glm::dmat3(1.0) + (axial - radial) * glm::outerProduct(e, e);
}

glm::dvec3 direction(double azimuthDeg, double elevationDeg) {
  double az = azimuthDeg * kPi / 180, el = elevationDeg * kPi / 180;
  return {std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el)};
}

ScalarVolume faOf(const TensorField& f) {
  ScalarVolume fa(f.grid, 1);
  for (std::size_t i = 0; i < f.tensors.size(); ++i)
    if (f.valid[i]) fa.data[i] = static_cast<float>(computeMetrics(eigenDecompose(f.tensors[i])).fa);
  return fa;
}

void setTensor(TensorField& f, std::size_t i, const glm::dmat3& m) {
  SymTensor t = SymTensor::fromMat(m);
  f.tensors[i] = t;
  f.valid[i] = t.isFinite() && !t.isZero();
  if (!f.valid[i]) f.tensors[i] = SymTensor{};
}

// Calls fn(index, world position) for every voxel.
void forEachVoxel(const Grid& g, const std::function<void(std::size_t, const glm::dvec3&)>& fn) {
  for (int k = 0; k < g.dims.z; ++k)
    for (int j = 0; j < g.dims.y; ++j)
      for (int i = 0; i < g.dims.x; ++i)
        fn(g.index(i, j, k), g.toWorld(glm::dvec3(i, j, k)));
}

Phantom sphere(const PhantomOptions& o) {
  Phantom p;
  Grid g = centredGrid(glm::ivec3(o.size), o.spacing, o.las);
  p.tensors = makeTensorField(g);
  p.scalar = ScalarVolume(g, 1);
  p.isovalue = 0.35 * (o.size - 1) * o.spacing;
  forEachVoxel(g, [&](std::size_t i, const glm::dvec3& x) {
    double r = glm::length(x);
    p.scalar.data[i] = static_cast<float>(r);
    if (r < 1e-9) return; // the Hessian of |x| is undefined at the centre
    glm::dvec3 n = x / r;
    setTensor(p.tensors, i, (glm::dmat3(1.0) - glm::outerProduct(n, n)) / r);
  });
  return p;
}

Phantom constant(const PhantomOptions& o) {
  Phantom p;
  Grid g = centredGrid(glm::ivec3(o.size), o.spacing, o.las);
  p.tensors = makeTensorField(g);
  glm::dmat3 d = prolate(direction(o.angleDeg, o.elevationDeg));
  for (std::size_t i = 0; i < g.voxelCount(); ++i)
    setTensor(p.tensors, i, d);
  p.scalar = faOf(p.tensors);
  p.isovalue = 0.5;
  return p;
}

Phantom crossing(const PhantomOptions& o) {
  Phantom p;
  Grid g = centredGrid(glm::ivec3(o.size), o.spacing, o.las);
  p.tensors = makeTensorField(g);
  double extent = (o.size - 1) * o.spacing;
  double halfWidth = 0.12 * extent, halfThickness = 0.2 * extent;
  glm::dvec3 d1 = direction(-0.5 * o.crossingDeg, 0), d2 = direction(0.5 * o.crossingDeg, 0);
  glm::dmat3 t1 = prolate(d1), t2 = prolate(d2);
  forEachVoxel(g, [&](std::size_t i, const glm::dvec3& x) {
    if (std::abs(x.z) > halfThickness) return;
    glm::dvec3 inPlane(x.x, x.y, 0);
    // Distance from the line through the centre along each bundle direction.
    bool in1 = glm::length(inPlane - glm::dot(inPlane, d1) * d1) <= halfWidth;
    bool in2 = glm::length(inPlane - glm::dot(inPlane, d2) * d2) <= halfWidth;
    glm::dmat3 m(0.0);
    if (in1) m += t1;
    if (in2) m += t2;
    if (in1 || in2) setTensor(p.tensors, i, m);
  });
  p.scalar = faOf(p.tensors);
  p.isovalue = 0.5;
  return p;
}

// A polyline sampled from a parametric curve, optionally swept along y into a sheet (|y| <= sheetHalfY);
// distance queries return the nearest sample's tangent.
struct Bundle {
  std::vector<glm::dvec3> points;
  double radius = 0;
  double sheetHalfY = 0;
  // Squared distance to the nearest sample; sets `tangent` to the curve direction there.
  double distance2(glm::dvec3 x, glm::dvec3& tangent) const {
    x.y -= std::clamp(x.y, -sheetHalfY, sheetHalfY); // inside the sheet only the x-z distance counts
    double best = std::numeric_limits<double>::max();
    std::size_t bi = 0;
    for (std::size_t s = 0; s < points.size(); ++s) { // dot(x - p, x - p), written out: a phantom's hot loop
      const double dx = x.x - points[s].x, dy = x.y - points[s].y, dz = x.z - points[s].z;
      const double d2 = dx * dx + dy * dy + dz * dz;
      if (d2 < best) best = d2, bi = s;
    }
    std::size_t a = bi > 0 ? bi - 1 : bi, b = bi + 1 < points.size() ? bi + 1 : bi;
    tangent = glm::normalize(points[b] - points[a]);
    return best;
  }
};

Bundle makeBundle(const std::function<glm::dvec3(double)>& curve, double radius, double sheetHalfY = 0,
                  int samples = 160) {
  Bundle b;
  b.radius = radius;
  b.sheetHalfY = sheetHalfY;
  for (int s = 0; s <= samples; ++s)
    b.points.push_back(curve(double(s) / samples));
  return b;
}

// Head of semi-axes (0.40, 0.46, 0.40) x extent; tissue MD 1e-3, a CSF-like rim with MD 3e-3; fibre bundles
// in unit coordinates u = world / extent (so the grid spans about [-0.5, 0.5]). The middle axial slice
// (z = 0) cuts all three kinds of bundle: the callosum body (red), the cingula before and behind it
// (green) and the corticospinal columns (blue).
Phantom brain(const PhantomOptions& o) {
  Phantom p;
  Grid g = centredGrid(glm::ivec3(o.size), o.spacing, o.las);
  p.tensors = makeTensorField(g);
  double extent = (o.size - 1) * o.spacing;
  const glm::dvec3 head(0.40, 0.46, 0.40);
  std::vector<Bundle> bundles;
  // Corpus callosum: a left-right arch, highest at the midline, swept 0.12 anterior and posterior (red).
  bundles.push_back(makeBundle(
      [](double t) {
        double x = -0.30 + 0.60 * t;
        return glm::dvec3(x, 0.0, -0.02 + 0.06 * (1 - (x / 0.30) * (x / 0.30)));
      },
      0.05, 0.12));
  // Cingula: anterior-posterior bundles beside the midline, arching over the callosum (green).
  for (double side : {-1.0, 1.0})
    bundles.push_back(makeBundle(
        [side](double t) {
          double y = -0.38 + 0.76 * t;
          return glm::dvec3(side * 0.07, y, 0.11 * std::exp(-(y / 0.12) * (y / 0.12)));
        },
        0.04));
  // Corticospinal tracts: two superior-inferior columns behind the callosum, bending outwards as they
  // rise (blue).
  for (double side : {-1.0, 1.0})
    bundles.push_back(makeBundle(
        [side](double t) {
          double z = -0.38 + 0.53 * t;
          return glm::dvec3(side * (0.20 + 0.15 * (z + 0.38) * (z + 0.38)), -0.22, z);
        },
        0.055));
  forEachVoxel(g, [&](std::size_t i, const glm::dvec3& world) {
    glm::dvec3 u = world / extent;
    glm::dvec3 q = u / head;
    double r = glm::length(q);
    if (r > 1) return;
    const bool rim = r > 0.88; // CSF rim (no bundle), then tissue
    glm::dmat3 m = (rim ? 3e-3 : 1e-3) * glm::dmat3(1.0);
    double bestScore = 1; // distance / radius of the nearest bundle containing the voxel
    if (!rim)
      for (const Bundle& b : bundles) {
        glm::dvec3 tangent;
        double score = std::sqrt(b.distance2(u, tangent)) / b.radius;
        if (score < bestScore) {
          bestScore = score;
          m = prolate(tangent);
        }
      }
    setTensor(p.tensors, i, m);
  });
  p.scalar = faOf(p.tensors);
  p.isovalue = 0.4;
  return p;
}

} // namespace

namespace {

// Bretzel5 (paper Eq. 14) on x, y in [-2.2, 2.2], z in [-1, 1] function units; scale = mm per unit. The
// tensors are the Hessian with respect to world mm: H_world = H_u / scale^2.
Phantom bretzel5Phantom(const PhantomOptions& o) {
  Phantom p;
  double scale = (o.size - 1) * o.spacing / 4.4;
  int nz = std::max(2, static_cast<int>(std::lround(2.0 * scale / o.spacing)) + 1);
  Grid g = centredGrid(glm::ivec3(o.size, o.size, nz), o.spacing, o.las);
  p.tensors = makeTensorField(g);
  p.scalar = ScalarVolume(g, 1);
  p.isovalue = 0;
  forEachVoxel(g, [&](std::size_t i, const glm::dvec3& x) {
    Bretzel5Value v = bretzel5(x / scale);
    p.scalar.data[i] = static_cast<float>(v.f);
    setTensor(p.tensors, i, v.hessian / (scale * scale));
  });
  return p;
}

void checkOptions(const PhantomOptions& o) {
  if (o.size < 4 || o.size > 512)
    throw UsageError("phantom size must be between 4 and 512 voxels (got " + std::to_string(o.size) + ")");
  if (!(o.spacing >= kMinPhantomSpacingMm && o.spacing <= kMaxPhantomSpacingMm)) {
    char msg[96];
    std::snprintf(msg, sizeof msg, "phantom spacing must be between %g and %g mm (got %g)",
                  kMinPhantomSpacingMm, kMaxPhantomSpacingMm, o.spacing);
    throw UsageError(msg);
  }
}

} // namespace

std::vector<std::string> phantomNames() {
  return {"sphere", "bretzel5", "constant", "crossing", "brain"};
}

FibreSet makeFibrePhantom(const std::string& name, const PhantomOptions& o) {
  checkOptions(o);
  if (name != "crossing" && name != "constant")
    throw UsageError("phantom '" + name + "' has no fibre set (crossing and constant do)");
  Grid g = centredGrid(glm::ivec3(o.size), o.spacing, o.las);
  FibreSet f = makeFibreSet(g, name == "crossing" ? 2 : 1);
  if (name == "constant") {
    const glm::vec3 d(direction(o.angleDeg, o.elevationDeg));
    for (std::size_t i = 0; i < g.voxelCount(); ++i)
      f.fibres[i] = {d, 0.7f};
    return f;
  }
  const double extent = (o.size - 1) * o.spacing;
  const double halfWidth = 0.12 * extent, halfThickness = 0.2 * extent;
  const glm::dvec3 d1 = direction(-0.5 * o.crossingDeg, 0), d2 = direction(0.5 * o.crossingDeg, 0);
  for (int k = 0; k < g.dims.z; ++k)
    for (int j = 0; j < g.dims.y; ++j)
      for (int i = 0; i < g.dims.x; ++i) {
        const glm::dvec3 x = g.toWorld(glm::dvec3(i, j, k));
        if (std::abs(x.z) > halfThickness) continue;
        const glm::dvec3 inPlane(x.x, x.y, 0);
        const bool in1 = glm::length(inPlane - glm::dot(inPlane, d1) * d1) <= halfWidth;
        const bool in2 = glm::length(inPlane - glm::dot(inPlane, d2) * d2) <= halfWidth;
        Fibre* v = f.at(i, j, k);
        // Signs alternate too: directions have none.
        const float sign = ((i + j + k) % 3 == 0) ? -1.0f : 1.0f;
        if (in1 && in2) {
          const bool swap = (i + j + k) % 2 == 1;
          v[swap ? 1 : 0] = {sign * glm::vec3(d1), 0.4f};
          v[swap ? 0 : 1] = {glm::vec3(d2), 0.4f};
        } else if (in1) {
          v[0] = {sign * glm::vec3(d1), 0.7f};
        } else if (in2) {
          v[0] = {glm::vec3(d2), 0.7f};
        }
      }
  return f;
}

Phantom makePhantom(const std::string& name, const PhantomOptions& options) {
  checkOptions(options);
  if (name == "sphere") return sphere(options);
  if (name == "bretzel5") return bretzel5Phantom(options);
  if (name == "constant") return constant(options);
  if (name == "crossing") return crossing(options);
  if (name == "brain") return brain(options);
  throw UsageError("unknown phantom '" + name + "' (expected sphere, bretzel5, constant, crossing or brain)");
}

} // namespace dtf::io
