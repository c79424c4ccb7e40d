// SPDX-License-Identifier: GPL-3.0-or-later
// Geometry stage of the projection pass (paper §2.1): the geometry buffers the tensor stage reads, for every
// pixel of the guarded target: the world normal and linear eye depth of the nearest surface (RG32UI) and
// its window depth (DEPTH32F, for the early depth test of the later passes and the composite's depth).
// Two sources fill the same buffers: a mesh (dtfabric's own front ends) rasterised with a trivial shader,
// or a host application's depth and world-normal textures (the embedding route), imported by a fullscreen
// pass that also continues the surface into the guard border.
//   outputs: geometry RG32UI (octahedral world normal as snorm16 x2, linear depth mm as float bits;
//                     0 = no surface)
//            depth    DEPTH32F (window depth; 1 = no surface)
#pragma once

#include "render/fabric/frame_view.h"
#include "render/gl_objects.h"
#include "render/gpu_scene.h"
#include "render/program_bindings.h"
#include "render/shader_program.h"

namespace dtf::render {

// A host's surface as textures: window depth (any depth format, sampled as a float in [0, 1], compare mode
// ignored) and world normals (float or signed formats: the vector; unsigned normalised formats with
// `biasedNormals`: 0.5 n + 0.5), both addressed in the host framebuffer's pixels, with the viewport the
// surface was drawn into and the host's matrices.
struct HostSurface {
  GLuint depth = 0, normal = 0;
  bool biasedNormals = false;
  glm::ivec2 origin{0}; // the viewport's lower-left pixel in the textures
  glm::mat4 projection{1.0f};
};

class GeometryStage {
public:
  GeometryStage();
  GeometryStage(const GeometryStage&) = delete;
  GeometryStage& operator=(const GeometryStage&) = delete;
  // (Re)creates the buffers when the size changes; no-op otherwise.
  void resize(glm::ivec2 target);
  // Rasterises `mesh` (world RAS mm) for `view`; with `cullHidden` back faces of a closed outward mesh are
  // culled (same image). With `draw` false the buffers are only cleared (no surface).
  void run(const GpuMesh& mesh, const FrameView& view, bool cullHidden, bool draw = true);
  // Imports the host's textures for `view` (FrameView::fromHost: its viewport is the host's, scale 1).
  void import(const HostSurface& host, const FrameView& view);

  const Texture& geometry() const { return geometry_; }
  const Texture& depth() const { return depth_; }
  glm::ivec2 size() const { return size_; }

private:
  void clear();
  ShaderProgram meshProgram_, importProgram_;
  VertexArray vao_;
  Sampler sampler_; // nearest, no depth comparison: the host's texture parameters do not matter
  Framebuffer fbo_;
  Texture geometry_, depth_;
  glm::ivec2 size_{0};
};

} // namespace dtf::render
