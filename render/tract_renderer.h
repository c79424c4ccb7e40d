// SPDX-License-Identifier: GPL-3.0-or-later
// Fibre tracts drawn over the fabric (issue "Fibre tracts: overlays and side-by-side comparison"): after
// FabricRenderer::renderStill/renderFrame, draw() renders the polylines (world RAS mm) into the same
// output framebuffer with depth test against the depth the composite wrote (gl_FragDepth), without
// clearing it, so the opaque fabric surface hides the tracts behind it. Each segment is a screen-aligned
// tube impostor (a quad widened in a geometry shader), coloured in DEC by its tangent (|t.x| red, |t.y|
// green, |t.z| blue) and lit with tangent-based line lighting. A slab keeps only what lies near a plane.
// The points are one vertex buffer, the segments an element buffer of index pairs drawn as GL_LINES
// (widening in a vertex shader that pulls both end points runs 3-4x slower on llvmpipe, whose vertex
// stage is single-threaded).
//
// Levels of detail for interactive frames: level k joins every 2^k-th point of each line (first and last
// always kept). Within a level the segments are stored line by line in a stratified line order (bit-reversed
// index), so any prefix of a level's segments is an even sample of the lines: a frame budget can be met by
// drawing a coarser level, or a prefix of one, and a still image built up in chunks. Display only: analysis
// (agreement, selection) uses the full polylines. Needs a current GL 4.5 context; draw() allocates nothing.
#pragma once

#include "io/model/geometry.h"
#include "render/fabric/frame_view.h"
#include "render/gl_objects.h"
#include "render/shader_program.h"

#include <cstddef>
#include <cstdint>
#include <glm/glm.hpp>
#include <glm/gtc/type_precision.hpp>
#include <span>
#include <utility>
#include <vector>

namespace dtf::render {

// Points drawn at most by default: more only slows the overlay down without showing more at screen
// resolution.
inline constexpr std::size_t kTractDisplayPointCap = 1'000'000;

struct TractStyle {
  float widthPx = 2.0f;        // tube width in pixels
  float slabMm = 0.0f;         // > 0: only points within slabMm of `plane` are drawn
  glm::vec4 plane{0, 0, 1, 0}; // unit normal n and offset w: signed distance dot(n, p) + w (world mm)
  float depthBiasMm = 0.05f;   // towards the viewer, so tracts lying in a surface are not lost to z-fighting
  // >= 0: the points whose node (kTractDisplayNode) rounds to within highlightHalfWidth of this node are
  // drawn in highlightColour, unlit (the Profile panel's hovered node: a band across the bundle; one node of
  // 100 is about a millimetre of a long bundle, too thin to see alone).
  int highlightNode = -1;
  int highlightHalfWidth = 1;
  glm::vec3 highlightColour{1.0f, 1.0f, 0.25f};

  bool operator==(const TractStyle&) const = default;
};

// Points a displayed line keeps at least (fewer only when it has fewer): past the cap, lines are thinned
// before they are reduced to chords. At 10 M streamlines of 50 points the default cap shows 125 k lines of 8
// points each, the range peers show (10 k - 150 k streamlines).
inline constexpr std::size_t kMinDisplayLinePoints = 8;

// For display only: keeps every n-th point of each line (n the smallest step that fits the cap) and always
// its first and last point, so at most maxPoints points remain; when the lines at kMinDisplayLinePoints
// points each (or all of a shorter line's) exceed the cap, every m-th line is kept. Lines with fewer than
// two points are dropped. Per-point and per-streamline data follow what is kept, and the groups are
// restricted to the kept lines (renumbered). Deterministic.
Polylines decimateForDisplay(const Polylines& lines, std::size_t maxPoints = kTractDisplayPointCap);
// The same for the lines `keep` lists (ascending indices into `lines`): decimateForDisplay of
// surfaces::subsetWithGroups(lines, keep), without making that subset (what a region change draws: its cost
// follows the selection's line count and the cap, not its points). `minLinePoints` replaces
// kMinDisplayLinePoints: kWholeDisplayLines keeps the lines whole (every m-th of them), as a near-surface
// selection needs them.
inline constexpr std::size_t kWholeDisplayLines = static_cast<std::size_t>(-1);
Polylines decimateForDisplay(const Polylines& lines, const std::vector<std::uint32_t>& keep,
                             std::size_t maxPoints = kTractDisplayPointCap,
                             std::size_t minLinePoints = kMinDisplayLinePoints);

// What TractRenderer uploads, prepared on any thread: the display points and the segments of each level.
struct DisplayTracts {
  std::vector<glm::vec3> points;            // decimateForDisplay(lines, maxPoints).points
  std::vector<glm::u8vec4> colours;         // per point, from kTractDisplayColours; empty: DEC
  std::vector<float> nodes;                 // per point, from kTractDisplayNode (-1: none); empty: none
  std::size_t lines = 0;                    // lines drawn (>= 2 points each)
  std::vector<std::uint32_t> segments;      // point index pairs, level after level
  std::vector<std::size_t> levelOffsets{0}; // level k's segments: [levelOffsets[k], levelOffsets[k + 1])

  int levelCount() const { return static_cast<int>(levelOffsets.size()) - 1; }
  std::size_t segmentCount(int level) const {
    return levelOffsets[static_cast<std::size_t>(level) + 1] - levelOffsets[static_cast<std::size_t>(level)];
  }
};

// A per-point array with this name (4 components, RGBA in 0..1) gives the tracts their colours: alpha 1
// uses the RGB (lit like DEC), alpha 0 keeps the DEC colour of the tangent.
inline constexpr const char* kTractDisplayColours = "display colour";
// A per-point array with this name (1 component) gives each point its node along the profiled bundle
// (surfaces::nodePerPoint; NaN: a point of no profiled streamline). With it a TractStyle can highlight one
// node and setNodeColours colour the points by node.
inline constexpr const char* kTractDisplayNode = "display node";
// Node colours setNodeColours takes at most.
inline constexpr std::size_t kMaxTractNodeColours = 128;
// The colour map for tract values: viridis, linear between matplotlib's colours at 0, 1/4, 1/2, 3/4 and 1
// (#440154, #3b528b, #21918c, #5ec962, #fde725); t is clamped to [0, 1]. Its legend: render/figure_furniture.h
// drawColourBar.
glm::vec3 tractValueColour(float t);

// Display decimation to maxPoints, then up to maxLevels levels of detail (a level is added only while it
// has at most 3/4 of the previous level's segments).
DisplayTracts prepareDisplayTracts(const Polylines& lines, std::size_t maxPoints = kTractDisplayPointCap,
                                   int maxLevels = 5);

class TractRenderer {
public:
  // Compiles the program; throws GlError.
  TractRenderer();

  // Uploads `lines` (world RAS mm) via prepareDisplayTracts(lines, maxPoints). Throws GlError.
  void setTracts(const Polylines& lines, std::size_t maxPoints = kTractDisplayPointCap);
  // Uploads prepared display tracts (the GL part of setTracts), into the buffers of the last upload when
  // they are large enough. Throws GlError.
  void upload(const DisplayTracts& tracts);
  // Draws every segment of level 0 into the currently bound framebuffer (e.g. FabricRenderer::output()) at
  // view.viewport, with depth test (GL_LESS) against its depth and depth writes on; clears nothing.
  void draw(const FrameView& view, const TractStyle& style) const;
  // Draws segments [first, first + count) of `level` (clamped to the level) the same way.
  void draw(const FrameView& view, const TractStyle& style, int level, std::size_t first,
            std::size_t count) const;

  // Colours the points with a node (kTractDisplayNode) by their node: colours[k] for node k where its alpha
  // is 1 (alpha 0: the point keeps its colour). An empty span turns it off. At most kMaxTractNodeColours
  // (more: throws UsageError). Sets a uniform only; allocates nothing.
  void setNodeColours(std::span<const glm::vec4> colours);
  // Whether the uploaded tracts carry nodes.
  bool hasNodes() const { return hasNodes_; }

  std::size_t pointCount() const { return pointCount_; }
  std::size_t lineCount() const { return lineCount_; }
  int levelCount() const { return static_cast<int>(levelOffsets_.size()) - 1; }
  std::size_t segmentCount(int level = 0) const;

private:
  ShaderProgram program_; // tracts/lines.{vert,geom,frag}; uniforms by TractLinesProgram::Uniform
  VertexArray vao_;
  Buffer points_, segments_, colours_, nodes_;
  std::size_t pointsCapacity_ = 0, segmentsCapacity_ = 0, coloursCapacity_ = 0, nodesCapacity_ = 0; // bytes
  bool hasNodes_ = false;
  std::vector<std::size_t> levelOffsets_{0};
  std::size_t pointCount_ = 0, lineCount_ = 0;
};

} // namespace dtf::render
