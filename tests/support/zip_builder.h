// SPDX-License-Identifier: GPL-3.0-or-later
// Builds ZIP archives byte by byte for tests (independent of io/zip_archive): entries stored or raw-deflated
// with zlib, with the central directory and end record, so tests can make TRX files, and break them.
#pragma once

#include <algorithm>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>
#include <zlib.h>

namespace dtf::test {

struct ZipEntry {
  std::string name, data;
  bool deflate = false;
  // When set, `data` is already raw-deflated and these are the inflated size and CRC-32 (for entries too
  // large to hold inflated, such as deflate bombs).
  std::uint64_t inflatedSize = 0;
  std::uint32_t inflatedCrc = 0;
};

// Little-endian, `bytes` wide; bytes beyond the eighth are zero (a shift by 64 or more is undefined).
inline void zipPut(std::string& s, std::uint64_t v, int bytes) {
  for (int i = 0; i < bytes; ++i)
    s.push_back(i < 8 ? static_cast<char>((v >> (8 * i)) & 0xff) : '\0');
}

inline std::string rawDeflate(const std::string& in) {
  z_stream z{};
  deflateInit2(&z, 6, Z_DEFLATED, -15, 8, Z_DEFAULT_STRATEGY);
  std::string out(deflateBound(&z, static_cast<uLong>(in.size())) + 16, '\0');
  z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(in.data()));
  z.avail_in = static_cast<uInt>(in.size());
  z.next_out = reinterpret_cast<Bytef*>(out.data());
  z.avail_out = static_cast<uInt>(out.size());
  deflate(&z, Z_FINISH);
  out.resize(z.total_out);
  deflateEnd(&z);
  return out;
}

// `zeros` zero bytes raw-deflated in 1 MiB steps (a deflate bomb's body: about 1 KiB per MiB), with their
// CRC-32 in `crc`.
inline std::string rawDeflateZeros(std::uint64_t zeros, std::uint32_t& crc, int windowBits = -15) {
  z_stream z{};
  deflateInit2(&z, 9, Z_DEFLATED, windowBits, 9, Z_DEFAULT_STRATEGY);
  const std::string in(std::size_t(1) << 20, '\0');
  std::string out, buf(std::size_t(1) << 16, '\0');
  uLong c = crc32(0L, Z_NULL, 0);
  for (std::uint64_t left = zeros;;) {
    const uInt n = static_cast<uInt>(std::min<std::uint64_t>(left, in.size()));
    c = crc32(c, reinterpret_cast<const Bytef*>(in.data()), n);
    left -= n;
    z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(in.data()));
    z.avail_in = n;
    const int flush = left == 0 ? Z_FINISH : Z_NO_FLUSH;
    int rc;
    do {
      z.next_out = reinterpret_cast<Bytef*>(buf.data());
      z.avail_out = static_cast<uInt>(buf.size());
      rc = deflate(&z, flush);
      out.append(buf.data(), buf.size() - z.avail_out);
    } while (z.avail_out == 0 || (flush == Z_FINISH && rc != Z_STREAM_END));
    if (left == 0) break;
  }
  deflateEnd(&z);
  crc = static_cast<std::uint32_t>(c);
  return out;
}

inline std::string zipArchive(const std::vector<ZipEntry>& entries) {
  std::string out, cd;
  for (const auto& e : entries) {
    const bool pre = e.inflatedSize > 0;
    const std::string body = e.deflate && !pre ? rawDeflate(e.data) : e.data;
    const std::uint32_t crc =
        pre ? e.inflatedCrc
            : static_cast<std::uint32_t>(
                  crc32(0L, reinterpret_cast<const Bytef*>(e.data.data()), static_cast<uInt>(e.data.size())));
    const std::uint64_t size = pre ? e.inflatedSize : e.data.size();
    const std::size_t offset = out.size();
    auto common = [&](std::string& s) {
      zipPut(s, 20, 2);
      zipPut(s, 0, 2);
      zipPut(s, e.deflate || pre ? 8 : 0, 2);
      zipPut(s, 0, 4); // time, date
      zipPut(s, crc, 4);
      zipPut(s, body.size(), 4);
      zipPut(s, size, 4);
      zipPut(s, e.name.size(), 2);
      zipPut(s, 0, 2);
    };
    zipPut(out, 0x04034b50, 4);
    common(out);
    out += e.name + body;
    zipPut(cd, 0x02014b50, 4);
    zipPut(cd, 20, 2);
    common(cd);
    zipPut(cd, 0, 2 + 2 + 2 + 4); // comment, disk, attributes
    zipPut(cd, offset, 4);
    cd += e.name;
  }
  const std::size_t cdAt = out.size();
  out += cd;
  zipPut(out, 0x06054b50, 4);
  zipPut(out, 0, 4);
  zipPut(out, entries.size(), 2);
  zipPut(out, entries.size(), 2);
  zipPut(out, cd.size(), 4);
  zipPut(out, cdAt, 4);
  zipPut(out, 0, 2);
  return out;
}

} // namespace dtf::test
