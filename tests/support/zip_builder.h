// Builds ZIP archives byte by byte for tests (independent of io/zip_archive): entries stored or raw-deflated
// with zlib, with the central directory and end record, so tests can make TRX files, and break them.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>
#include <zlib.h>

namespace dtf::test {

struct ZipEntry {
  std::string name, data;
  bool deflate = false;
};

inline void zipPut(std::string& s, std::uint64_t v, int bytes) {
  for (int i = 0; i < bytes; ++i)
    s.push_back(static_cast<char>((v >> (8 * i)) & 0xff));
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

inline std::string zipArchive(const std::vector<ZipEntry>& entries) {
  std::string out, cd;
  for (const auto& e : entries) {
    const std::string body = e.deflate ? rawDeflate(e.data) : e.data;
    const std::uint32_t crc = static_cast<std::uint32_t>(
        crc32(0L, reinterpret_cast<const Bytef*>(e.data.data()), static_cast<uInt>(e.data.size())));
    const std::size_t offset = out.size();
    auto common = [&](std::string& s) {
      zipPut(s, 20, 2);
      zipPut(s, 0, 2);
      zipPut(s, e.deflate ? 8 : 0, 2);
      zipPut(s, 0, 4); // time, date
      zipPut(s, crc, 4);
      zipPut(s, body.size(), 4);
      zipPut(s, e.data.size(), 4);
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
