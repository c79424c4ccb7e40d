// SPDX-License-Identifier: GPL-3.0-or-later
// libFuzzer target: NIfTI header, scalar, tensor (io/formats/tensor_io.h) and fibre-peaks (io/formats/fibre_io.h) readers. Inputs that start with the
// gzip magic are read as .nii.gz, the others as .nii. Any dtf::Error is an accepted outcome; a crash, a
// sanitizer report, a leak or an allocation beyond -rss_limit_mb is a finding.
#include "fuzz_file.h"
#include "io/model/error.h"
#include "io/model/log.h"
#include "io/formats/fibre_io.h"
#include "io/formats/tensor_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const bool quiet = (dtf::setLogSink([](dtf::LogLevel, const std::string&) {}), true);
  (void)quiet;
  const bool gz = size >= 2 && data[0] == 0x1f && data[1] == 0x8b;
  static const std::string plain = dtf::fuzz::scratchPath("in", ".nii");
  static const std::string packed = dtf::fuzz::scratchPath("in", ".nii.gz");
  const std::string& path = gz ? packed : plain;
  dtf::fuzz::writeInput(path, data, size);
  try {
    dtf::io::readHeader(path);
  } catch (const dtf::Error&) {
    return 0; // the volume readers run the same header checks first
  }
  try {
    dtf::io::readScalarVolume(path);
  } catch (const dtf::Error&) {
  }
  try {
    dtf::io::readTensorVolume(path);
  } catch (const dtf::Error&) {
  }
  try {
    dtf::io::looksLikeFibres(path);
    dtf::io::readFibres(path); // auto: marker, or the frame by fibre coherence
  } catch (const dtf::Error&) {
  }
  try {
    dtf::io::readFibres(path, dtf::io::FibreLayout::DipyPeaks);
  } catch (const dtf::Error&) {
  }
  return 0;
}
