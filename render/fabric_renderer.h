// The fabric renderer: owns the passes of paper §2 (projection, silhouette, advection, composite), the
// GPU copies of the mesh, tensor field and noise, and the offscreen output framebuffer every frame ends
// in (the GUI blits it, batch mode reads it back). A frame runs fully on the GPU; textures are created
// only when the viewport size changes and uploads happen only when the data change.
// Needs a current GL 4.5 context (GlContext::headless() or the GUI's).
#pragma once

#include "io/model/geometry.h"
#include "io/model/image.h"
#include "io/model/fibre_set.h"
#include "io/model/tensor_field.h"
#include "render/camera.h"
#include "render/fabric/advection_pass.h"
#include "render/fabric/composite_pass.h"
#include "render/fabric/frame_view.h"
#include "render/fabric/phong_pass.h"
#include "render/fabric/projection_pass.h"
#include "render/fabric/silhouette_pass.h"
#include "render/gpu_fibres.h"
#include "render/gpu_scene.h"

#include <array>
#include <cstdint>
#include <memory>
#include <optional>

namespace dtf::render {

struct FabricParams {
  double lod = 0;             // l of Eq. 7 in mm; 0 = auto: one noise tile spans autoLodPixels pixels
  double autoLodPixels = 256;
  double k = 0.1;             // Eq. 12 weight of beta
  int iterations = 3;         // advection iterations per frame (paper: 3)
  double epsilon = 0.05;      // change below which a pixel is converged (paper §2.5)
  double r = 0.5;             // Eq. 13 blend
  ColourMode colour = ColourMode::Medical;
  double spotScale = 0.025;   // s of Eq. 6
  std::uint32_t seed = 1;     // noise seed
  int noiseSize = 256;        // noise tile edge, texels
  bool lighting = true;
  bool silhouette = true;
  double silhouettePixels = 1.5; // Laplacian threshold in pixel sizes (mm per pixel)
  double sharpen = 0.0;
  double depthColour = 0.0;
  double stepPixels = 2.0;    // advection step length in pixels (thread length ~ step / sqrt(k))
  double contrast = 4.0;      // f(p) stretch before Eq. 13 / medical luminance; 1 = raw
  double noiseBlend = 0.0;    // 0 = Eq. 9 exactly
  int guard = 16;             // guard border in pixels
  glm::vec3 background{0.0f};
  int stillMaxIterations = 100;       // renderStill: iteration cap
  double stillChangedFraction = 0.002; // renderStill: stop when fewer covered pixels than this changed
  float fadeOutOfPlane = 0.0f;
  float faFloor = 0.0f;       // fabric only where FA >= faFloor (the rest shows the background or grey)
  double movingScale = 1.0;   // renderFrame: internal resolution while the camera moves (e.g. 0.5)
  float fibreThreshold = 0.15f; // ColourMode::Fibres: lobes below this fraction of their voxel's strongest
                                // are dropped (between mrview's usual 0.1 and 0.2)
};

// GPU times of the passes of the last timed frame, ms (GL_TIME_ELAPSED).
struct PassTimes {
  double projection = 0, silhouette = 0, advection = 0, composite = 0, phong = 0;
};

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
  // Output size in pixels; targets are re-created only when it changes.
  void resize(int width, int height);

  // One interactive frame: projection, silhouette, params.iterations advection steps continuing the
  // previous frame's state (restarted from beta when the camera, data or parameters changed, so moving
  // the camera never smears), composite.
  void renderFrame(const Camera& camera, const FabricParams& params);
  // A still image: starts from beta and iterates at least until the start's weight (1 - k)^n < epsilon,
  // then until fewer than stillChangedFraction of the covered pixels change by more than epsilon (or
  // stillMaxIterations); composites and reads back. Deterministic.
  Image renderStill(const Camera& camera, const FabricParams& params);
  // Plain Blinn-Phong of the same mesh into the output target.
  void renderPhong(const Camera& camera, const glm::vec3& colour = glm::vec3(0.8f));
  // The output target, row 0 at the top.
  Image readback() const;

  // GL_TIME_ELAPSED queries around each pass; results of the last frame in lastTimes() (waits).
  void setTiming(bool on) { timing_ = on; }
  PassTimes lastTimes() const;
  // Advection iterations of the last renderStill / changed pixels after the last counted iteration.
  int lastIterations() const { return lastIterations_; }
  unsigned changedPixels() const { return advection_.changedPixels(); }
  // Covered pixels of the last projection, guard border included (occlusion query; waits).
  unsigned coveredPixels() const;
  double effectiveLod(const FrameView& view, const FabricParams& params) const;

  const FrameView& frameView() const { return view_; }
  // The output framebuffer: colour plus the depth the composite writes (gl_FragDepth). Overlays such as
  // TractRenderer bind it after renderFrame/renderStill and draw with depth test without clearing it;
  // readback() then returns the overlaid image.
  const Framebuffer& output() const { return output_; }
  const ProjectionPass& projection() const { return projection_; }
  const SilhouettePass& silhouette() const { return silhouette_; }
  const AdvectionPass& advection() const { return advection_; }

private:
  void prepare(const Camera& camera, const FabricParams& params, bool& restart);
  void composite(const FabricParams& params);
  int fields(const FabricParams& params) const; // advected fields: 3 for three-population fibre sets
  void beginTimer(int pass);
  void endTimer();

  ProjectionPass projection_;
  SilhouettePass silhouette_;
  AdvectionPass advection_;
  CompositePass composite_;
  PhongPass phong_;
  GpuMesh mesh_;
  GpuTensorField field_;
  GpuFibreSet fibres_;
  FibreSet fibreSet_;                  // kept to re-upload when FabricParams::fibreThreshold changes
  std::optional<ScalarVolume> fibreFa_;
  float uploadedThreshold_ = FabricParams{}.fibreThreshold;
  GpuScalarVolume background_;
  Texture noise_;
  std::shared_ptr<const NoiseTile> noiseTile_;
  Framebuffer output_;
  Texture outColour_, outDepth_;
  glm::ivec2 size_{0};
  FrameView view_;
  std::array<Query, 5> timers_;
  std::array<bool, 5> timerUsed_{};
  bool timing_ = false;
  bool dataChanged_ = true;
  glm::mat4 lastViewProj_{0.0f};
  glm::mat4 lastCameraViewProj_{0.0f}; // viewport matrix of the last frame: tells a moving camera
  FabricParams lastParams_;
  int lastIterations_ = 0;
  bool still_ = false;
};

} // namespace dtf::render
