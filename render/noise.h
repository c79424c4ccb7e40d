// SPDX-License-Identifier: GPL-3.0-or-later
// The input noise of the fabric (paper §2.2, Eq. 6): a Turing/Turk reaction-diffusion pattern of smooth
// spots on a periodic (seamless) square tile, computed once on the CPU from a fixed seed and cached. The
// projection pass maps it onto the surface (Eq. 7-9); advection smears it along the tensor directions.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

namespace dtf::render {

struct NoiseOptions {
  int size = 256;            // tile edge in texels (periodic in both directions)
  double spotScale = 0.025;   // s of Eq. 6: smaller -> larger spots
  std::uint32_t seed = 1;    // std::mt19937 seed of the random beta field
  int iterations = 1500;     // explicit Euler steps of Eq. 6
};

struct NoiseTile {
  int size = 0;
  std::vector<float> values; // size*size, row-major, rank-normalised: uniform on [0, 1]
  float at(int x, int y) const { return values[static_cast<std::size_t>(y) * size + x]; }
};

// Runs Eq. 6 with Da = 0.125, Db = 0.031 and periodic boundaries; same options give identical values.
NoiseTile makeReactionDiffusion(const NoiseOptions& options);
// Cached per (size, spotScale, seed, iterations) for the life of the process. Thread-safe.
std::shared_ptr<const NoiseTile> cachedReactionDiffusion(const NoiseOptions& options);

} // namespace dtf::render
