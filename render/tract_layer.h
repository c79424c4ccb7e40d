// The viewer's tract overlay under a frame budget (issue "Fibre tracts": >= 1M points stay interactive).
// A TractLayer keeps the tracts of one pane in their own colour + depth target and composites it over the
// fabric output every frame the fabric changes, so the tracts are not redrawn while the fabric refines.
// When the camera, the style, the tracts or the surface change, the layer restarts: it copies the fabric's
// depth (the tracts are depth-tested against it), draws the finest level of detail that fits the frame's
// segment budget, and shows it at once. While the camera is still it then builds the full level 0 in a
// back target, one budget-sized chunk per frame, and swaps it in when complete: moving frames stay within
// the budget, still ones end with every display point drawn. TractBudget turns the measured GPU time of
// the tract draws into the next frame's segment budget. Needs a current GL 4.5 context; a frame allocates
// nothing.
#pragma once

#include "render/fabric/frame_view.h"
#include "render/gl_objects.h"
#include "render/shader_program.h"
#include "render/tract_renderer.h"

#include <array>
#include <cstddef>
#include <cstdint>

namespace dtf::render {

// Segments per frame for a target GPU time: a cost per segment (ms), smoothed over frames, divided into
// the target. Pure arithmetic, no GL.
class TractBudget {
public:
  explicit TractBudget(double targetMs = 20.0, std::size_t initialSegments = 100'000);
  // A draw of `segments` segments took `ms` of GPU time. Draws below kMinSample segments are ignored (fixed
  // costs dominate them). The budget moves by at most a factor of 2 per sample.
  void measured(std::size_t segments, double ms);
  std::size_t segments() const { return segments_; }
  double targetMs() const { return targetMs_; }
  double msPerSegment() const { return msPerSegment_; } // < 0 until the first sample

  static constexpr std::size_t kMinSample = 1000, kMinSegments = 2000, kMaxSegments = std::size_t(1) << 26;

private:
  double targetMs_;
  double msPerSegment_ = -1;
  std::size_t segments_;
};

class TractLayer {
public:
  // Compiles the composite program; throws GlError.
  TractLayer();

  // One frame of one pane. `fabric` is the fabric output (colour + depth) of `view`, re-rendered this frame
  // when fabricChanged; `key` stands for the tracts and the surface (a change restarts the layer).
  struct Frame {
    const Framebuffer* fabric = nullptr;
    bool fabricChanged = false;
    FrameView view;
    TractStyle style;
    std::uint64_t key = 0;
    bool moving = false;
    std::size_t budget = 100'000; // segments to draw this frame
  };
  // Draws what this frame needs and composites the layer over `fabric` when the output must change.
  // Returns true when it wrote into `fabric`'s colour. Throws GlError.
  bool frame(const TractRenderer& tracts, const Frame& f);
  // Every level-0 segment is on screen (or nothing is left to draw).
  bool complete() const { return !building_; }
  // Forgets the layer (the next frame restarts).
  void reset();
  // The oldest unread GPU timing of a draw: segments drawn and ms. False when none is ready (never waits).
  bool takeTiming(std::size_t& segments, double& ms);
  // Level and segments of the frame shown (the last swap).
  int shownLevel() const { return shownLevel_; }
  std::size_t shownSegments() const { return shownSegments_; }

private:
  struct Target {
    Texture colour, depth;
    Framebuffer fbo;
  };
  void ensureSize(glm::ivec2 size);
  void begin(Target& t, const Framebuffer& fabric);
  void drawTimed(const TractRenderer& tracts, const FrameView& view, const TractStyle& style, int level,
                 std::size_t first, std::size_t count);
  void composite(const Framebuffer& fabric);

  ShaderProgram program_;
  VertexArray vao_;
  std::array<Target, 2> targets_;
  int front_ = 0;
  Texture fabricCopy_; // the fabric output without tracts
  Framebuffer copyFbo_;
  bool copyValid_ = false;
  glm::ivec2 size_{0};
  // What the layer shows: a change of any of these restarts it.
  glm::mat4 viewProj_{0.0f};
  TractStyle style_;
  std::uint64_t key_ = 0;
  GLuint fabricId_ = 0;
  bool valid_ = false;
  bool building_ = false; // the back target is being filled with level 0
  bool backReady_ = false;
  std::size_t progress_ = 0;
  int shownLevel_ = 0;
  std::size_t shownSegments_ = 0;
  std::array<Query, 2> queries_;
  std::array<std::size_t, 2> querySegments_{};
  std::array<bool, 2> queryPending_{};
  int nextQuery_ = 0;
};

} // namespace dtf::render
