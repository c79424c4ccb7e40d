// SPDX-License-Identifier: GPL-3.0-or-later
// ROI selection over a tractogram: which streamlines meet a RegionSet (regions.h). Streamlines are read
// through a TractView, a non-owning view of positions and line starts, so a Polylines in memory and a file
// mapped into memory (io/formats/mapped_tracts.h) are selected the same way without a copy.
//
// Two routes give the same answer: `lineAccepted` walks one streamline's vertices in order (the reference,
// and what a tracker calls per streamline), and `selectLines` answers a whole tractogram through a
// TractIndex: a loose uniform grid over chunks of a few consecutive vertices, so a region query touches only
// the chunks near it. The index prunes; the decision for each surviving streamline is the same walk.
#pragma once

#include "io/model/geometry.h"
#include "surfaces/selection/regions.h"

#include <cstdint>
#include <glm/glm.hpp>
#include <memory>
#include <vector>

namespace dtf::surfaces {

// Positions in world RAS mm and where each streamline starts. Line i holds points [start(i), start(i+1) -
// gap): `gap` points lie between two lines (1 for .tck's NaN separator triplets, 0 for Polylines and TRX).
struct TractView {
  const glm::vec3* points = nullptr;
  const std::uint32_t* starts32 = nullptr; // lineCount + 1 entries (one of the two is set)
  const std::uint64_t* starts64 = nullptr;
  std::size_t lineCount = 0;
  std::uint32_t gap = 0;

  std::uint64_t start(std::size_t i) const { return starts64 ? starts64[i] : starts32[i]; }
  std::uint64_t begin(std::size_t i) const { return start(i); }
  std::uint64_t end(std::size_t i) const { return start(i + 1) - gap; }
  std::uint64_t size(std::size_t i) const { return end(i) - begin(i); }
  std::uint64_t pointCount() const; // points in lines, separators excluded
};

// A view of a Polylines (which must outlive it).
TractView viewOf(const Polylines& lines);

// Arc length of line i in mm.
double lineLength(const TractView& v, std::size_t i);

// A region set prepared for fast tests: single-precision parameters, mask affines inverted once.
class RegionTester {
public:
  explicit RegionTester(const RegionSet& set); // validates (InputError)
  ~RegionTester();
  RegionTester(RegionTester&&) noexcept;
  RegionTester& operator=(RegionTester&&) noexcept;

  const RegionSet& set() const;
  // The decision for one streamline of n points, regions and length range together (tckedit's walk; with
  // `precise`, the segments too). An empty streamline is kept only when the set has no region.
  bool accepts(const glm::vec3* points, std::size_t n) const;
  // True when one of the n points (with precise, also a segment between two) lies in region r, whatever
  // the set's other rules. Used by the index query and the tests.
  bool touches(std::size_t r, const glm::vec3* points, std::size_t n) const;
  bool containsPoint(std::size_t r, const glm::vec3& p) const;
  bool segmentTouches(std::size_t r, const glm::vec3& a, const glm::vec3& b) const;
  // Where a box (world mm) lies against region r: 0 none of it can hold a point in the region, 1 every point
  // in it is in the region (spheres and boxes only), 2 undecided. Conservative against contains().
  int classifyBox(std::size_t r, const glm::dvec3& lo, const glm::dvec3& hi) const;
  // Region r's world bounds (Region::bounds, found once when the tester is made).
  void bounds(std::size_t r, glm::dvec3& lo, glm::dvec3& hi) const;

  struct Impl;

private:
  std::unique_ptr<Impl> impl_;
};

// A spatial index of one tractogram. Built once (all cores), then queried many times. Chunks of kChunkPoints
// consecutive vertices (plus the next chunk's first, so each segment lies in one chunk) are sorted by the
// grid cell of their centre; each holds its line, its place on the line and its bounding box quantized to
// 1/255 of three cells, 12 bytes in all, so a query reads the chunks near a region in order and touches the
// positions only for chunks its box leaves undecided (the positions, which must outlive the index, are
// viewed, not copied). Throws InputError past 2^32 streamlines or chunks.
class TractIndex {
public:
  // `cellMm` 0 picks the grid cell from the data's extent; `threads` 0 = all cores.
  explicit TractIndex(const TractView& view, double cellMm = 0.0, int threads = 0);
  const TractView& view() const { return view_; }
  std::size_t chunkCount() const { return chunks_.size() + oversized_.size(); }
  double cellMm() const { return cell_; }
  std::size_t bytes() const; // memory held by the index itself

  // The lines with a vertex (with `precise`, also a segment) in region r of `tester`, ascending and exact.
  std::vector<std::uint32_t> linesTouching(const RegionTester& tester, std::size_t r, int threads = 0) const;

  struct Chunk {
    std::uint32_t line;
    std::uint16_t part;   // the chunk's first vertex is begin(line) + part * kChunkPoints
    std::uint8_t box[6];  // lo x, y, z, hi x, y, z in 1/255 of three cells from the cell's corner minus one cell
  };
  struct Oversized {
    std::uint32_t line;
    std::uint64_t first; // the chunk's first vertex
  };

private:
  TractView view_;
  double cell_ = 8.0;
  glm::dvec3 origin_{0.0};
  glm::ivec3 dims_{1};
  std::vector<std::uint64_t> cellStart_; // per cell + 1: where its chunks begin in chunks_
  std::vector<Chunk> chunks_;            // grouped by the cell of their centre
  std::vector<Oversized> oversized_;     // chunks longer than a cell, or far along very long lines
};

inline constexpr int kChunkPoints = 4; // vertices a chunk starts; it also holds the next chunk's first vertex

// What a selection did.
struct SelectionStats {
  std::size_t candidates = 0; // streamlines the index or length filter left for the walk
  std::size_t walked = 0;     // streamlines whose vertices were walked
  bool indexed = false;
};

// The streamlines of `view` that `tester` accepts, ascending. With an index (built on the same view) each
// region is queried and the answers combined (includes intersected, excludes removed); only ordered
// includes and a length range need the survivors' vertices walked. Without one every streamline is walked
// (all cores either way).
std::vector<std::uint32_t> selectLines(const TractView& view, const RegionTester& tester,
                                       const TractIndex* index = nullptr, int threads = 0,
                                       SelectionStats* stats = nullptr);

// The lines of `lines` listed in `keep` (ascending) with every per-point and per-streamline value, and the
// groups restricted to them (renumbered; a group left empty is kept empty).
Polylines subsetWithGroups(const Polylines& lines, const std::vector<std::uint32_t>& keep);

} // namespace dtf::surfaces
