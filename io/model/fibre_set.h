// SPDX-License-Identifier: GPL-3.0-or-later
// The canonical in-memory crossing-fibre volume ("fibre set"): per voxel up to `maxFibres` fibre
// populations, each a unit direction in WORLD RAS (already rotated out of any voxel/bvec frame) with an
// amplitude (FOD peak amplitude, volume fraction, or 1 where the file carries no amplitude), sorted
// strongest first. Readers (io/formats/fibre_io.h) convert into this form, like TensorField for tensors.
//
// Storage: fibres[grid.index(i,j,k) * maxFibres + n] for n < maxFibres; a slot with amplitude 0 (and a
// zero direction) is absent, and absent slots always follow the present ones. Directions have no sign.
//
// The interpolation here (interpolateFibres) is the CPU reference of the renderer's per-pixel lobe
// matching: directions cannot be interpolated per component (signs are arbitrary, peak order differs
// between voxels), so each neighbour's lobes are matched to a reference voxel's lobes by |cos| and
// sign-aligned before they are averaged.
#pragma once

#include "io/model/grid.h"
#include "io/model/tensor_field.h"
#include "io/model/volume.h"

#include <glm/glm.hpp>
#include <vector>

namespace dtf {

struct Fibre {
  glm::vec3 direction{0.0f}; // unit, world RAS; zero when absent
  float amplitude = 0.0f;    // > 0 when present
};

struct FibreSet {
  Grid grid;
  int maxFibres = 0;         // slots per voxel (K)
  std::vector<Fibre> fibres; // grid.voxelCount() * maxFibres

  Fibre* at(int i, int j, int k) {
    return &fibres[grid.index(i, j, k) * static_cast<std::size_t>(maxFibres)];
  }
  const Fibre* at(int i, int j, int k) const {
    return &fibres[grid.index(i, j, k) * static_cast<std::size_t>(maxFibres)];
  }
  // Number of present fibres of voxel `index` (grid.index order; normalised sets: absent slots last).
  int count(std::size_t index) const;
  // Voxels holding at least one fibre.
  std::size_t occupiedVoxels() const;
  // Largest amplitude anywhere (0 for an empty set).
  float maxAmplitude() const;
};

// An empty set (all slots absent) on `grid` with k slots per voxel. Throws InputError for k < 1 or k > 16.
FibreSet makeFibreSet(const Grid& grid, int k);

// Sorts the fibres of every voxel strongest first and moves absent slots (amplitude <= 0, non-finite or a
// zero direction) to the end; normalises present directions.
void normaliseFibres(FibreSet& set);

// A carrier tensor per voxel for code that needs a TensorField (surface clipping to the data): the sum of
// amplitude-weighted d d^T plus a small isotropic part, in mm^2/s-like units (not a diffusion tensor; FA
// of it has no meaning). Valid where the voxel has fibres.
TensorField fibreCarrierField(const FibreSet& set);

// The fibres at a fractional voxel index, by the renderer's rule: the 8 surrounding voxels with trilinear
// weights; in each voxel lobes below relativeThreshold x that voxel's strongest are dropped; the voxel with
// the largest weight among those with fibres is the reference; each reference lobe takes, from every other
// voxel, the lobe with the largest |cos| to it (when |cos| >= minMatchCos and no other reference lobe is
// closer to that lobe: mutual best), sign-aligned to it, weighted by
// trilinear weight x amplitude. Directions are the normalised weighted sums, amplitudes the weighted mean
// amplitude over the voxels with fibres. Returns at most `maxOut` fibres, strongest first; empty when
// fewer than half the weight lies on voxels with fibres.
// With sortByAmplitude false the fibres keep the reference voxel's slot order (absent ones left out are
// then marked by amplitude 0 in their slot: the result has exactly min(maxOut, maxFibres, 3) entries).
std::vector<Fibre> interpolateFibres(const FibreSet& set, const glm::dvec3& ijk, float relativeThreshold,
                                     int maxOut = 3, float minMatchCos = 0.5f, bool sortByAmplitude = true);

// The renderer's slot layout: the first min(K, 3) fibres of each voxel, those below relativeThreshold x the
// voxel's strongest dropped, re-slotted and sign-flipped so that a slot holds the same bundle with the same
// sign from voxel to voxel. This is the lobe matching by |cos| between neighbours: each voxel, in scan
// order, takes the assignment of its fibres to slots that best agrees in |cos| x amplitude with its
// already-slotted face neighbours (strongest first where no neighbour has fibres), and flips each fibre to
// agree in sign with them. One advection field per slot then follows one bundle, even where the bundles'
// amplitudes are equal and their strength order flips between voxels, and slots can be interpolated per
// component (interpolateSlots). Unlike a normalised set, absent slots may lie between present ones. Seams
// remain where two propagation fronts disagree.
FibreSet continuousSlots(const FibreSet& set, float relativeThreshold = 0.0f);

// The renderer's interpolation of continuousSlots output at a fractional voxel index (its CPU reference):
// per slot, the trilinear interpolation of the dyadic amplitude x d d^T and of amplitude over the 8
// surrounding voxels; amplitude = interpolated amplitude / the weight of voxels with fibres; direction = the
// principal eigenvector of the interpolated dyadic (sign-free: where voxels disagree, a sign seam or noisy
// directions, it turns continuously as an interpolated tensor's does), signed along the interpolated
// amplitude x direction. Exactly min(K, 3) entries in slot order (amplitude 0 = none); all absent where less
// than half the weight lies on voxels with fibres.
std::vector<Fibre> interpolateSlots(const FibreSet& slotted, const glm::dvec3& ijk);

// Fibre coherence of the first fibres: over neighbouring voxel pairs (13 neighbour directions) of
// single-fibre voxels (no second fibre above half the first), the fraction where both point along the step
// between them (|cos| > 0.866 with the step's world direction). `frameChange` is applied to every direction
// first (the other frame hypothesis of a file that does not say its frame, e.g. the grid rotation). Used to
// tell voxel-frame from world-frame peak files: fibres continue along themselves only in the right frame.
struct Coherence {
  double score = 0;      // fraction of pairs along the step (0..1)
  std::size_t pairs = 0; // pairs counted
};
Coherence fibreCoherence(const FibreSet& set, const glm::dmat3& frameChange = glm::dmat3(1.0));

} // namespace dtf
