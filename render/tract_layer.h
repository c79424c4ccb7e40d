// SPDX-License-Identifier: GPL-3.0-or-later
// The viewer's tract overlay under a frame budget (issue "Fibre tracts": >= 1M points stay interactive).
// A TractLayer keeps the tracts of one pane in their own colour + depth target and composites it over the
// fabric output every frame the fabric changes, so the tracts are not redrawn while the fabric refines.
// When the camera, the style, the tracts or the surface change, the layer restarts: it copies the fabric's
// depth (the tracts are depth-tested against it), draws the finest level of detail that fits the frame's
// segment budget, and shows it at once. While the camera is still it then builds the full level 0 in a
// back target, one budget-sized chunk per frame, and swaps it in when complete: moving frames stay within
// the budget, still ones end with every display point drawn. TractBudget turns the measured time of the
// tract draws into the next frame's choice. Needs a current GL 4.5 context; a frame allocates
// nothing.
#pragma once

#include "render/fabric/frame_view.h"
#include "render/gl_objects.h"
#include "render/shader_program.h"
#include "render/tract_renderer.h"

#include <array>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <span>

namespace dtf::render {

// How much of the tracts to draw per frame for a target time. The cost per segment differs between levels
// (a coarse level has longer segments: more fragments each), so each level keeps its own smoothed cost,
// learnt from the draws that use it; a level not measured yet borrows the nearest measured level's cost.
// Pure arithmetic, no GL.
class TractBudget {
public:
  explicit TractBudget(double targetMs = 20.0);
  // A draw of `segments` segments of `level` took `ms`. Draws below kMinSample segments are ignored (fixed
  // costs dominate them); the estimate moves halfway towards each sample.
  void measured(int level, std::size_t segments, double ms);

  struct Choice {
    int level = 0;
    std::size_t segments = 0;
  };
  // The finest level whose estimated time fits the target, whole; when none fits, the prefix (an even
  // sample of the lines) of the level that shows the largest share of the lines within the target.
  Choice choose(std::span<const std::size_t> levelSegments) const;
  Choice choose(const TractRenderer& tracts) const;
  // Level-0 segments per frame while a still image is built up.
  std::size_t chunk() const;
  // Estimated ms per segment of `level` (kInitialMsPerSegment before any sample).
  double msPerSegment(int level) const;
  double targetMs() const { return targetMs_; }

  static constexpr std::size_t kMinSample = 500, kMinSegments = 500;
  static constexpr double kInitialMsPerSegment = 1e-3; // 20'000 segments in 20 ms: llvmpipe's order
  static constexpr int kMaxLevels = 16;

private:
  double targetMs_;
  std::array<double, kMaxLevels> cost_; // ms per segment; < 0: not measured
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
    TractBudget::Choice draw{0, 100'000}; // what a restart draws at once
    std::size_t chunk = 100'000;          // level-0 segments added per still frame
  };
  // Draws what this frame needs and composites the layer over `fabric` when the output must change.
  // Returns true when it wrote into `fabric`'s colour. Throws GlError.
  bool frame(const TractRenderer& tracts, const Frame& f);
  // Every level-0 segment is on screen (or nothing is left to draw).
  bool complete() const { return !building_; }
  // Forgets the layer (the next frame restarts).
  void reset();
  // How draws are timed: a GL_TIME_ELAPSED query (read a frame or two later, never waiting), or the wall
  // time between a glFinish before and one after the draw. Software rasterisers (llvmpipe, softpipe,
  // swrast: the default there) need the latter: llvmpipe's query covers little of its deferred
  // rasterisation (9-13 ms reported for draws that took 240 ms).
  enum class Timing { Query, Finish };
  void setTiming(Timing t) { timing_ = t; }
  // The oldest unread timing of a draw: level, segments drawn and ms. False when none is ready.
  bool takeTiming(int& level, std::size_t& segments, double& ms);
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
  Timing timing_ = Timing::Query;
  std::array<Query, 2> queries_;
  std::array<std::size_t, 2> querySegments_{};
  std::array<int, 2> queryLevel_{};
  std::array<bool, 2> queryPending_{};
  std::array<double, 2> finishMs_{}; // Timing::Finish: the measured time, ready at once
  int nextQuery_ = 0;
};

} // namespace dtf::render
