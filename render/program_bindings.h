// SPDX-License-Identifier: GPL-3.0-or-later
// The texture units, atomic-counter bindings and uniforms of every pass program, named once here. The
// bindings reach the GLSL as defines (bindingDefines(Program::kBindings), injected when the program is
// compiled): `layout(binding = UNIT_PREV2) uniform sampler2D u_prev2;`, and a shader naming a binding that
// is not injected does not compile. The C++ binds with the enums (bindTexture(Unit::Prev2, ...)) and sets
// uniforms by the Uniform enums, whose locations each program looks up once when it is linked.
#pragma once

#include "render/shader_program.h"

#include <array>

namespace dtf::render {

// Two binding tables as one (a program's shared bindings followed by its own).
template <std::size_t A, std::size_t B>
constexpr std::array<BindingName, A + B> joinBindings(std::span<const BindingName, A> a,
                                                      std::span<const BindingName, B> b) {
  std::array<BindingName, A + B> out{};
  for (std::size_t i = 0; i < A; ++i) out[i] = a[i];
  for (std::size_t i = 0; i < B; ++i) out[A + i] = b[i];
  return out;
}
template <std::size_t A, std::size_t B>
constexpr std::array<BindingName, A + B> joinBindings(const BindingName (&a)[A], const BindingName (&b)[B]) {
  return joinBindings(std::span<const BindingName, A>(a), std::span<const BindingName, B>(b));
}
template <std::size_t A, std::size_t B>
constexpr std::array<BindingName, A + B> joinBindings(const std::array<BindingName, A>& a,
                                                      const BindingName (&b)[B]) {
  return joinBindings(std::span<const BindingName, A>(a), std::span<const BindingName, B>(b));
}

// The texture units, the image units an iteration reads and the counter of the advection (AdvectionPass),
// used by both its programs. Image units stay below 8, the number GL 4.5 guarantees; an iteration's reads
// share units 3 to 6 with the compute restart's second targets and its edges, which no program uses together.
// A restart reads the surface target as an image (its texel and the silhouette test's neighbours) at unit 7.
struct AdvectionBindings {
  enum class Unit : GLuint {
    Prev1 = 0, Surface = 2, Silhouette = 3, Prev2 = 4, Prev3 = 5, HistorySurface = 6, Depth = 7
  };
  // An iteration's texel reads (imageLoad: on llvmpipe inlined, where a texelFetch calls a function): p_i at
  // the pixel itself and the projection's vectors (three-field iterations: its vectors3 target).
  enum class ReadImage : GLuint { Here1 = 3, Here2 = 4, Here3 = 5, Vectors = 6, Surface = 7 };
  enum class Counter : GLuint { Changed = 0 };
  // What an iteration binds (common/advection_step.glsl): also the composite's, which reads the state at its
  // pixel on the same image units and runs a frame's last iteration itself (ADVECT).
  static constexpr BindingName kIteration[] = {
      {unit(Unit::Prev1), "UNIT_PREV1", "u_prev1"},
      {unit(Unit::Prev2), "UNIT_PREV2", "u_prev2"},
      {unit(Unit::Prev3), "UNIT_PREV3", "u_prev3"},
      {unit(ReadImage::Here1), "IMAGE_HERE1", "u_here1"},
      {unit(ReadImage::Here2), "IMAGE_HERE2", "u_here2"},
      {unit(ReadImage::Here3), "IMAGE_HERE3", "u_here3"},
      {unit(ReadImage::Vectors), "IMAGE_VECTORS", "u_vectors"},
      {unit(Counter::Changed), "COUNTER_CHANGED", "u_changed"},
  };
  // A restart's inputs (common/advection_restart.glsl).
  static constexpr BindingName kRestart[] = {
      {unit(Unit::Surface), "UNIT_SURFACE", "u_surface"},
      {unit(Unit::Silhouette), "UNIT_SILHOUETTE", "u_silhouette"},
      {unit(ReadImage::Surface), "IMAGE_SURFACE", "u_surfaceImage"},
  };
  static constexpr auto kShared = joinBindings(kIteration, kRestart);
};

// fabric/advection.frag (AdvectionPass), every variant: the shared bindings and the movie's reprojection.
struct AdvectionProgram {
  using Unit = AdvectionBindings::Unit;
  using Counter = AdvectionBindings::Counter;
  static constexpr BindingName kOwn[] = {
      {unit(Unit::HistorySurface), "UNIT_HISTORY_SURFACE", "u_histSurface"},
      {unit(Unit::Depth), "UNIT_DEPTH", "u_depth"},
  };
  static constexpr auto kBindings = joinBindings(AdvectionBindings::kShared, kOwn);
  enum class Uniform {
    K, Step, ComplementSecond, Epsilon, WindowToWorld, WorldToPrevWindow, WorldToPrevEye, DepthTol, Threshold,
    Background, Count
  };
};

// fabric/advection.comp (AdvectionPass::setCompute): the shared bindings (common/advection_step.glsl,
// common/advection_restart.glsl) and the image units it writes.
struct AdvectionComputeProgram {
  using Unit = AdvectionBindings::Unit;
  using Counter = AdvectionBindings::Counter;
  using Uniform = AdvectionProgram::Uniform;
  // Next: the iteration's target (the restart's first ping-pong texture); Other: the restart's second.
  enum class Image : GLuint { Next1 = 0, Next2 = 1, Next3 = 2, Other1 = 3, Other2 = 4, Other3 = 5, Edge = 6 };
  static constexpr BindingName kOwn[] = {
      {unit(Image::Next1), "IMAGE_NEXT1", "o_p1"},   {unit(Image::Next2), "IMAGE_NEXT2", "o_p2"},
      {unit(Image::Next3), "IMAGE_NEXT3", "o_p3"},   {unit(Image::Other1), "IMAGE_OTHER1", "o_p1b"},
      {unit(Image::Other2), "IMAGE_OTHER2", "o_p2b"}, {unit(Image::Other3), "IMAGE_OTHER3", "o_p3b"},
      {unit(Image::Edge), "IMAGE_EDGE", "o_edge"},
  };
  static constexpr auto kBindings = joinBindings(AdvectionBindings::kShared, kOwn);
};

// fabric/composite.frag (CompositePass). It reads its inputs as images (imageLoad, inlined on llvmpipe), and
// a host's window depth as a texture (WINDOW_DEPTH: a depth format, which no image unit takes). The advected
// fields at its pixel are read on an iteration's units (AdvectionBindings::ReadImage Here1..3), with whose
// bindings the ADVECT variant runs a frame's last iteration in the same pass (AdvectionPass::iterateDrawing
// binds the state, the vectors and the counter); its own images take the other units.
struct CompositeProgram {
  enum class Unit : GLuint { Depth = 0 }; // WINDOW_DEPTH, never with ADVECT (whose p1 is on texture unit 0)
  using ReadImage = AdvectionBindings::ReadImage;
  // Light: ADVECT without DEPTH_COLOUR reads the projection's light target instead of the surface.
  enum class Image : GLuint { Surface = 0, Light = 0, Eigen = 1, Lambda = 2, Fibres = 7 };
  static constexpr BindingName kOwn[] = {
      {unit(Image::Surface), "IMAGE_SURFACE", "u_surface"},
      {unit(Image::Light), "IMAGE_LIGHT", "u_light"},
      {unit(Image::Eigen), "IMAGE_EIGEN", "u_eigen"},
      {unit(Image::Lambda), "IMAGE_LAMBDA", "u_lambda"},
      {unit(Image::Fibres), "IMAGE_FIBRES", "u_fibres"},
      {unit(Unit::Depth), "UNIT_DEPTH", "u_depth"},
  };
  static constexpr auto kBindings = joinBindings(AdvectionBindings::kIteration, kOwn);
  enum class Uniform {
    Guard, Origin, Scale, EyeDepth, R, Contrast, LightWeight, LightMix, Lighting, DepthColour, DepthRange,
    Sharpen, SecondaryRatio, SecondaryFa, FadeOutOfPlane, OpacityFa, Target, ClearColour,
    K, Step, ComplementSecond, Epsilon, // ADVECT: the iteration's (AdvectionProgram's of the same names)
    Count
  };
};

// fabric/composite_depth.frag (CompositePass::runDepth).
struct CompositeDepthProgram {
  using Image = CompositeProgram::Image; // the composite's units for the same targets
  static constexpr BindingName kBindings[] = {
      {unit(Image::Surface), "IMAGE_SURFACE", "u_surface"},
      {unit(Image::Lambda), "IMAGE_LAMBDA", "u_lambda"},
  };
  enum class Uniform { Guard, EyeDepth, Count };
};

// fabric/silhouette.frag (SilhouettePass).
struct SilhouetteProgram {
  enum class Unit : GLuint { Surface = 0 };   // its size (fabric/silhouette.vert)
  enum class Image : GLuint { Surface = 0 };  // its texels
  static constexpr BindingName kBindings[] = {{unit(Unit::Surface), "UNIT_SURFACE", "u_surface"},
                                              {unit(Image::Surface), "IMAGE_SURFACE", "u_surfaceImage"}};
  enum class Uniform { Threshold, Background, Count };
};

// fabric/projection.frag (TensorStage) with common/tensor_field.glsl or common/fibre_field.glsl (FIBRES):
// the two includes are exclusive, so the tensor and lobe textures share units 0 and 1. Each slot's lobe is
// two textures (LobeK and LobeKB: its amplitude-weighted dyadic; common/fibre_field.glsl).
struct ProjectionProgram {
  enum class Unit : GLuint {
    TensorA = 0,
    TensorB = 1,
    Lobe0 = 0,
    Lobe1 = 1,
    Noise = 2,
    Background = 3,
    Lobe0B = 4,
    Lobe2 = 5,
    FibreFa = 6,
    TensorEdge = 7,
    Uncertainty = 8,
    Lobe1B = 10,
    Lobe2B = 11,
    Along = 12
  };
  // The geometry stage's target, texel by texel (an image load: inlined on llvmpipe); above the compute
  // pass's five written images.
  enum class ReadImage : GLuint { Geometry = 5 };
  static constexpr BindingName kBindings[] = {
      {unit(Unit::TensorA), "UNIT_TENSOR_A", "u_tensorA"},
      {unit(Unit::TensorB), "UNIT_TENSOR_B", "u_tensorB"},
      {unit(Unit::TensorEdge), "UNIT_TENSOR_EDGE", "u_tensorEdge"},
      {unit(Unit::Lobe0), "UNIT_LOBE0", "u_lobe0"},
      {unit(Unit::Lobe1), "UNIT_LOBE1", "u_lobe1"},
      {unit(Unit::Lobe2), "UNIT_LOBE2", "u_lobe2"},
      {unit(Unit::Lobe0B), "UNIT_LOBE0B", "u_lobe0b"},
      {unit(Unit::Lobe1B), "UNIT_LOBE1B", "u_lobe1b"},
      {unit(Unit::Lobe2B), "UNIT_LOBE2B", "u_lobe2b"},
      {unit(Unit::FibreFa), "UNIT_FIBRE_FA", "u_fibreFa"},
      {unit(Unit::Noise), "UNIT_NOISE", "u_noise"},
      {unit(Unit::Background), "UNIT_BACKGROUND", "u_background"},
      {unit(ReadImage::Geometry), "IMAGE_GEOMETRY", "u_geometry"},
      {unit(Unit::Uncertainty), "UNIT_UNCERTAINTY", "u_uncertainty"},
      {unit(Unit::Along), "UNIT_ALONG", "u_along"},
  };
  enum class Uniform {
    ClipToEye,
    EyeToWorld,
    ViewProj,
    ViewRot,
    TargetSize,
    Eps,
    DegenerateTol,
    Orthographic,
    PixelMm,
    PixelMmPerDepth,
    NoiseOrigin,
    Lod,
    NoiseBlend,
    WorldToTex,
    LobeCount,
    FaFloor,
    BackgroundWorldToTex,
    UncertaintyWorldToTex,
    Fray,
    FrayCells,
    AlongScale,
    AlongOffset,
    Count
  };
};

// fabric/projection.comp (TensorStage::setCompute): the fragment pass's texture units (the same
// common/projection_pixel.glsl), the geometry stage's depth, the targets as images and the covered-pixel
// count's buffer.
struct ProjectionComputeProgram {
  using Unit = ProjectionProgram::Unit;
  using Uniform = ProjectionProgram::Uniform;
  static constexpr GLuint kDepthUnit = 9; // below the lobe textures' 10 and 11
  // Around the geometry stage's read image (5).
  enum class Image : GLuint { Vectors = 0, Surface = 1, Eigen = 2, Lambda = 3, Fibres = 4, Vectors3 = 6, Light = 7 };
  enum class Buffer : GLuint { Covered = 0 };
  static constexpr BindingName kOwn[] = {
      {kDepthUnit, "UNIT_DEPTH", "u_depth"},
      {unit(Image::Vectors), "IMAGE_VECTORS", "i_vectors"},
      {unit(Image::Surface), "IMAGE_SURFACE", "i_surface"},
      {unit(Image::Eigen), "IMAGE_EIGEN", "i_eigen"},
      {unit(Image::Lambda), "IMAGE_LAMBDA", "i_lambda"},
      {unit(Image::Fibres), "IMAGE_FIBRES", "i_fibres"},
      {unit(Image::Vectors3), "IMAGE_VECTORS3", "i_vectors3"},
      {unit(Image::Light), "IMAGE_LIGHT", "i_light"},
      {unit(Buffer::Covered), "BUFFER_COVERED", "CoveredPixels"},
  };
  static constexpr auto kBindings = joinBindings(ProjectionProgram::kBindings, kOwn);
};

// fabric/geometry.vert + geometry.frag (GeometryStage, own meshes).
struct GeometryProgram {
  static constexpr std::span<const BindingName> kBindings{};
  enum class Uniform { ViewProj, View, Count };
};

// common/deferred.vert + fabric/host_import.frag (GeometryStage, a host's depth and normals).
struct HostImportProgram {
  enum class Unit : GLuint { HostDepth = 0, HostNormal = 1 };
  static constexpr BindingName kBindings[] = {
      {unit(Unit::HostDepth), "UNIT_HOST_DEPTH", "u_hostDepth"},
      {unit(Unit::HostNormal), "UNIT_HOST_NORMAL", "u_hostNormal"},
  };
  enum class Uniform { ClipToEye, HostClipToEye, Projection, ViewRot, BiasedNormals, Origin, Extent, Guard, Count };
};

// fabric/phong.vert + phong.frag (PhongPass).
struct PhongProgram {
  static constexpr std::span<const BindingName> kBindings{};
  enum class Uniform { ViewProj, View, ViewRot, Orthographic, Colour, Count };
};

// common/fullscreen.vert + tracts/layer.frag (TractLayer).
struct TractLayerProgram {
  enum class Unit : GLuint { Fabric = 0, Layer = 1 };
  static constexpr BindingName kBindings[] = {
      {unit(Unit::Fabric), "UNIT_FABRIC", "u_fabric"},
      {unit(Unit::Layer), "UNIT_LAYER", "u_layer"},
  };
};

// tracts/lines.vert + lines.geom + lines.frag (TractRenderer): no textures, uniforms only.
struct TractLinesProgram {
  static constexpr std::span<const BindingName> kBindings{};
  enum class Uniform {
    View,
    Proj,
    ViewRot,
    Viewport,
    WidthPx,
    DepthBiasMm,
    Plane,
    SlabMm,
    HighlightNode,
    HighlightHalfWidth,
    HighlightColour,
    NodeColoured,
    NodeColours,
    Count
  };
};

// The programs' bindings as defines.
template <class Program>
std::vector<std::string> programDefines() {
  return bindingDefines({std::span<const BindingName>(Program::kBindings)});
}

constexpr const char* uniformName(AdvectionProgram::Uniform u) {
  using U = AdvectionProgram::Uniform;
  switch (u) {
  case U::K: return "u_k";
  case U::Step: return "u_step";
  case U::ComplementSecond: return "u_complementSecond";
  case U::Epsilon: return "u_epsilon";
  case U::WindowToWorld: return "u_windowToWorld";
  case U::WorldToPrevWindow: return "u_worldToPrevWindow";
  case U::WorldToPrevEye: return "u_worldToPrevEye";
  case U::DepthTol: return "u_depthTol";
  case U::Threshold: return "u_threshold";
  case U::Background: return "u_background";
  case U::Count: break;
  }
  return "";
}

constexpr const char* uniformName(CompositeProgram::Uniform u) {
  using U = CompositeProgram::Uniform;
  switch (u) {
  case U::Guard: return "u_guard";
  case U::Origin: return "u_origin";
  case U::Scale: return "u_scale";
  case U::EyeDepth: return "u_eyeDepth";
  case U::R: return "u_r";
  case U::Contrast: return "u_contrast";
  case U::LightWeight: return "u_lightWeight";
  case U::LightMix: return "u_lightMix";
  case U::Lighting: return "u_lighting";
  case U::DepthColour: return "u_depthColour";
  case U::DepthRange: return "u_depthRange";
  case U::Sharpen: return "u_sharpen";
  case U::SecondaryRatio: return "u_secondaryRatio";
  case U::SecondaryFa: return "u_secondaryFa";
  case U::FadeOutOfPlane: return "u_fadeOutOfPlane";
  case U::OpacityFa: return "u_opacityFa";
  case U::Target: return "u_target";
  case U::ClearColour: return "u_clearColour";
  case U::K: return uniformName(AdvectionProgram::Uniform::K);
  case U::Step: return uniformName(AdvectionProgram::Uniform::Step);
  case U::ComplementSecond: return uniformName(AdvectionProgram::Uniform::ComplementSecond);
  case U::Epsilon: return uniformName(AdvectionProgram::Uniform::Epsilon);
  case U::Count: break;
  }
  return "";
}

constexpr const char* uniformName(CompositeDepthProgram::Uniform u) {
  using U = CompositeDepthProgram::Uniform;
  switch (u) {
  case U::Guard: return "u_guard";
  case U::EyeDepth: return "u_eyeDepth";
  case U::Count: break;
  }
  return "";
}

constexpr const char* uniformName(SilhouetteProgram::Uniform u) {
  using U = SilhouetteProgram::Uniform;
  switch (u) {
  case U::Threshold: return "u_threshold";
  case U::Background: return "u_background";
  case U::Count: break;
  }
  return "";
}

constexpr const char* uniformName(ProjectionProgram::Uniform u) {
  using U = ProjectionProgram::Uniform;
  switch (u) {
  case U::ClipToEye: return "u_clipToEye";
  case U::EyeToWorld: return "u_eyeToWorld";
  case U::ViewProj: return "u_viewProj";
  case U::ViewRot: return "u_viewRot";
  case U::TargetSize: return "u_targetSize";
  case U::Eps: return "u_eps";
  case U::DegenerateTol: return "u_degenerateTol";
  case U::Orthographic: return "u_orthographic";
  case U::PixelMm: return "u_pixelMm";
  case U::PixelMmPerDepth: return "u_pixelMmPerDepth";
  case U::NoiseOrigin: return "u_noiseOrigin";
  case U::Lod: return "u_lod";
  case U::NoiseBlend: return "u_noiseBlend";
  case U::WorldToTex: return "u_worldToTex";
  case U::LobeCount: return "u_lobeCount";
  case U::FaFloor: return "u_faFloor";
  case U::BackgroundWorldToTex: return "u_backgroundWorldToTex";
  case U::UncertaintyWorldToTex: return "u_uncertaintyWorldToTex";
  case U::Fray: return "u_fray";
  case U::FrayCells: return "u_frayCells";
  case U::AlongScale:
    return "u_alongScale";
  case U::AlongOffset:
    return "u_alongOffset";
  case U::Count: break;
  }
  return "";
}

constexpr const char* uniformName(GeometryProgram::Uniform u) {
  using U = GeometryProgram::Uniform;
  switch (u) {
  case U::ViewProj: return "u_viewProj";
  case U::View: return "u_view";
  case U::Count: break;
  }
  return "";
}

constexpr const char* uniformName(HostImportProgram::Uniform u) {
  using U = HostImportProgram::Uniform;
  switch (u) {
  case U::ClipToEye: return "u_clipToEye";
  case U::HostClipToEye: return "u_hostClipToEye";
  case U::Projection: return "u_projection";
  case U::ViewRot: return "u_viewRot";
  case U::BiasedNormals: return "u_biasedNormals";
  case U::Origin: return "u_origin";
  case U::Extent: return "u_extent";
  case U::Guard: return "u_guard";
  case U::Count: break;
  }
  return "";
}

constexpr const char* uniformName(PhongProgram::Uniform u) {
  using U = PhongProgram::Uniform;
  switch (u) {
  case U::ViewProj: return "u_viewProj";
  case U::View: return "u_view";
  case U::ViewRot: return "u_viewRot";
  case U::Orthographic: return "u_orthographic";
  case U::Colour: return "u_colour";
  case U::Count: break;
  }
  return "";
}

constexpr const char* uniformName(TractLinesProgram::Uniform u) {
  using U = TractLinesProgram::Uniform;
  switch (u) {
  case U::View:
    return "u_view";
  case U::Proj:
    return "u_proj";
  case U::ViewRot:
    return "u_viewRot";
  case U::Viewport:
    return "u_viewport";
  case U::WidthPx:
    return "u_widthPx";
  case U::DepthBiasMm:
    return "u_depthBiasMm";
  case U::Plane:
    return "u_plane";
  case U::SlabMm:
    return "u_slabMm";
  case U::HighlightNode:
    return "u_highlightNode";
  case U::HighlightHalfWidth:
    return "u_highlightHalfWidth";
  case U::HighlightColour:
    return "u_highlightColour";
  case U::NodeColoured:
    return "u_nodeColoured";
  case U::NodeColours:
    return "u_nodeColour";
  case U::Count:
    break;
  }
  return "";
}

} // namespace dtf::render
