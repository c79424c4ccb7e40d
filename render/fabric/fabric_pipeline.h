// SPDX-License-Identifier: GPL-3.0-or-later
// The fabric after the geometry stage, shared by both routes: dtfabric's own front ends (FabricRenderer
// fills the geometry buffers from a mesh) and a host application (EmbeddedFabric imports them from the
// host's depth and normal textures). Owns the data on the GPU (tensor field, fibre set, background volume),
// the noise tile, the tensor stage, silhouettes, advection with its state across frames, the composite and
// the pass timers. A frame: project() (tensor stage, silhouettes, advection restart when the view, data or
// parameters changed), advect() or converge(), composite() into the bound framebuffer.
// The noise is anchored to the data: b_min of Eq. 7 is the lower corner of the world bounds of the tensor
// field's (or fibre set's) voxel centres, so every surface cut from the same data, in any front end or
// host, carries the same noise at the same world point (given the same l).
#pragma once

#include "io/model/fibre_set.h"
#include "io/model/tensor_field.h"
#include "render/fabric/advection_pass.h"
#include "render/fabric/composite_pass.h"
#include "render/fabric/frame_view.h"
#include "render/fabric/projection_pass.h"
#include "render/fabric/silhouette_pass.h"
#include "render/fabric_params.h"
#include "render/gpu_fibres.h"
#include "render/gpu_scene.h"

#include <array>
#include <cstdint>
#include <memory>
#include <optional>

namespace dtf::render {

class FabricPipeline {
public:
  enum Pass { kProjection = 0, kSilhouette, kAdvection, kComposite, kPhong, kPasses };

  FabricPipeline();

  void setField(const TensorField& field);
  void setFibres(const FibreSet& fibres, const ScalarVolume* fa = nullptr);
  void clearFibres();
  void setBackground(const ScalarVolume* volume, float lo, float hi);
  // A cone-of-uncertainty map in degrees (io::readConeMap) that frays the threads; null removes it. One
  // component: every direction's cone; K components on the fibre set's grid: fibre k's cone (fibre index
  // order of the set given to setFibres, e.g. bedpostx's populations), turned into the renderer's slot
  // order here.
  void setUncertainty(const ScalarVolume* cone);
  bool hasUncertainty() const { return !uncertainty_.empty(); }
  // The fabric only near streamlines: a proximity weight in [0, 1] on a world axis-aligned grid
  // (surfaces/analyses/tract_proximity.h) scales the data's cover, so the composite shows what lies beneath
  // (the background volume) away from them; null removes it (the fabric everywhere).
  void setAlong(const ScalarVolume* weight);
  bool hasAlong() const { return !along_.empty(); }
  // World bounds of the data's voxel centres (tensor field, else fibre set); false when there is none.
  bool dataBounds(glm::vec3& lo, glm::vec3& hi) const;
  // b_min of Eq. 7 for the given parameters: the lower corner of the data bounds (the fibre set's in the
  // fibre colour mode), or `fallback` without data.
  glm::vec3 noiseOrigin(const FabricParams& params, const glm::vec3& fallback) const;
  double effectiveLod(const FrameView& view, const FabricParams& params) const;
  // The advection state restarts on the next project() (the geometry buffers changed for another reason).
  void invalidate() { dataChanged_ = true; }

  // Whether the geometry buffers, the tensor stage's targets and the silhouettes from the last project() still
  // hold for `view` and `params`: the same view matrices and target size, the same data and the same
  // parameters, nothing invalidated since. A still camera then skips the geometry stage, the tensor stage
  // and the silhouettes (they would write the same values) and only advects and composites.
  bool projectionCurrent(const FrameView& view, const FabricParams& params) const;
  // A frame that skips project() because projectionCurrent(): the state carries on.
  void reuseProjection() { reprojectNext_ = false; }
  // Tensor stage on the geometry stage's buffers, then silhouettes; restarts the advection from beta when
  // the data, the view's matrices or the parameters changed since the last call, or `forceRestart`.
  // The geometry stage must have run for `view`; the caller starts the kProjection timer before it (the
  // projection's time covers both stages) and this call ends it. Returns whether the advection restarted.
  bool project(const FrameView& view, const FabricParams& params, const glm::vec3& noiseFallback,
               bool forceRestart = false);
  // Movies: the next project() that would restart the advection because the view or the surface changed
  // (not the parameters or the size) starts instead from the state kept by keepHistory(), reprojected into
  // the new view (AdvectionPass::reproject), so the fabric stays coherent from frame to frame.
  void reprojectNext() { reprojectNext_ = true; }
  // Whether reprojectNext() can carry the state for these parameters (two thread fields: tensors and fibre
  // sets of up to two populations).
  bool reprojects(const FabricParams& params) const { return fields(params) == 2; }
  // Keeps the current state and the surface it lies on (after the frame's advection) for reprojectNext().
  void keepHistory(const FrameView& view);
  // params.iterations Eq. 12 iterations, continuing the state.
  void advect(const FabricParams& params);
  // Iterates to convergence (see FabricRenderer::renderStill); returns the iterations run.
  int converge(const FabricParams& params);
  // Composites the viewport into the bound framebuffer at `origin`, its depth as `depth` says.
  // overBackground: the bound framebuffer holds params.background (alpha 1) wherever the pass may draw
  // (CompositeSettings::overClear).
  void composite(const FrameView& view, const FabricParams& params, glm::ivec2 origin = glm::ivec2(0),
                 CompositeDepth depth = CompositeDepth::Computed, bool overBackground = false);
  // advect() and composite() with CompositeDepth::Present and overBackground in fewer passes: the first
  // params.iterations - 1 iterations, then the last one and the composite in one pass over the guarded
  // targets (CompositePass::advecting), its colour into `colour` (RGBA8, the guarded targets' size: the
  // viewport's pixels at view.guard; it must hold params.background wherever the projection covers
  // nothing). The same state, count and colours. For full resolution, fragment passes, params.iterations
  // >= 1 and no sharpening (fusesComposite()).
  void advectComposing(const FrameView& view, const FabricParams& params, const Texture& colour);
  bool fusesComposite(const FrameView& view, const FabricParams& params) const;
  // The depth composite() writes with CompositeDepth::Computed at full resolution, alone, into the bound
  // framebuffer's cleared depth (CompositePass::runDepth); it changes only when project() runs.
  void compositeDepth(const FrameView& view);
  // Counts project() calls: what was derived from the projection is current while this stays the same.
  std::uint64_t projections() const { return projections_; }

  void beginTimer(Pass pass);
  void endTimer();
  void setTiming(bool on) { timing_ = on; }
  bool timing() const { return timing_; }
  void clearTimers() { timerUsed_.fill(false); }
  PassTimes lastTimes() const;

  ProjectionPass& projection() { return projection_; }
  const ProjectionPass& projection() const { return projection_; }
  const SilhouettePass& silhouette() const { return silhouette_; }
  const AdvectionPass& advection() const { return advection_; }
  AdvectionPass& advection() { return advection_; }
  // The tensor stage and the advection as compute shaders, or as fullscreen draws (the same images; the
  // default: compute on a hardware GPU, draws on a software rasteriser).
  void setComputePasses(bool on) {
    projection_.setCompute(on);
    advection_.setCompute(on);
  }
  bool computePasses() const { return advection_.compute(); }
  bool fibresEmpty() const { return fibres_.empty(); }

private:
  int fields(const FabricParams& params) const; // advected fields: 3 for three-population fibre sets
  AdvectionSettings advectionSettings(const FabricParams& params) const;
  CompositeSettings compositeSettings(const FabricParams& params, glm::ivec2 origin, CompositeDepth depth,
                                      bool overBackground) const;
  CompositeInputs compositeInputs(const FabricParams& params) const;
  // Whether this frame's advection counts its changed pixels (see advect()).
  bool countsThisFrame(const FabricParams& params) const;
  ProjectionPass projection_;
  SilhouettePass silhouette_;
  AdvectionPass advection_;
  CompositePass composite_;
  GpuTensorField field_;
  GpuFibreSet fibres_;
  FibreSet fibreSet_; // kept to re-upload when FabricParams::fibreThreshold changes
  std::optional<ScalarVolume> fibreFa_;
  float uploadedThreshold_ = FabricParams{}.fibreThreshold;
  GpuScalarVolume background_;
  GpuScalarVolume uncertainty_;
  GpuScalarVolume along_;
  std::optional<ScalarVolume> cone_; // as given, re-uploaded in slot order when the fibres change
  void uploadUncertainty();
  Texture noise_;
  std::shared_ptr<const NoiseTile> noiseTile_;
  bool haveField_ = false, haveFibres_ = false;
  glm::vec3 fieldLo_{0.0f}, fieldHi_{0.0f}, fibreLo_{0.0f}, fibreHi_{0.0f};
  std::array<Query, kPasses> timers_;
  std::array<bool, kPasses> timerUsed_{};
  bool timing_ = false;
  bool dataChanged_ = true;
  bool reprojectNext_ = false;
  std::uint64_t projections_ = 0;
  std::optional<FrameView> historyView_;
  glm::mat4 lastViewProj_{0.0f};
  glm::ivec2 lastTarget_{0};
  float lastPixelMm_ = 0.0f;
  glm::vec2 lastDepthRange_{0.0f};
  bool projected_ = false; // project() ran since the last invalidation
  bool restarted_ = false; // the last project() restarted the advection and advect() has not run since
  int sinceRestart_ = 0;   // advection iterations since the last restart
  FabricParams lastParams_;
};

} // namespace dtf::render
