// SPDX-License-Identifier: GPL-3.0-or-later
// gzip streams made with zlib (an inflater independent of the readers' libdeflate) for the gzip tests:
// inflate a file, re-compress it as several members, build a small stream that inflates far beyond what
// its header declares.
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>
#include <zlib.h>

namespace dtf::test {

using Bytes = std::vector<std::uint8_t>;

inline Bytes readBytes(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return Bytes(std::istreambuf_iterator<char>(in), {});
}

inline void writeBytes(const std::filesystem::path& p, const Bytes& b) {
  std::ofstream out(p, std::ios::binary);
  out.write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
}

// One gzip member of `b` (zlib, level 6).
inline Bytes gzipMember(const Bytes& b) {
  z_stream z{};
  if (deflateInit2(&z, 6, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY) != Z_OK) throw std::runtime_error("zlib");
  Bytes out(deflateBound(&z, static_cast<uLong>(b.size())) + 64);
  z.next_in = const_cast<Bytef*>(b.data());
  z.avail_in = static_cast<uInt>(b.size());
  z.next_out = out.data();
  z.avail_out = static_cast<uInt>(out.size());
  const int r = deflate(&z, Z_FINISH);
  out.resize(z.total_out);
  deflateEnd(&z);
  if (r != Z_STREAM_END) throw std::runtime_error("zlib deflate");
  return out;
}

// Every member of a gzip stream inflated (zlib's gz reader continues across members).
inline Bytes gunzipFile(const std::filesystem::path& p) {
  gzFile g = gzopen(p.c_str(), "rb");
  if (!g) throw std::runtime_error("gzopen");
  Bytes out;
  unsigned char buf[1 << 16];
  int n;
  while ((n = gzread(g, buf, sizeof buf)) > 0)
    out.insert(out.end(), buf, buf + n);
  gzclose(g);
  if (n < 0) throw std::runtime_error("gzread");
  return out;
}

// `b` cut at `cuts` (byte positions) and each piece gzipped as its own member, concatenated.
inline Bytes multiMember(const Bytes& b, const std::vector<std::size_t>& cuts) {
  Bytes out;
  std::size_t from = 0;
  std::vector<std::size_t> ends = cuts;
  ends.push_back(b.size());
  for (std::size_t to : ends) {
    const Bytes m = gzipMember(Bytes(b.begin() + static_cast<std::ptrdiff_t>(from),
                                     b.begin() + static_cast<std::ptrdiff_t>(to)));
    out.insert(out.end(), m.begin(), m.end());
    from = to;
  }
  return out;
}

// `b` followed by `extra` zero bytes, gzipped: a small file (about extra / 1000 bytes) that inflates far
// beyond the size its own header declares.
inline Bytes bomb(const Bytes& b, std::size_t extra) {
  Bytes big = b;
  big.resize(b.size() + extra, 0);
  return gzipMember(big);
}

} // namespace dtf::test
