// SPDX-License-Identifier: GPL-3.0-or-later
// The orientation check: is a gradient table (or a tensor file's frame) right, or is an axis negated or
// swapped? A wrong table leaves DEC colours unchanged (they use |e1|) but turns every direction. The check
// scores each of the 24 signed axis permutations by fibre coherence over the white matter (Schilling et
// al., Magn Reson Imaging 58:82-89, 2019): fibres continue along themselves, so neighbouring voxels whose
// principal directions both point along the step between them are common under the true table and rare
// under a wrong one. It runs on a fitted TensorField (world RAS), after fitting and before any surface.
//
// Frames. A candidate M is a 3x3 signed permutation acting on the gradient table's own frame (the FSL bvec
// frame for a DWI: voxel axes with x negated when det(affine) > 0); the corrected table is M * given.
// With A the table frame -> world rotation (io::bvecFrameToWorld for a DWI, the identity for a tensor file
// whose directions are judged in world RAS), a fit against the table M*g equals the fit against g with its
// tensors turned by G = A M A^T (see transformedField for why this is exact).
#pragma once

#include "io/model/fibre_set.h"
#include "io/model/tensor_field.h"
#include "io/model/volume.h"

#include <array>
#include <cstddef>
#include <string>
#include <vector>

namespace dtf::surfaces {

// A signed axis permutation, row-major integer entries in {-1, 0, 1}.
struct AxisTransform {
  std::array<int, 9> m{1, 0, 0, 0, 1, 0, 0, 0, 1};

  bool isIdentity() const;
  glm::dmat3 matrix() const; // the same as a glm (column-major) matrix
  glm::dvec3 apply(const glm::dvec3& v) const;
  AxisTransform inverse() const; // the transpose
  // Short name of the new table's rows in terms of the given one, e.g. "x y z" (identity), "-x y z",
  // "y x z", "z x -y".
  std::string name() const;
  bool operator==(const AxisTransform& o) const { return m == o.m; }
};

// Product a*b of two signed permutations.
AxisTransform compose(const AxisTransform& a, const AxisTransform& b);
// True when a == b or a == -b (the same measurement: a table and its negation give the same tensors).
bool sameUpToSign(const AxisTransform& a, const AxisTransform& b);

// The 24 signed permutations up to global sign: of the 48 signed permutation matrices, one of each pair
// {P, -P}, the one with fewer negative entries (3 non-zero entries, so never a tie). The identity first.
std::vector<AxisTransform> orientationCandidates();

// The field a fit against the table M*g would give, from the field fitted against g (no refit):
// D' = G D G^T with G = A M A^T, A = tableToWorld (world gradients A*M*g = G*(A*g)). Exact for linear and
// weighted least squares: the design row of a volume is (1, -b q(g)) with q(g).d = g^T D g, and
// q(G g).d = q(g).t(d) for t(D) = G^T D G, an invertible linear map of the six unknowns. So the turned
// table's design is X' = X T over the same log-signals (T = diag(1, t)); its least-squares solution is
// T^-1 beta, i.e. D' = G D G^T, with the same predictions and residuals, hence the same WLS weights (taken
// from the OLS prediction) and the same weighted solution turned alike. Only rounding differs (a refit
// agrees to float precision; test_orientation_check). Invalid voxels stay invalid.
TensorField transformedField(const TensorField& field, const glm::dmat3& tableToWorld,
                             const AxisTransform& m);

struct CheckOptions {
  double faThreshold = 0.3;          // white matter: valid, inside the mask, FA >= this
  double cosThreshold = 0.866;       // |cos| between e1 and the step for both voxels (30 degrees)
  std::size_t minWhiteMatter = 3000; // fewer white-matter voxels: inconclusive
  double minMargin = 0.07;           // best over the runner-up below 1 + this: inconclusive
};

struct CandidateScore {
  AxisTransform transform;
  double score = 0;      // coherent neighbour pairs per white-matter voxel
  std::size_t pairs = 0; // coherent neighbour pairs (each unordered pair once)
};

enum class Verdict { Ok, Corrected, Inconclusive };
const char* verdictName(Verdict v); // "ok", "corrected", "inconclusive"

struct OrientationReport {
  Verdict verdict = Verdict::Inconclusive;
  AxisTransform correction;               // corrected table = correction * given; identity unless corrected
  std::vector<CandidateScore> candidates; // orientationCandidates() order (identity = the given table first)
  std::size_t best = 0;                   // index of the highest score
  std::size_t runnerUp = 0;               // index of the second highest
  double scoreGiven = 0, scoreBest = 0;
  double margin = 0;          // scoreBest / score(runnerUp) - 1
  std::size_t maskVoxels = 0; // voxels considered (valid and inside the mask)
  std::size_t whiteMatterVoxels = 0;
  std::string whiteMatterRule; // how white matter was chosen, e.g. "FA >= 0.30"
  std::string reason;          // one line: why this verdict
  CheckOptions options;        // the thresholds used
};

// Scores every candidate on `field` (world RAS, fitted with the given table) and decides. `mask` (same
// grid, non-zero = inside; nullptr = every valid voxel) restricts the voxels; white matter is the voxels
// in it with FA >= options.faThreshold. One eigen-decomposition per white-matter voxel; each candidate
// then costs 13 neighbour tests per voxel. Throws InputError for a mask on another grid.
OrientationReport checkOrientation(const TensorField& field, const glm::dmat3& tableToWorld,
                                   const MaskVolume* mask = nullptr, const CheckOptions& options = {});

// The same check on a fibre set's first (strongest) fibre per voxel. `storedToWorld` is the rotation the
// reader applied from the file's stored frame to world RAS (identity for world-frame peaks); candidates act
// on that stored frame, so a file read in the wrong frame or layout scores best under the correction from
// the frame it was read in to its true one. White matter: occupied voxels inside `mask` with, when `fa` is
// given (a paired tensor on the same grid), FA >= options.faThreshold; without FA, voxels with a single
// dominant fibre (no second above half the first) whose first amplitude is at least the median over all
// voxels with fibres (unit peaks: every dominant voxel). On the real Prisma peaks this rule gives the same
// verdicts as the tensor's FA, with margins about 10% against 14% (the measurements are in the source and
// tests). Throws InputError for a mask or FA on another grid.
OrientationReport checkFibreOrientation(const FibreSet& set, const glm::dmat3& storedToWorld,
                                        const MaskVolume* mask = nullptr, const ScalarVolume* fa = nullptr,
                                        const CheckOptions& options = {});

// Voxel indices of the three slices a person looks at to judge the directions, chosen from `field` (the
// candidate under inspection): axial through the body of the corpus callosum (the axial slice with the most
// left-right white matter near the midline), coronal through the corticospinal tracts (the most
// superior-inferior white matter), sagittal at the midline (the most left-right white matter crossing it).
// Indices are along surfaces::voxelAxisFor of each slice axis.
struct EvidenceSlices {
  int axial = -1, coronal = -1, sagittal = -1;
};
EvidenceSlices chooseEvidenceSlices(const TensorField& field, const MaskVolume* mask = nullptr,
                                    double faThreshold = 0.3);

} // namespace dtf::surfaces
