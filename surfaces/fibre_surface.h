// SPDX-License-Identifier: GPL-3.0-or-later
// Fibre-following surfaces (the paper's brain figures use Anwander et al.'s dissection-like surfaces):
// surfaces to which the principal diffusion direction e1 is tangent, so that projecting the tensor onto
// them (paper Eq. 1) throws little of the fibre direction away.
//
// Method: a stream surface of the e1 field (Hultquist-style advancing front). A seed line drawn across a
// slice is sampled into particles; each particle is traced along +e1 and -e1 (RK4, sign kept continuous)
// and consecutive fronts are stitched into triangles. By construction e1 lies in the surface wherever it is
// traced, unlike a relaxed plane, which only approximately aligns and needs a global solve. Where
// neighbouring particles diverge beyond `maxGapFactor` seed spacings the surface tears instead of
// inserting particles (an approximation: diverging fans become ribbons with gaps).
#pragma once

#include "io/model/geometry.h"
#include "io/model/tensor_field.h"

namespace dtf::surfaces {

struct FibreSurfaceOptions {
  double stepMm = 0.5;         // integration step
  double maxLengthMm = 40.0;   // per direction from the seed line
  double faStop = 0.15;        // stop a particle where FA drops below this
  double maxAngleDeg = 45.0;   // stop where the direction turns more than this in one step
  double seedSpacingMm = 0.75; // particle spacing along the seed line
  double maxGapFactor = 3.0;   // tear between neighbours further apart than this many seed spacings
};

// Stream surface of e1 seeded on the segment a-b (world RAS mm). Throws InputError when the seed line lies
// outside the data or no particle can be traced. Normals are computed; the result may self-intersect where
// fibres fold back: check with findSelfIntersections (surfaces/mesh_checks.h).
Mesh fibreSurfaceFromLine(const TensorField& field, const glm::dvec3& a, const glm::dvec3& b,
                          const FibreSurfaceOptions& options = {});

// Quality of a surface for the fabric: FA- and area-weighted mean of |e1 . n| over the surface (0 = the
// fibre direction lies in the surface everywhere, 1 = fibres cross it at right angles). `weightSum` gets
// the total weight (0 when the surface misses the data).
double fibreCrossingScore(const Mesh& mesh, const TensorField& field, double* weightSum = nullptr);

} // namespace dtf::surfaces
