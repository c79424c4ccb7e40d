// SPDX-License-Identifier: GPL-3.0-or-later
// Pass 4 of the fabric (paper §2.6, Eq. 13, and the medical colouring of §3.2): combines the advected
// fields, silhouettes and light into the final colour of the viewport, and writes gl_FragDepth from the
// projection depth. Draws into the framebuffer bound by the caller (the renderer's output target), at
// the viewport size; empty pixels are discarded (the caller's clear colour stays); at the data's edge
// without a background volume the colour is blended over the framebuffer by the data's cover (alpha), or
// laid over a known clear colour in the shader (CompositeSettings::overClear).
//   inputs: advected p1, p2 (their blocked pixels off the target's outer ring are the silhouettes),
//           projection surface/eigen/lambda
#pragma once

#include "render/fabric/advection_pass.h"
#include "render/fabric/frame_view.h"
#include "render/fabric_params.h"
#include "render/gl_objects.h"
#include "render/program_bindings.h"
#include "render/shader_program.h"

namespace dtf::render {

// Where the depth of the composited surface comes from.
enum class CompositeDepth {
  Computed, // written from the projection's linear depth, untested (the renderer's cleared output)
  Window,   // the projection's window depth texel (a host's surface depth), written and tested with GL_LEQUAL
  // Already in the framebuffer: the caller copied the projection's window depth there (the renderer's output
  // at full resolution). Nothing is written, and the early depth test shades only the covered pixels.
  Present,
};

struct CompositeSettings {
  ColourMode mode = ColourMode::Medical;
  float r = 0.5f;            // Eq. 13 blend between the two directions
  float contrast = 1.0f;     // f(p) = clamp(0.5 + contrast (p - 0.5)); 1 = the raw fields
  bool lighting = true;
  float lightWeight = 0.5f;  // engineering: light(L) = lightWeight * L
  float lightMix = 0.8f;     // medical: colour * mix(1, L, lightMix)
  bool silhouettes = true;
  float depthColour = 0.0f;  // 0..1 depth-enhancing colour
  float sharpen = 0.0f;      // unsharp-mask weight
  float secondaryRatio = 0.5f; // medical: lambda2'/lambda1' from which the secondary direction shows
  float secondaryFa = 0.2f;    // medical: FA below which the secondary direction shows
  float fadeOutOfPlane = 0.0f; // medical: 0..1 fading of structures along the normal
  bool background = false;     // a grey background volume beneath the fabric (projection's lambda.z)
  bool anatomy = false;        // the anatomy look: the fabric's opacity follows FA over the grey beneath
  glm::vec2 opacityFa{0.15f, 0.4f}; // anatomy: smoothstep(x, y, FA)
  bool decFa = false;          // medical: no fabric, the DEC-FA map |e1| x FA
  glm::ivec2 origin{0};        // the viewport's lower-left pixel in the framebuffer drawn into
  CompositeDepth depth = CompositeDepth::Computed;
  // The framebuffer holds clearColour with alpha 1 wherever the pass may draw (the renderer's output, just
  // cleared): the data's edge is laid over it in the shader instead of blended over the framebuffer, which a
  // software rasteriser pays for with a read of every pixel drawn. The same colour, to within one level.
  bool overClear = false;
  glm::vec3 clearColour{0.0f};
};

struct CompositeInputs {
  const Texture* p1; // advected fields (negative where the advection was blocked)
  const Texture* p2;
  const Texture* surface;
  const Texture* eigen;
  const Texture* lambda;
  const Texture* p3 = nullptr;     // Fibres: third population's field
  const Texture* fibres = nullptr; // Fibres: projection's per-population colour and weight
  const Texture* depth = nullptr;  // CompositeDepth::Window: the projection's depth
  const Texture* light = nullptr;  // CompositePass::advecting: the projection's light target (R16)
};

class CompositePass {
public:
  CompositePass();
  // Draws the viewport (guard offset applied) into the bound framebuffer at settings.origin.
  void run(const CompositeInputs& in, const FrameView& view, const CompositeSettings& settings);
  // The frame's last advection iteration and the composite in one pass (fabric/composite.frag ADVECT), for
  // the renderer's own output at full resolution without sharpening (the unsharp mask needs the neighbours'
  // new state): returns the program with its uniforms set (the composite's settings with overClear, and the
  // iteration's `iteration`) and the composite's own inputs bound (surface, eigen, lambda, fibres; in.p1,
  // in.p2, in.p3 are not read: the iteration computes them). AdvectionPass::iterateDrawing binds the state,
  // draws it over the guarded targets into the next state and a colour target, and counts when
  // `countChanges`. `fields` 2 or 3 as AdvectionPass::iterate.
  const ShaderProgram& advecting(const CompositeInputs& in, const FrameView& view, const CompositeSettings& settings,
                                 const AdvectionSettings& iteration, bool countChanges, int fields);
  // Only the depth that run() with CompositeDepth::Computed writes at full resolution and origin 0 (the
  // pixels it discards are left as they are: the caller clears to 1), into the bound framebuffer, for later
  // runs with CompositeDepth::Present. Reads in.surface and in.lambda; `background` as the settings' field.
  void runDepth(const CompositeInputs& in, const FrameView& view, bool background);

private:
  // The variant of the settings' look (the bits of programs_ below MEDICAL..FADE, without SHARPEN,
  // WINDOW_DEPTH) and its uniforms on that program; `target` the guarded targets' size.
  static unsigned lookMask(const CompositeSettings& s, bool fibres);
  void setUniforms(const ShaderProgram& p, const FrameView& view, const CompositeSettings& s,
                   glm::ivec2 target) const;
  // Binds eigen, lambda, fibres and the surface, or in its place `light` (R16).
  void bindInputs(const CompositeInputs& in, const CompositeSettings& s, const Texture* light = nullptr) const;
  // MEDICAL, SILHOUETTES, BACKGROUND, DEPTH_COLOUR, SHARPEN, FIBRES, WINDOW_DEPTH, ANATOMY, DEC_FA, FADE,
  // FAR_PLANE (CompositeDepth::Present), OVER_CLEAR, ADVECT, THIRD, COUNT, INTEGER_STEP
  ShaderVariants programs_;
  ShaderVariants depthPrograms_; // fabric/composite_depth.frag: BACKGROUND
  VertexArray vao_;
  Sampler texelSampler_; // on the texture units read texel by texel (common/texel.glsl)
};

} // namespace dtf::render
