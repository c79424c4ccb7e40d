// SPDX-License-Identifier: GPL-3.0-or-later
// Pass 1 of the fabric (paper §2.1, §2.3), in two stages that run one after the other on the guarded target:
// the geometry stage (render/fabric/geometry_stage.h) writes the geometry buffers, world normal and linear
// depth per pixel plus the window depth, from a mesh (dtfabric's own front ends) or from a host's depth and
// normal textures (the embedding route); the tensor stage then does the tensor work once per covered pixel
// (the early depth test skips the background) and writes the image-space in-plane eigenvector directions
// and everything the later passes need. On a software rasteriser the split is what makes the pass cheap:
// shading cost follows pixels, not triangles, and no pixel is shaded twice (the paper's §3.3 depth
// pre-pass, without drawing the mesh twice).
//   inputs : geometry buffers, GpuTensorField (or GpuFibreSet), noise texture, FrameView
//   outputs: vectors RG32UI (packSnorm2x16(v1.xy); v2.xy as snorm10 and beta as unorm12: image-space
//                    directions, max-norm 1, 0 = no direction; packVectors in common/projection_pixel.glsl)
//            surface RGBA32F (beta, light L, linear depth mm, 1 = covered)
//            light   R16 (L again, unorm16: all the composite reads of the surface per frame when the
//                    frame's last iteration runs in it, a fetch of 2 bytes instead of 16)
//            eigen   RGBA8 (|e1|: DEC colour of the world principal eigenvector of T (medical mode only),
//                    FA)
//            lambda  RGBA8 (lambda2'/lambda1' of the in-plane eigenvalues (1 without a positive lambda1'),
//                    |e1 . n|, the background volume's grey value where there is no tensor data, 1 = tensor
//                    data)
//            depth   DEPTH32F (the geometry stage's window depth, for gl_FragDepth in the composite and the
//                    early depth test of the later fullscreen passes)
//            geometry RG32UI (the geometry stage's buffer)
//            fibres  RGBA32UI (fibre sets only: per population k = 1..3 packUnorm4x8(|d_k| world DEC colour,
//                    weight = amplitude / strongest x in-surface fraction); .w packUnorm4x8(FA, the data's
//                    cover, the background grey, 0) as eigen and lambda hold them: a fibre set's composite
//                    reads this texel alone)
//            vectors3 RGBA32UI (fibre sets only: .xy the vectors texel, .z population 3's image direction,
//                    packSnorm2x16, max-norm 1, .w 0: a three-field iteration's one fetch)
// The surface target is cleared to 0 first (no coverage); vectors, eigen and lambda are defined only where
// surface.a = 1. A zero vector there means "no direction".
#pragma once

#include "render/fabric/frame_view.h"
#include "render/fabric/geometry_stage.h"
#include "render/gl_objects.h"
#include "render/gpu_fibres.h"
#include "render/gpu_scene.h"
#include "render/program_bindings.h"
#include "render/shader_program.h"

namespace dtf::render {

struct ProjectionSettings {
  float lod = 10.0f;           // l of Eq. 7, mm
  glm::vec3 noiseOrigin{0.0f}; // b_min of Eq. 7, mm: a point fixed to the data, so every surface cut
                               // from the same data carries the same noise at the same world point
  float noiseBlend = 0.0f;     // 0 = Eq. 9 exactly
  float degenerateTol = 0.02f; // relative in-plane eigenvalue gap treated as degenerate
  bool principal = true;       // also decompose T for the 3D principal eigenvector (medical mode)
  bool cullHidden = true;      // cull back faces of closed meshes seen from outside (same image)
  float faFloor = 0.0f;        // the fabric only where FA >= faFloor; elsewhere "no tensor data"
  bool fibres = false;         // sample the GpuFibreSet instead of the tensor field
  // Uncertainty (optional): a cone map in degrees (uploaded windowed to [0, 90]); each noise cell of edge
  // lod / frayCells turns the directions by a hash-drawn angle in [-1, 1] x fray x cone (common/fray.glsl).
  const GpuScalarVolume* uncertainty = nullptr;
  float fray = 1.0f;
  float frayCells = 16.0f;
  // Along streamlines (optional): a proximity weight in [0, 1] on a world axis-aligned grid
  // (surfaces/analyses/tract_proximity.h) that scales the data's cover, so the fabric shows only near them.
  const GpuScalarVolume* along = nullptr;
};

// The tensor stage: geometry buffers -> directions, beta, light, eigen, lambda (fibres).
class TensorStage {
public:
  TensorStage();
  // (Re)creates the targets when the size changes; no-op otherwise.
  void resize(glm::ivec2 target);
  // Runs on `geometry`'s buffers (their size is the view's target). `background` (optional) is sampled where
  // the surface has no tensor data. With settings.fibres, `fibres` (required) replaces the tensor field.
  void run(const GeometryStage& geometry, const GpuTensorField& field, const Texture& noise,
           const FrameView& view, const ProjectionSettings& settings,
           const GpuScalarVolume* background = nullptr, const GpuFibreSet* fibres = nullptr);

  const Texture& vectors() const { return vectors_; }
  const Texture& surface() const { return surface_; }
  const Texture& eigen() const { return eigen_; }
  const Texture& lambda() const { return lambda_; }
  const Texture& light() const { return light_; }
  const Texture& fibres() const { return fibres_; }
  const Texture& vectors3() const { return vectors3_; }
  glm::ivec2 size() const { return size_; }
  // Pixels shaded by the last run (= covered pixels). Waits for the GPU.
  unsigned coveredPixels() const;
  // The tensor stage as a compute shader (fabric/projection.comp) instead of a fullscreen draw: the same
  // targets, many times faster where the fragment pipeline is a small part of the GPU. Default: compute on
  // a hardware GPU, fragment on a software rasteriser (softwareRasteriser(), render/gl_context.h).
  void setCompute(bool compute) { compute_ = compute; }
  bool compute() const { return compute_; }

private:
  void attachDepth(const Texture& depth);
  // The uniforms and textures both programs take (`p` is made current).
  void prepare(const ShaderProgram& p, const GpuTensorField& field, const Texture& noise, const FrameView& view,
               const ProjectionSettings& s, const GpuScalarVolume* background, const GpuFibreSet* fibres,
               bool useFibres, bool hasBackground, bool fray) const;
  void dispatch(const GeometryStage& geometry, bool haveData, bool useFibres);
  ShaderVariants program_;        // WITH_PRINCIPAL, NOISE_BLEND, BACKGROUND, FIBRES, UNCERTAINTY, ALONG
  ShaderVariants computeProgram_; // the same variants (compiled on first use)
  bool compute_ = false;
  bool lastCompute_ = false; // the last run was a dispatch: coveredPixels() reads covered_
  VertexArray vao_;
  Query samples_;
  Buffer covered_;
  Framebuffer fbo_, fibreFbo_;
  GLuint attachedDepth_ = 0;
  Texture vectors_, surface_, eigen_, lambda_, light_, fibres_, vectors3_;
  glm::ivec2 size_{0};
};

// Both stages together, the projection pass as the renderers run it.
class ProjectionPass {
public:
  // Sizes follow the view's target.
  void resize(glm::ivec2 target);
  // Geometry stage from `mesh`, then the tensor stage (see TensorStage::run).
  void run(const GpuMesh& mesh, const GpuTensorField& field, const Texture& noise, const FrameView& view,
           const ProjectionSettings& settings, const GpuScalarVolume* background = nullptr,
           const GpuFibreSet* fibres = nullptr);
  // The tensor stage alone, on whatever the geometry stage last wrote (a mesh or a host's textures).
  void runTensor(const GpuTensorField& field, const Texture& noise, const FrameView& view,
                 const ProjectionSettings& settings, const GpuScalarVolume* background = nullptr,
                 const GpuFibreSet* fibres = nullptr);

  GeometryStage& geometryStage() { return geometry_; }
  const GeometryStage& geometryStage() const { return geometry_; }
  const TensorStage& tensorStage() const { return tensor_; }

  const Texture& vectors() const { return tensor_.vectors(); }
  const Texture& surface() const { return tensor_.surface(); }
  const Texture& eigen() const { return tensor_.eigen(); }
  const Texture& lambda() const { return tensor_.lambda(); }
  const Texture& light() const { return tensor_.light(); }
  const Texture& depth() const { return geometry_.depth(); }
  const Texture& geometry() const { return geometry_.geometry(); }
  const Texture& fibres() const { return tensor_.fibres(); }
  const Texture& vectors3() const { return tensor_.vectors3(); }
  glm::ivec2 size() const { return tensor_.size(); }
  // Pixels shaded by the last run's tensor stage (= covered pixels). Waits for the GPU.
  unsigned coveredPixels() const { return tensor_.coveredPixels(); }
  void setCompute(bool compute) { tensor_.setCompute(compute); }
  bool compute() const { return tensor_.compute(); }

private:
  GeometryStage geometry_;
  TensorStage tensor_;
};

} // namespace dtf::render
