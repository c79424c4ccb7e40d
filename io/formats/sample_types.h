// SPDX-License-Identifier: GPL-3.0-or-later
// The stored number types the volume readers meet (NIfTI datatypes, MRtrix datatypes, NRRD types, AFNI
// brick types, MATLAB v4 precisions) and the one table that converts them: each reader maps its own codes
// onto SampleType and reads through this table. Internal to dtf_io.
#pragma once

#include <cstddef>
#include <cstdint>

namespace dtf::io::detail {

enum class SampleType { UInt8, Int8, UInt16, Int16, UInt32, Int32, UInt64, Int64, Float32, Float64 };

struct SampleTypeInfo {
  const char* name; // "UInt8", "Int16", "Float32", ...
  int bytes;
  bool isFloat, isSigned;
  // One value at p, stored in either byte order, as double.
  double (*fetch)(const std::uint8_t* p, bool bigEndian);
  // n consecutive values in the host's byte order, each cast to float.
  void (*toFloat)(const std::uint8_t* src, std::size_t n, float* dst);
};

const SampleTypeInfo& sampleTypeInfo(SampleType t);

inline double fetchSample(const std::uint8_t* p, SampleType t, bool bigEndian) {
  return sampleTypeInfo(t).fetch(p, bigEndian);
}

} // namespace dtf::io::detail
