// SPDX-License-Identifier: GPL-3.0-or-later
// libFuzzer target: bval/bvec parsing and the gradient table checks (io/diffusion/dwi.h). The input is read both as
// a bval and as a bvec file; when both parse to the same count, makeDwi checks them against a 2x2x2
// volume with that many components (directions normalised and rotated into world RAS).
#include "fuzz_file.h"
#include "io/diffusion/dwi.h"
#include "io/model/error.h"
#include "io/model/log.h"

#include <optional>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const bool quiet = (dtf::setLogSink([](dtf::LogLevel, const std::string&) {}), true);
  (void)quiet;
  static const std::string path = dtf::fuzz::scratchPath("grad", ".txt");
  dtf::fuzz::writeInput(path, data, size);
  std::optional<std::vector<double>> bvals;
  std::optional<std::vector<glm::dvec3>> bvecs;
  try {
    bvals = dtf::io::readBvals(path);
  } catch (const dtf::Error&) {
  }
  try {
    bvecs = dtf::io::readBvecs(path, bvals ? bvals->size() : 0);
  } catch (const dtf::Error&) {
  }
  if (bvals && bvecs && bvals->size() == bvecs->size() && bvals->size() <= 4096) {
    const glm::dmat4 affine = glm::dmat4(glm::dvec4(-2, 0, 0, 0), glm::dvec4(0, 2, 0, 0),
                                         glm::dvec4(0, 0, 2, 0), glm::dvec4(10, -10, 5, 1));
    dtf::Volume<float> signal(dtf::Grid::fromAffine(glm::ivec3(2), affine), static_cast<int>(bvals->size()),
                              1.0f);
    try {
      dtf::io::makeDwi(std::move(signal), *bvals, *bvecs);
    } catch (const dtf::Error&) {
    }
  }
  return 0;
}
