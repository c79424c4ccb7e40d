// SPDX-License-Identifier: GPL-3.0-or-later
// A small ZIP reader and writer over zlib, enough for TRX tractograms: entries stored or deflated, ZIP64
// sizes and offsets, no encryption, no multi-disk archives. The reader memory-maps the archive, so a stored
// entry is a view into the mapping (no copy); a deflated entry is inflated into memory. The writer stores
// entries uncompressed so that readers can map them.
#pragma once

#include <cstddef>
#include <cstdint>
#include <fstream>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace dtf::io {

// A read-only memory mapping of a whole file. Throws InputError naming the file when it cannot be mapped.
class MappedFile {
public:
  // `populate`: the pages are mapped at once (MAP_POPULATE), for a file that is read whole: one system
  // call instead of a page fault per 4 KiB.
  explicit MappedFile(const std::string& path, bool populate = false);
  ~MappedFile();
  MappedFile(const MappedFile&) = delete;
  MappedFile& operator=(const MappedFile&) = delete;
  std::string_view bytes() const { return {data_, size_}; }

private:
  const char* data_ = nullptr;
  std::size_t size_ = 0;
};

class ZipReader {
public:
  struct Entry {
    std::string name;
    std::uint16_t method = 0; // 0 stored, 8 deflated
    std::uint32_t crc = 0;
    std::uint64_t compressedSize = 0, size = 0, dataOffset = 0;
  };
  // Maps `path` and reads its central directory. Throws InputError naming the file and the problem (no end
  // of central directory, entries outside the file, encrypted or multi-disk archives, bad local headers).
  explicit ZipReader(const std::string& path);
  const std::vector<Entry>& entries() const { return entries_; }
  // The entry's bytes: a view into the mapping when stored, else inflated into `storage`. The CRC-32 is
  // checked in both cases. Throws InputError on an unknown method, corrupt data or a CRC mismatch.
  std::string_view read(const Entry& e, std::string& storage) const;

private:
  std::string path_;
  MappedFile file_;
  std::vector<Entry> entries_;
};

// Writes a ZIP archive of stored entries to an open stream, each entry's data aligned to 64 bytes in the file
// (a padding extra field), so that a reader mapping the file can use its arrays in place. ZIP64 records (APPNOTE 4.5.3, read by Python's
// zipfile, libzip and trx-python) are written for the entries, offsets and counts past the classic limits,
// or for all of them with Zip64::Always (tests). Throws InputError (naming `path`) on a write failure.
class ZipWriter {
public:
  enum class Zip64 { AsNeeded, Always };
  ZipWriter(std::ofstream& out, std::string path, Zip64 zip64 = Zip64::AsNeeded)
      : out_(out), path_(std::move(path)), always64_(zip64 == Zip64::Always) {}
  void add(const std::string& name, const void* data, std::size_t size);
  void finish();

private:
  struct Central {
    std::string name;
    std::uint32_t crc;
    std::uint64_t size, offset;
    bool zip64; // the local header carries a ZIP64 extra field
  };
  std::ofstream& out_;
  std::string path_;
  bool always64_ = false;
  std::vector<Central> central_;
  std::uint64_t written_ = 0;
};

} // namespace dtf::io
