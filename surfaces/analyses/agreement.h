// SPDX-License-Identifier: GPL-3.0-or-later
// How well the fabric agrees with tractography on a surface: the fabric's threads follow the principal
// eigenvector of the tensor projected onto the surface (paper Eq. 1, T' = P T P^T with P = I - n n^T), so
// comparing that direction with the tangent of tracts that run along the surface says whether the
// texture points where the fibres go. With a fibre set (crossing fibres) each tract point is measured against
// the nearest fibre population in the surface instead, as the multi-population fabric weaves every one of
// them. Used by `dtfabric compare`; inputs are world RAS mm throughout.
#pragma once

#include "io/model/fibre_set.h"
#include "io/model/geometry.h"
#include "io/model/tensor_field.h"

#include <cstdint>
#include <vector>

namespace dtf::surfaces {

// The fabric's in-surface principal direction at a point: e1 of T' = P T P^T for the unit normal `n`.
// Returns false when T' is degenerate: zero/non-finite, or its two in-plane eigenvalues differ by less than
// `minPlanarAnisotropy` x their sum (an in-plane isotropic tensor has no preferred direction).
// `planarAnisotropy` gets (l1' - l2') / (l1' + l2') when given.
bool projectedPrincipalDirection(const SymTensor& t, const glm::dvec3& n, glm::dvec3& dir,
                                 double minPlanarAnisotropy = 0.02, double* planarAnisotropy = nullptr);

struct AgreementOptions {
  double nearMm = 2.0;               // only tract points at most this far from the surface
  int bins = 9;                      // histogram bins over 0..90 degrees
  double minTangentFraction = 0.25;  // skip points whose tangent, projected onto the surface, is shorter
                                     // than this fraction of its length (the tract crosses the surface
                                     // within ~14.5 degrees of its normal: no in-surface direction)
  double minPlanarAnisotropy = 0.02; // see projectedPrincipalDirection
  // Fibre sets: populations below this fraction of their voxel's strongest are dropped (the renderer's
  // --fibre-threshold), and so are those whose projection onto the surface is shorter than
  // minInSurfaceFraction of their length (they leave the surface steeply and fade out of the fabric).
  float fibreThreshold = 0.15f;
  double minInSurfaceFraction = 0.25;
};

struct AgreementResult {
  std::vector<double> anglesDeg;     // per compared point, 0..90
  std::vector<std::uint32_t> lineOf; // per compared point, its streamline
  std::size_t nearPoints = 0;        // tract points within nearMm
  std::size_t skippedTangent = 0;    // ... skipped: projected tangent too short
  std::size_t skippedDegenerate = 0; // ... skipped: T' degenerate (fibre sets: no population in the
                                     // surface) or outside the data
  double meanDeg = 0, medianDeg = 0, fracBelow15 = 0; // NaN when no point was compared: nothing measured
  double binDeg = 10;
  std::vector<std::size_t> histogram; // counts per bin [b*binDeg, (b+1)*binDeg)
};

// For every tract point within nearMm of `surface`: the angle between the tract tangent (central
// difference, one-sided at the ends) projected onto the surface at the closest point (triangle normal)
// and the projected principal direction of the tensor interpolated at that closest point.
// Throws InputError when the surface has no triangles; UsageError for bad options.
AgreementResult tractSurfaceAgreement(const Polylines& tracts, const Mesh& surface, const TensorField& field,
                                      const AgreementOptions& options = {});

// The same against a fibre set: the angle between the projected tangent and the nearest of the fibre
// populations there (interpolateFibres at the closest point, populations below options.fibreThreshold
// dropped), each projected onto the surface (P d).
AgreementResult tractSurfaceAgreement(const Polylines& tracts, const Mesh& surface, const FibreSet& fibres,
                                      const AgreementOptions& options = {});

// The angle in degrees (0..90) between the unit in-surface direction `tangent` and the nearest of `fibres`
// projected onto the plane with unit normal `n`; populations whose projection is shorter than
// minInSurfaceFraction are skipped. Returns false when none is left.
bool nearestPopulationAngle(const std::vector<Fibre>& fibres, const glm::dvec3& n, const glm::dvec3& tangent,
                            double minInSurfaceFraction, double& angleDeg);

// Summary statistics and histogram of `anglesDeg` (fills meanDeg .. histogram of `r`).
void summarizeAngles(AgreementResult& r, int bins);

} // namespace dtf::surfaces
