// SPDX-License-Identifier: GPL-3.0-or-later
// Internal to dtf_io: whole-buffer gzip, zlib and raw-deflate inflation through libdeflate for the readers
// (.nii.gz, .mif.gz, .trk.gz, NRRD gzip encoding, zip entries) and gzip compression for the writers.
// libdeflate has no streaming interface, so a stream is inflated whole into a buffer sized from what the
// caller's header declares (or the gzip ISIZE trailer as a hint, never trusted for allocation), never beyond
// `limit` bytes: a small file that inflates to far more than its header implies (a deflate bomb) is refused
// before it can exhaust memory. Short reads of the first bytes (format detection) stay with zlib's streams.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace dtf::io::detail {

// Deflate expands at most 1032:1 (a 258-byte match in two bits); more output than this from `n` input
// bytes is impossible, so a header declaring more describes a truncated or corrupt file.
std::size_t maxInflatedSize(std::size_t n);

// The output limit for data whose header declares `declared` bytes: a little room above it (trailing bytes
// some writers add), far below what a deflate bomb inflates to.
inline std::size_t inflateLimit(std::size_t declared) {
  return declared + std::max<std::size_t>(declared / 8, std::size_t(1) << 20);
}

// True when `p` starts with the gzip magic bytes 1f 8b.
bool isGzip(const std::uint8_t* p, std::size_t n);

// Inflates the gzip data p[0..n): every member of a multi-member file (as `cat a.gz b.gz`, pigz and bgzip
// write them), each checked against its CRC-32 and ISIZE; bytes after the last member that do not start a
// new member are ignored, as gzip does. Data in zlib format (78 xx) are inflated too. `expect` (0 when
// unknown) is the size the caller's header declares and sizes the buffer; the output may not exceed
// `limit` bytes. `what` names the data in messages ("the voxel data"). Throws InputError starting with
// `path`: corrupt or truncated data ("corrupt or truncated gzip data"), or output beyond `limit`
// ("inflate to more than ...").
std::vector<std::uint8_t> inflateGzip(const std::string& path, const std::uint8_t* p, std::size_t n,
                                      std::size_t expect, std::size_t limit,
                                      const std::string& what = "the gzip data");

// The same without throwing: the output in `out`, the status, for Corrupt the member and byte where it failed.
enum class InflateStatus { Ok, NotCompressed, Corrupt, TooLarge };
struct InflateResult {
  InflateStatus status = InflateStatus::Ok;
  std::size_t members = 0; // members inflated whole
  std::size_t at = 0;      // Corrupt: the input byte where the failing member starts
  std::size_t limit = 0;   // the output limit applied (also bounded by maxInflatedSize)
};
InflateResult inflateGzipTo(const std::uint8_t* p, std::size_t n, std::size_t expect, std::size_t limit,
                            std::vector<std::uint8_t>& out);
// The InputError of a stream that inflated beyond `limit`, naming `path` and the declared size `expect`.
[[noreturn]] void tooLarge(const std::string& path, const std::string& what, std::size_t expect, std::size_t limit);

// Inflates raw deflate data p[0..n) that must give exactly `size` bytes into `out` (a zip entry).
// Returns false for corrupt data, a stream that gives more or fewer bytes or does not end within n bytes.
bool inflateRawExact(const std::uint8_t* p, std::size_t n, std::uint8_t* out, std::size_t size);

// A single-member gzip file of `bytes` (libdeflate level 6).
std::vector<std::uint8_t> gzipCompress(const std::uint8_t* p, std::size_t n, int level = 6);

} // namespace dtf::io::detail
