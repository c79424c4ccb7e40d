// SPDX-License-Identifier: GPL-3.0-or-later
// Pass 3 of the fabric (paper §2.5, Eq. 12): iterative advection of the mapped noise beta along both
// image-space eigenvector fields at once, ping-ponging two pairs of R32F state textures (p1 and p2, one
// channel each: a software rasteriser's bilinear fetch costs per channel of the texture); blocked pixels
// (silhouettes, background, the target's outermost ring) hold kBlocked in both.
// The state persists between frames (the paper runs 3 iterations per frame and continues next frame);
// reset() restarts from beta and takes beta and the blocked pixels (silhouettes, background) from the
// projection and silhouette passes.
//   inputs : reset: projection surface (beta, coverage), silhouette edges; iterate: projection vectors
//            (RG32UI: directions and beta, 8 bytes; with a third field the vectors3 target, RGBA32UI: the
//            same and the third direction, one fetch)
//   output : field(0), field(1) R32F (p1, p2, or kBlocked), the size of the guarded target
// With three populations (fibre sets) a third field p3 runs along the third direction in the same
// iteration (the THIRD variant, its own framebuffers: the two-field fabric never pays for it).
// The number of pixels that changed by more than epsilon in the last counted iteration is kept in an
// atomic counter (the stopping criterion); reading it with changedPixels() waits for the GPU.
#pragma once

#include "render/gl_objects.h"
#include "render/program_bindings.h"
#include "render/shader_program.h"

#include <glm/glm.hpp>

#include <vector>

namespace dtf::render {

// The state value of blocked pixels: any bilinear weight on it makes a sample negative.
constexpr float kBlocked = -1e20f;

struct AdvectionSettings {
  float k = 0.1f;        // weight of beta in Eq. 12
  float stepPixels = 1.0f; // length of one step in pixels along the max-norm scaled vectors
  float epsilon = 0.05f; // change below which a pixel counts as converged
  bool complementSecond = false; // p2 advects 1 - beta (fibre sets: interleaved populations)
  // A whole number of pixels per step: every sample lies on a texel row or column and is read as two texels
  // (INTEGER_STEP in common/advection_step.glsl) instead of a bilinear sample of four.
  bool integerStep() const;
};

class AdvectionPass {
public:
  AdvectionPass();
  void resize(glm::ivec2 target);
  // The target pixels the surface can cover (x, y, width, height; FrameView::targetCoverRect; a negative
  // width: all). The restarts shade only these and clear the rest to the state of uncovered pixels (blocked,
  // edge 1): a software rasteriser would run their whole shader there. Compute restarts run everywhere.
  void setCover(const glm::ivec4& rect) { cover_ = rect; }
  // p_0 = beta on covered pixels, kBlocked elsewhere. Writes both ping-pong textures, so pixels the
  // iterations skip (see iterate) hold the blocked state in either.
  void reset(const Texture& surface, const Texture& edges, int fields = 2, bool complementSecond = false);
  // reset() and the silhouette pass in one fullscreen pass: finds the silhouettes of `surface` as
  // SilhouettePass::run does (every pixel shaded) and writes them into `edges` (the silhouette pass's
  // target, the surface's size) while it restarts the state from them.
  void resetFindingSilhouettes(const Texture& surface, const Texture& edges, float thresholdMm, float backgroundMm,
                               int fields = 2, bool complementSecond = false);
  // Movies: keeps a copy of the current (p1, p2) state and of the projection's surface target it was
  // computed on, for reproject() in the next frame. The copies are (re)allocated only when the size changes.
  void keepHistory(const Texture& surface);
  bool hasHistory() const { return historySize_ == size_ && size_.x > 0; }
  // Like reset() (two fields), but p_0 comes from the kept state where the same surface point was visible in
  // the kept frame (see fabric/advection.frag, REPROJECT): `depth` is this frame's window depth,
  // `windowToWorld` maps (pixel x, y, window depth, 1) to world, `worldToPrevWindow` and `worldToPrevEye`
  // are the kept frame's; `depthTolMm` the linear-depth mismatch that counts as another surface.
  void reproject(const Texture& surface, const Texture& edges, const Texture& depth,
                 const glm::mat4& windowToWorld, const glm::mat4& worldToPrevWindow,
                 const glm::mat4& worldToPrevEye, float depthTolMm, bool complementSecond = false);
  // `count` Eq. 12 iterations; the last one counts the changed pixels when countChanges is set. With the
  // projection's depth buffer given, only covered pixels are shaded (background pixels are blocked and
  // would keep their state anyway), which skips the background on a software rasteriser.
  // `fields` 2 (tensors: v1, v2; `vectors` RG32UI) or 3 (fibre sets: also p3 along v3; `vectors` RGBA32UI,
  // .xy the two-field texel and .z v3 as snorm16 x2: the projection's vectors3 target). Throws GlError for
  // a vectors texture of the other layout.
  void iterate(const Texture& vectors, const AdvectionSettings& settings, int count, bool countChanges = true,
               const Texture* depth = nullptr, int fields = 2);
  // One iteration drawn by `program`, the caller's (the composite that runs a frame's last iteration,
  // CompositePass::advecting: its uniforms set and its own inputs bound), which writes the next state at
  // draw buffers 1, 2 (3: the third field) and a colour at draw buffer 0 into `colour` (RGBA8, the state's
  // size). As iterate() with the projection's depth: only covered pixels are shaded, and the changed pixels
  // are counted when countChanges is set. Fragment passes only (not with setCompute(true)); throws GlError
  // for targets of another size or a vectors texture of the other layout.
  void iterateDrawing(const ShaderProgram& program, const Texture& vectors, bool countChanges, const Texture& depth,
                      int fields, const Texture& colour);
  // Iterations and restarts from beta as a compute shader (fabric/advection.comp) instead of fullscreen
  // draws: the same values, many times faster where the fragment pipeline is a small part of the GPU (the
  // movie's reprojecting restart stays a draw). The default is compute on a
  // hardware GPU and fragment on a software rasteriser (softwareRasteriser(), render/gl_context.h).
  void setCompute(bool compute) { useCompute_ = compute; }
  bool compute() const { return useCompute_; }
  // The current p1 (c = 0), p2 (c = 1) or p3 (c = 2; three-field runs only).
  const Texture& field(int c) const { return state_[current_][c]; }
  // Replaces p1, p2 of the current state except at blocked pixels (tests: the "forgets its start"
  // property). Values are (p1, p2) pairs in GL row order.
  void setFields(const float* rg);
  // The current (p1, p2) pairs in GL row order (reads back; tests and diagnostics).
  std::vector<float> readFields() const;
  // Pixels that changed by more than epsilon in the last iteration of the last iterate(); the largest
  // unsigned when that call did not count (not known to have converged).
  unsigned changedPixels() const;

private:
  void step(const AdvectionSettings& s, bool countChanges, bool covered, bool third);
  void dispatchStep(const AdvectionSettings& s, bool countChanges, bool third);
  // The restart from beta into both ping-pong textures as a dispatch of `program` (its own uniforms set);
  // `edges`: the silhouette target it writes (RESET SILHOUETTES), or nullptr.
  void dispatchRestart(const ShaderProgram& program, const Texture& surface, const Texture* edges, bool third,
                       bool complementSecond);
  // The iteration's uniforms on `program`, then bindIterationInputs.
  void setIterationUniforms(const ShaderProgram& program, const AdvectionSettings& s, bool countChanges, bool third);
  // Binds what an iteration reads (the current state as textures and images, the counter, cleared when
  // counting); `program` is made current first.
  void bindIterationInputs(const ShaderProgram& program, bool countChanges, bool third);
  // The vectors texture's layout checked and bound for `fields` fields.
  void bindVectors(const Texture& vectors, int fields);
  // Attaches `depth` to the iteration framebuffers (0: none) where another is attached.
  void attachDepth(GLuint depth);
  // The early depth test against the attached surface depth that shades only covered pixels (on), and the
  // GL defaults again (off).
  void coveredPixelsOnly(bool on);
  // Binds the current state to the iteration's read image units (p_i at each pixel itself).
  void bindHere(bool third);
  // The restart from beta of reset() and resetFindingSilhouettes(): `program` (its own uniforms set) into
  // `fbo`.
  void drawRestart(const ShaderProgram& program, const Framebuffer& fbo, const Texture& surface,
                   bool complementSecond, int states, bool edge);
  // Clears `states` state attachments (then the edge attachment) of fbo outside cover_ and scissors to it;
  // false (nothing done) when cover_ is the whole target.
  bool scissorCover(const Framebuffer& fbo, int states, bool edge);
  ShaderVariants iteration_; // FAR_PLANE, COUNT, THIRD
  ShaderVariants restart_; // RESET with THIRD, SILHOUETTES
  ShaderProgram reproject_;
  ShaderVariants compute_; // COUNT, THIRD, RESET, SILHOUETTES (compiled on first use)
  bool useCompute_ = false;
  VertexArray vao_;
  Buffer counter_;
  Framebuffer fbo_[2], fbo3_[2], resetFbo_, resetFbo3_, resetEdgesFbo_, resetEdgesFbo3_;
  // iterateDrawing's: the colour target, then the next state (two or three fields), and the depth.
  Framebuffer drawFbo_[2], drawFbo3_[2];
  GLuint attachedDepth_ = 0, attachedEdges_ = 0, attachedColour_ = 0, drawDepth_ = 0;
  Texture state_[2][3]; // [ping-pong][component]
  int current_ = 0;
  bool counted_ = false; // the last iterate() counted its changed pixels
  glm::ivec2 size_{0};
  glm::ivec4 cover_{0, 0, -1, -1};
  Texture history_[2], historySurface_; // keepHistory()
  glm::ivec2 historySize_{0};
};

} // namespace dtf::render
