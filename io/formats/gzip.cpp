// SPDX-License-Identifier: GPL-3.0-or-later
#include "io/formats/gzip.h"

#include "io/model/error.h"
#include "io/model/huge_pages.h"

#include <libdeflate.h>

#include <algorithm>
#include <limits>
#include <memory>

namespace dtf::io::detail {

namespace {

struct DecompressorFree {
  void operator()(libdeflate_decompressor* d) const { libdeflate_free_decompressor(d); }
};
using Decompressor = std::unique_ptr<libdeflate_decompressor, DecompressorFree>;

struct CompressorFree {
  void operator()(libdeflate_compressor* c) const { libdeflate_free_compressor(c); }
};

bool isZlib(const std::uint8_t* p, std::size_t n) {
  return n >= 2 && (p[0] & 0x0f) == 8 && (p[0] >> 4) <= 7 && ((p[0] << 8) | p[1]) % 31 == 0;
}

std::uint32_t le32(const std::uint8_t* p) {
  return std::uint32_t(p[0]) | std::uint32_t(p[1]) << 8 | std::uint32_t(p[2]) << 16 | std::uint32_t(p[3]) << 24;
}

} // namespace

[[noreturn]] void tooLarge(const std::string& path, const std::string& what, std::size_t expect,
                           std::size_t limit) {
  std::string msg = path + ": " + what + " inflate to more than " + std::to_string(limit) + " bytes";
  if (expect > 0)
    msg += ", far beyond the " + std::to_string(expect) + " bytes the header declares: a deflate bomb or a "
           "corrupt file; refusing to inflate on";
  else
    msg += " (the most this file may hold): a deflate bomb or a corrupt file; refusing to inflate on";
  throw InputError(msg);
}

std::size_t maxInflatedSize(std::size_t n) {
  constexpr std::size_t kRatio = 1032, kSlack = 4096;
  return n > (std::numeric_limits<std::size_t>::max() - kSlack) / kRatio ? std::numeric_limits<std::size_t>::max()
                                                                        : n * kRatio + kSlack;
}

bool isGzip(const std::uint8_t* p, std::size_t n) {
  return n >= 2 && p[0] == 0x1f && p[1] == 0x8b;
}

InflateResult inflateGzipTo(const std::uint8_t* p, std::size_t n, std::size_t expect, std::size_t limit,
                            std::vector<std::uint8_t>& out) {
  InflateResult res;
  const bool gz = isGzip(p, n);
  if (!gz && !isZlib(p, n)) {
    res.status = InflateStatus::NotCompressed;
    return res;
  }
  res.limit = std::min(limit, maxInflatedSize(n));
  // The first buffer: the declared size, else the last member's ISIZE (the whole size of a one-member file
  // below 4 GiB), else a few times the input. Each is only a hint, bounded by the limit; the buffer grows
  // when the data need more.
  std::size_t hint = expect;
  if (hint == 0 && gz && n >= 18) hint = le32(p + n - 4);
  if (hint == 0) hint = std::min<std::size_t>(n, std::size_t(1) << 28) * 4;
  assignAdvised(out, std::max<std::size_t>(std::min(hint, res.limit), 1), std::uint8_t(0));
  Decompressor d(libdeflate_alloc_decompressor());
  if (!d) throw std::bad_alloc();
  std::size_t in = 0, done = 0;
  for (;;) {
    std::size_t used = 0, got = 0;
    const libdeflate_result r =
        gz ? libdeflate_gzip_decompress_ex(d.get(), p + in, n - in, out.data() + done, out.size() - done, &used,
                                           &got)
           : libdeflate_zlib_decompress_ex(d.get(), p + in, n - in, out.data() + done, out.size() - done, &used,
                                           &got);
    if (r == LIBDEFLATE_INSUFFICIENT_SPACE) {
      if (out.size() >= res.limit) {
        res.status = InflateStatus::TooLarge;
        return res;
      }
      // Inflate this member again into a larger buffer (libdeflate cannot resume).
      out.resize(out.size() > res.limit / 2 ? res.limit : std::max(out.size() * 2, std::size_t(1) << 16));
      continue;
    }
    if (r != LIBDEFLATE_SUCCESS) {
      res.status = InflateStatus::Corrupt;
      res.at = in;
      out.resize(done);
      return res;
    }
    in += used;
    done += got;
    ++res.members;
    if (!gz || in >= n || !isGzip(p + in, n - in)) break;
  }
  out.resize(done);
  return res;
}

std::vector<std::uint8_t> inflateGzip(const std::string& path, const std::uint8_t* p, std::size_t n,
                                      std::size_t expect, std::size_t limit, const std::string& what) {
  std::vector<std::uint8_t> out;
  const InflateResult r = inflateGzipTo(p, n, expect, limit, out);
  switch (r.status) {
  case InflateStatus::Ok:
    return out;
  case InflateStatus::NotCompressed:
    throw InputError(path + ": " + what + " are not gzip or zlib data");
  case InflateStatus::TooLarge:
    tooLarge(path, what, expect, r.limit);
  case InflateStatus::Corrupt:
    break;
  }
  throw InputError(path + ": corrupt or truncated gzip data in " + what + " (member " +
                   std::to_string(r.members + 1) + " at byte " + std::to_string(r.at) +
                   " does not inflate or fails its CRC-32/size check)");
}

bool inflateRawExact(const std::uint8_t* p, std::size_t n, std::uint8_t* out, std::size_t size) {
  Decompressor d(libdeflate_alloc_decompressor());
  if (!d) return false;
  std::uint8_t spare = 0;
  std::size_t used = 0, got = 0;
  const libdeflate_result r =
      libdeflate_deflate_decompress_ex(d.get(), p, n, size ? out : &spare, size, &used, &got);
  return r == LIBDEFLATE_SUCCESS && got == size && used <= n;
}

std::vector<std::uint8_t> gzipCompress(const std::uint8_t* p, std::size_t n, int level) {
  std::unique_ptr<libdeflate_compressor, CompressorFree> c(libdeflate_alloc_compressor(level));
  if (!c) throw std::bad_alloc();
  std::vector<std::uint8_t> out(libdeflate_gzip_compress_bound(c.get(), n));
  const std::size_t size = libdeflate_gzip_compress(c.get(), p, n, out.data(), out.size());
  if (size == 0) throw std::bad_alloc(); // cannot happen with the bound's buffer
  out.resize(size);
  return out;
}

} // namespace dtf::io::detail
