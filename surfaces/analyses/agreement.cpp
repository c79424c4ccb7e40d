// SPDX-License-Identifier: GPL-3.0-or-later
#include "surfaces/analyses/agreement.h"

#include "io/model/error.h"
#include "surfaces/mesh_checks.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace dtf::surfaces {

bool projectedPrincipalDirection(const SymTensor& t, const glm::dvec3& n, glm::dvec3& dir,
                                 double minPlanarAnisotropy, double* planarAnisotropy) {
  if (t.isZero() || !t.isFinite()) return false;
  const glm::dmat3 p = glm::dmat3(1.0) - glm::outerProduct(n, n);
  const glm::dmat3 tp = p * t.toMat() * glm::transpose(p);
  const EigenSystem e = eigenDecompose(tp);
  // T' n = 0, so the in-plane eigenvalues are l1' (the largest) and trace(T') - l1'.
  const double l1 = e.values[0], l2 = tp[0][0] + tp[1][1] + tp[2][2] - l1;
  if (!(l1 > 0) || std::abs(glm::dot(e.vectors[0], n)) > 0.5) return false;
  const double aniso = (l1 - l2) / (l1 + std::abs(l2));
  if (planarAnisotropy) *planarAnisotropy = aniso;
  if (!(aniso >= minPlanarAnisotropy)) return false;
  dir = e.vectors[0];
  return true;
}

void summarizeAngles(AgreementResult& r, int bins) {
  bins = std::max(1, bins);
  r.binDeg = 90.0 / bins;
  r.histogram.assign(static_cast<std::size_t>(bins), 0);
  r.meanDeg = r.medianDeg = r.fracBelow15 = std::numeric_limits<double>::quiet_NaN();
  if (r.anglesDeg.empty()) return;
  double sum = 0;
  std::size_t below = 0;
  for (double a : r.anglesDeg) {
    sum += a;
    if (a < 15.0) ++below;
    int b = std::clamp(static_cast<int>(a / r.binDeg), 0, bins - 1);
    ++r.histogram[static_cast<std::size_t>(b)];
  }
  r.meanDeg = sum / static_cast<double>(r.anglesDeg.size());
  r.fracBelow15 = static_cast<double>(below) / static_cast<double>(r.anglesDeg.size());
  std::vector<double> sorted = r.anglesDeg;
  std::sort(sorted.begin(), sorted.end());
  const std::size_t m = sorted.size();
  r.medianDeg = m % 2 ? sorted[m / 2] : 0.5 * (sorted[m / 2 - 1] + sorted[m / 2]);
}

bool nearestPopulationAngle(const std::vector<Fibre>& fibres, const glm::dvec3& n, const glm::dvec3& tangent,
                            double minInSurfaceFraction, double& angleDeg) {
  double bestCos = -1;
  for (const Fibre& f : fibres) {
    if (!(f.amplitude > 0)) continue;
    const glm::dvec3 d(f.direction);
    const double dl = glm::length(d);
    if (!(dl > 0)) continue;
    const glm::dvec3 dp = d - glm::dot(d, n) * n;
    const double dpl = glm::length(dp);
    if (dpl < minInSurfaceFraction * dl) continue;
    bestCos = std::max(bestCos, std::abs(glm::dot(tangent, dp / dpl)));
  }
  if (bestCos < 0) return false;
  angleDeg = std::acos(std::min(1.0, bestCos)) * 180.0 / M_PI;
  return true;
}

namespace {

// Every tract point within nearMm of the surface with its in-surface tangent; `angleAt(closest, n, tangent,
// angleDeg)` gives the angle to the fabric's direction there (false: none).
template <class AngleAt>
AgreementResult measureAgreement(const Polylines& tracts, const Mesh& surface, const AgreementOptions& o,
                                 AngleAt angleAt) {
  if (!(o.nearMm >= 0)) throw UsageError("--near must be >= 0 mm");
  if (o.bins < 1 || o.bins > 90) throw UsageError("histogram bins must be 1..90");
  if (surface.empty()) throw InputError("the comparison surface has no triangles");
  DistanceQuery query(surface);
  AgreementResult r;
  for (std::size_t l = 0; l < tracts.lineCount(); ++l) {
    const std::uint32_t b = tracts.offsets[l], e = tracts.offsets[l + 1];
    if (e - b < 2) continue;
    for (std::uint32_t i = b; i < e; ++i) {
      glm::vec3 closest;
      std::uint32_t tri = 0;
      if (query.distance(tracts.points[i], &closest, &tri) > o.nearMm) continue;
      ++r.nearPoints;
      const glm::dvec3 tangent =
          glm::dvec3(tracts.points[std::min(i + 1, e - 1)]) - glm::dvec3(tracts.points[i > b ? i - 1 : b]);
      const glm::dvec3 a(surface.positions[surface.indices[3 * tri]]),
          bb(surface.positions[surface.indices[3 * tri + 1]]),
          c(surface.positions[surface.indices[3 * tri + 2]]);
      glm::dvec3 n = glm::cross(bb - a, c - a);
      const double tl = glm::length(tangent), nl = glm::length(n);
      if (!(tl > 0) || !(nl > 0)) {
        ++r.skippedTangent;
        continue;
      }
      n /= nl;
      const glm::dvec3 tp = tangent - glm::dot(tangent, n) * n;
      const double tpl = glm::length(tp);
      if (tpl < o.minTangentFraction * tl) {
        ++r.skippedTangent;
        continue;
      }
      double angle = 0;
      if (!angleAt(glm::dvec3(closest), n, tp / tpl, angle)) {
        ++r.skippedDegenerate;
        continue;
      }
      r.anglesDeg.push_back(angle);
      r.lineOf.push_back(static_cast<std::uint32_t>(l));
    }
  }
  summarizeAngles(r, o.bins);
  return r;
}

} // namespace

AgreementResult tractSurfaceAgreement(const Polylines& tracts, const Mesh& surface, const TensorField& field,
                                      const AgreementOptions& o) {
  const glm::dmat4 worldToVoxel = glm::inverse(field.grid.voxelToWorld);
  return measureAgreement(
      tracts, surface, o,
      [&](const glm::dvec3& p, const glm::dvec3& n, const glm::dvec3& tangent, double& angle) {
        glm::dvec3 fabric;
        const SymTensor t = field.sample(glm::dvec3(worldToVoxel * glm::dvec4(p, 1.0)));
        if (!projectedPrincipalDirection(t, n, fabric, o.minPlanarAnisotropy)) return false;
        const double cosA = std::min(1.0, std::abs(glm::dot(tangent, fabric)));
        angle = std::acos(cosA) * 180.0 / M_PI;
        return true;
      });
}

AgreementResult tractSurfaceAgreement(const Polylines& tracts, const Mesh& surface, const FibreSet& fibres,
                                      const AgreementOptions& o) {
  if (!(o.fibreThreshold >= 0 && o.fibreThreshold < 1))
    throw UsageError("the fibre threshold must be in [0, 1)");
  const glm::dmat4 worldToVoxel = glm::inverse(fibres.grid.voxelToWorld);
  return measureAgreement(
      tracts, surface, o,
      [&](const glm::dvec3& p, const glm::dvec3& n, const glm::dvec3& tangent, double& angle) {
        const glm::dvec3 ijk(worldToVoxel * glm::dvec4(p, 1.0));
        const std::vector<Fibre> here = interpolateFibres(fibres, ijk, o.fibreThreshold, fibres.maxFibres);
        return nearestPopulationAngle(here, n, tangent, o.minInSurfaceFraction, angle);
      });
}

} // namespace dtf::surfaces
