// SPDX-License-Identifier: GPL-3.0-or-later
#include "io/formats/sample_types.h"

#include <cstring>
#include <type_traits>

namespace dtf::io::detail {

namespace {

template <typename T> double fetch(const std::uint8_t* p, bool bigEndian) {
  std::uint8_t b[sizeof(T)];
  for (std::size_t k = 0; k < sizeof(T); ++k)
    b[k] = bigEndian ? p[sizeof(T) - 1 - k] : p[k];
  T v;
  std::memcpy(&v, b, sizeof(T));
  return static_cast<double>(v);
}

template <typename T> void toFloat(const std::uint8_t* src, std::size_t n, float* dst) {
  for (std::size_t i = 0; i < n; ++i) {
    T v;
    std::memcpy(&v, src + i * sizeof(T), sizeof(T));
    dst[i] = static_cast<float>(v);
  }
}

template <typename T> constexpr SampleTypeInfo info(const char* name) {
  return {
      name,       static_cast<int>(sizeof(T)), std::is_floating_point_v<T>, std::is_signed_v<T>, &fetch<T>,
      &toFloat<T>};
}

// In the order of SampleType.
constexpr SampleTypeInfo kTypes[] = {
    info<std::uint8_t>("UInt8"),   info<std::int8_t>("Int8"),     info<std::uint16_t>("UInt16"),
    info<std::int16_t>("Int16"),   info<std::uint32_t>("UInt32"), info<std::int32_t>("Int32"),
    info<std::uint64_t>("UInt64"), info<std::int64_t>("Int64"),   info<float>("Float32"),
    info<double>("Float64"),
};

} // namespace

const SampleTypeInfo& sampleTypeInfo(SampleType t) {
  return kTypes[static_cast<int>(t)];
}

} // namespace dtf::io::detail
