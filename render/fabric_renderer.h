// SPDX-License-Identifier: GPL-3.0-or-later
// The fabric renderer of dtfabric's own front ends: a mesh's geometry stage, then the passes of paper §2
// shared with the embedding route (render/fabric/fabric_pipeline.h: tensor stage, silhouette, advection,
// composite), and the offscreen output framebuffer every frame ends in (the GUI blits it, batch mode reads
// it back). A frame runs fully on the GPU; textures are created
// only when the viewport size changes and uploads happen only when the data change.
// Needs a current GL 4.5 context (GlContext::headless() or the GUI's).
#pragma once

#include "io/model/geometry.h"
#include "io/model/image.h"
#include "io/model/fibre_set.h"
#include "io/model/tensor_field.h"
#include "render/camera.h"
#include "render/fabric_params.h"
#include "render/fabric/fabric_pipeline.h"
#include "render/fabric/frame_view.h"
#include "render/fabric/phong_pass.h"
#include "render/gpu_scene.h"

#include <cstdint>

namespace dtf::render {

class FabricRenderer {
public:
  // Compiles the programs; throws GlError (no context, compile failure).
  FabricRenderer();
  ~FabricRenderer();

  void setMesh(const Mesh& mesh);
  void setField(const TensorField& field);
  // The fibre set rendered in ColourMode::Fibres (the first three fibres per voxel), with the FA of a paired
  // tensor for modulation (nullptr: none). setField still provides nothing else here; a mesh is needed.
  void setFibres(const FibreSet& fibres, const ScalarVolume* fa = nullptr);
  void clearFibres();
  // A grey background (FA, MD, a T1 on any grid) shown where the surface has no tensor data, windowed to
  // [lo, hi]; nullptr removes it.
  void setBackground(const ScalarVolume* volume, float lo = 0.0f, float hi = 1.0f);
  // A 95 % cone-of-uncertainty map in degrees on any grid (io::readConeMap): the threads fray as the cone
  // widens (FabricParams::fray); nullptr removes it. One component: every direction's cone; one per fibre of
  // the fibre set (its index order, on its grid): each population frays by its own cone.
  void setUncertainty(const ScalarVolume* cone);
  // The fabric only near streamlines (FabricPipeline::setAlong): a proximity weight in [0, 1] on a world
  // axis-aligned grid (surfaces/analyses/tract_proximity.h); nullptr removes it.
  void setAlong(const ScalarVolume* weight);
  bool hasAlong() const { return pipeline_.hasAlong(); }
  // Output size in pixels; targets are re-created only when it changes.
  void resize(int width, int height);

  // One interactive frame: projection, silhouette, params.iterations advection steps continuing the
  // previous frame's state (restarted from beta when the camera, data or parameters changed, so moving
  // the camera never smears), composite. With the camera, size, data and parameters of the previous frame
  // the projection and silhouettes are not recomputed (they are unchanged): the frame advects and composites.
  void renderFrame(const Camera& camera, const FabricParams& params);
  // A still image: starts from beta and iterates at least until the start's weight (1 - k)^n < epsilon,
  // then until fewer than stillChangedFraction of the covered pixels change by more than epsilon (or
  // stillMaxIterations); composites and reads back. Deterministic.
  Image renderStill(const Camera& camera, const FabricParams& params);
  // One frame of a movie, composited into the output target (read it with readback()). `first`: a still
  // (renderStill's convergence). Otherwise the previous movie frame's advection state, reprojected into
  // this view and onto this mesh (surface points visible in both frames keep their state; newly visible
  // ones start from beta), then params.iterations Eq. 12 iterations: the paper's interactive mode, coherent
  // under camera motion and surface changes instead of restarting from the noise. Changing the parameters
  // or the size between frames restarts from beta. Full resolution (movingScale does not apply). Three-
  // population fibre sets (three thread fields) converge every frame as a still instead (coherent: the noise
  // is anchored to world space).
  void renderMovieFrame(const Camera& camera, const FabricParams& params, bool first);
  // Plain Blinn-Phong of the same mesh into the output target.
  void renderPhong(const Camera& camera, const glm::vec3& colour = glm::vec3(0.8f));
  // The output target, row 0 at the top.
  Image readback() const;

  // GL_TIME_ELAPSED queries around each pass; results of the last frame in lastTimes() (waits).
  void setTiming(bool on) { pipeline_.setTiming(on); }
  PassTimes lastTimes() const;
  // Advection iterations of the last renderStill / pixels changed by the last frame's last iteration (the
  // largest unsigned after a frame that restarted from beta, and before FabricParams::stillMinIterations
  // since the restart: such frames cannot be converged and do not count, see FabricPipeline::advect()).
  int lastIterations() const { return lastIterations_; }
  unsigned changedPixels() const { return pipeline_.advection().changedPixels(); }
  // Covered pixels of the last projection, guard border included (occlusion query; waits).
  unsigned coveredPixels() const;
  double effectiveLod(const FrameView& view, const FabricParams& params) const;

  const FrameView& frameView() const { return view_; }
  // The output framebuffer: colour plus the depth the composite writes (gl_FragDepth). Overlays such as
  // TractRenderer bind it after renderFrame/renderStill and draw with depth test without clearing it;
  // readback() then returns the overlaid image.
  const Framebuffer& output() const { return output_; }
  const ProjectionPass& projection() const { return pipeline_.projection(); }
  const SilhouettePass& silhouette() const { return pipeline_.silhouette(); }
  const AdvectionPass& advection() const { return pipeline_.advection(); }
  // The tensor stage and the advection iterations as compute shaders (default on a hardware GPU) or as
  // fullscreen draws (default on a software rasteriser); the images are the same (TensorStage::setCompute,
  // AdvectionPass::setCompute).
  void setComputePasses(bool on) { pipeline_.setComputePasses(on); }
  bool computePasses() const { return pipeline_.computePasses(); }
  // renderFrame and renderMovieFrame run a frame's last advection iteration and the composite in one pass
  // where they can (fragment passes at full resolution, no sharpening: FabricPipeline::advectComposing): the
  // same image, one full-screen pass fewer. Off: separate passes (on by default; tests compare the two).
  void setFusedComposite(bool on) { fuse_ = on; }
  bool fusedComposite() const { return fuse_; }
  // Whether the last renderFrame or renderMovieFrame ran its last iteration in the composite.
  bool lastFrameFused() const { return lastFused_; }

private:
  void prepare(const Camera& camera, const FabricParams& params);
  // params.iterations iterations and the composite into the output, fused where they can be.
  void advectAndComposite(const FabricParams& params);
  void composite(const FabricParams& params);
  // The composite's depth at full resolution into outDepth_ (drawn once per projection).
  void presentDepth();

  FabricPipeline pipeline_;
  PhongPass phong_;
  GpuMesh mesh_;
  Framebuffer output_;
  Texture outColour_, outDepth_;
  // The composite's depth at full resolution (FabricPipeline::compositeDepth), drawn once per projection
  // (depthProjection_: FabricPipeline::projections() then; 0: none) and copied into outDepth_ every frame.
  Framebuffer depthFbo_;
  Texture compositeDepth_;
  std::uint64_t depthProjection_ = 0;
  // The fused pass's colour target, the guarded targets' size; it holds fusedBackground_ wherever the
  // projection of fusedProjection_ covers nothing (the pass rewrites every covered pixel each frame).
  Texture fusedColour_;
  std::uint64_t fusedProjection_ = 0;
  glm::vec3 fusedBackground_{0.0f};
  bool fuse_ = true;
  bool lastFused_ = false;
  glm::ivec2 size_{0};
  FrameView view_;
  glm::mat4 lastCameraViewProj_{0.0f}; // viewport matrix of the last frame: tells a moving camera
  int lastIterations_ = 0;
  bool still_ = false;
};

} // namespace dtf::render
