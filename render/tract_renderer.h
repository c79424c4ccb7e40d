// Fibre tracts drawn over the fabric (issue "Fibre tracts: overlays and side-by-side comparison"): after
// FabricRenderer::renderStill/renderFrame, draw() renders the polylines (world RAS mm) into the same
// output framebuffer with depth test against the depth the composite wrote (gl_FragDepth), without
// clearing it, so the opaque fabric surface hides the tracts behind it. Each segment is a screen-aligned
// tube impostor (a quad widened in a geometry shader), coloured in DEC by its tangent (|t.x| red, |t.y|
// green, |t.z| blue) and lit with tangent-based line lighting. A slab keeps only what lies near a plane.
// The points are uploaded once into one vertex buffer (one line strip per tract, glMultiDrawArrays);
// draw() allocates nothing. Needs a current GL 4.5 context.
#pragma once

#include "io/model/geometry.h"
#include "render/fabric/frame_view.h"
#include "render/gl_objects.h"

#include <glm/glm.hpp>

#include <cstddef>
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
};

// For display only: keeps every n-th point of each line (n the smallest step that fits the cap) and always
// its first and last point, so at most maxPoints points remain; when even two points per line exceed the
// cap, every m-th line is kept. Lines with fewer than two points are dropped. Deterministic.
Polylines decimateForDisplay(const Polylines& lines, std::size_t maxPoints = kTractDisplayPointCap);

class TractRenderer {
public:
  // Compiles the program; throws GlError.
  TractRenderer();

  // Uploads `lines` (world RAS mm), decimated for display with decimateForDisplay(lines, maxPoints).
  // Throws GlError when the buffer cannot be created.
  void setTracts(const Polylines& lines, std::size_t maxPoints = kTractDisplayPointCap);
  // Draws into the currently bound framebuffer (e.g. FabricRenderer::output()) at view.viewport, with
  // depth test (GL_LESS) against its depth and depth writes on; clears nothing.
  void draw(const FrameView& view, const TractStyle& style) const;

  std::size_t pointCount() const { return pointCount_; }
  std::size_t lineCount() const { return counts_.size(); }

private:
  ProgramHandle program_;
  VertexArray vao_;
  Buffer points_;
  std::vector<GLint> firsts_;
  std::vector<GLsizei> counts_;
  std::size_t pointCount_ = 0;
  GLint uView_ = -1, uProj_ = -1, uViewRot_ = -1, uViewport_ = -1, uWidth_ = -1, uBias_ = -1, uPlane_ = -1,
        uSlab_ = -1;
};

} // namespace dtf::render
