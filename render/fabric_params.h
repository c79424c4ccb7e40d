// SPDX-License-Identifier: GPL-3.0-or-later
// The fabric's parameters and the GPU pass times of a frame: plain values shared by the renderers
// (FabricRenderer, EmbeddedFabric) and the option table; no GL types, so a host's code can include it.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <glm/glm.hpp>

namespace dtf::render {

// Medical and Engineering colour a tensor's two in-plane eigenvector fields; Fibres colours each fibre
// population (up to three) in its own DEC colour (a tensor shown this way is its e1 only).
enum class ColourMode { Medical, Engineering, Fibres };

// Anatomy: the fabric's opacity follows FA (FabricParams::opacityFa*) over a grey background (a background
// volume when one is set, else FA), so isotropic tissue shows the anatomy. Plain: the paper's look, the
// fabric on every point with tensor data. DecFa: no fabric, the classic DEC-FA map (|e1| x FA; medical colour
// only), for comparison.
enum class Look { Anatomy, Plain, DecFa };

struct FabricParams {
  double lod = 0; // l of Eq. 7 in mm; 0 = auto: one noise tile spans autoLodPixels pixels (follows
                  // the zoom; set a fixed l for the same texture across views, meshes and hosts)
  double autoLodPixels = 256;
  double k = 0.1;        // Eq. 12 weight of beta
  int iterations = 3;    // advection iterations per frame (paper: 3)
  double epsilon = 0.05; // change below which a pixel is converged (paper §2.5)
  double r = 0.5;        // Eq. 13 blend
  ColourMode colour = ColourMode::Medical;
  double spotScale = 0.025; // s of Eq. 6
  std::uint32_t seed = 1;   // noise seed
  int noiseSize = 256;      // noise tile edge, texels
  bool lighting = true;
  bool silhouette = true;
  double silhouettePixels = 1.5; // Laplacian threshold in pixel sizes (mm per pixel)
  double sharpen = 0.0;
  double depthColour = 0.0;
  double stepPixels = 2.0; // advection step length in pixels (thread length ~ step / sqrt(k))
  double contrast = 4.0;   // f(p) stretch before Eq. 13 / medical luminance; 1 = raw
  double noiseBlend = 0.0; // 0 = Eq. 9 exactly
  int guard = 16;          // guard border in pixels
  glm::vec3 background{0.0f};
  int stillMaxIterations = 100;        // renderStill: iteration cap
  double stillChangedFraction = 0.002; // renderStill: stop when fewer covered pixels than this changed
  float fadeOutOfPlane = 0.0f;
  Look look = Look::Anatomy;
  float opacityFaLow = 0.15f;  // Look::Anatomy: the fabric's opacity is smoothstep(low, high, FA)
  float opacityFaHigh = 0.4f;
  float faFloor = 0.0f;         // fabric only where FA >= faFloor (the rest shows the background or grey)
  double movingScale = 1.0;     // renderFrame: internal resolution while the camera moves (e.g. 0.5)
  double fray = 1.0;       // with a cone map: each noise cell turns by up to fray x its 95 % cone
  double frayCells = 16.0; // noise cells per noise tile edge (each cell one hash-drawn turn)
  float fibreThreshold = 0.15f; // ColourMode::Fibres: lobes below this fraction of their voxel's strongest
                                // are dropped (between mrview's usual 0.1 and 0.2)

  // The fewest iterations after a restart from beta before a still may stop on its count of changed pixels:
  // until the start image's weight (1 - k)^n falls below epsilon the fabric is not converged, however little
  // the pixels change per iteration (within [1, stillMaxIterations]).
  int stillMinIterations() const {
    int n = stillMaxIterations;
    if (k > 0 && k < 1 && epsilon > 0 && epsilon < 1)
      n = static_cast<int>(std::ceil(std::log(epsilon) / std::log(1.0 - k)));
    else if (k >= 1)
      n = 1;
    return std::clamp(n, 1, std::max(stillMaxIterations, 1));
  }
};

// GPU times of the passes of the last timed frame, ms (GL_TIME_ELAPSED).
struct PassTimes {
  double projection = 0, silhouette = 0, advection = 0, composite = 0, phong = 0;
};

} // namespace dtf::render
