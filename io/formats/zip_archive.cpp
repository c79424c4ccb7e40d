// SPDX-License-Identifier: GPL-3.0-or-later
#include "io/formats/zip_archive.h"

#include "io/formats/gzip.h"
#include "io/model/error.h"

#include <algorithm>
#include <cstring>
#include <fcntl.h>
#include <limits>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

namespace dtf::io {

namespace {

std::uint64_t le(const char* p, int bytes) {
  std::uint64_t v = 0;
  for (int i = bytes - 1; i >= 0; --i)
    v = (v << 8) | static_cast<unsigned char>(p[i]);
  return v;
}

void putLe(std::string& out, std::uint64_t v, int bytes) {
  for (int i = 0; i < bytes; ++i)
    out.push_back(static_cast<char>((v >> (8 * i)) & 0xff));
}

std::uint32_t crcOf(const char* data, std::size_t size) {
  uLong crc = crc32(0L, Z_NULL, 0);
  while (size > 0) {
    const uInt chunk = static_cast<uInt>(std::min<std::size_t>(size, 1u << 30));
    crc = crc32(crc, reinterpret_cast<const Bytef*>(data), chunk);
    data += chunk;
    size -= chunk;
  }
  return static_cast<std::uint32_t>(crc);
}

constexpr std::uint64_t kDataAlignment = 64; // where stored entries' data begin (bytes)
constexpr std::uint32_t kLocalSig = 0x04034b50, kCentralSig = 0x02014b50, kEndSig = 0x06054b50,
                        kEnd64Sig = 0x06064b50, kLocator64Sig = 0x07064b50;

} // namespace

MappedFile::MappedFile(const std::string& path, bool populate) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throw InputError(path + ": cannot open: " + std::strerror(errno));
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd);
    throw InputError(path + ": not a regular file");
  }
  size_ = static_cast<std::size_t>(st.st_size);
  if (size_ > 0) {
    void* p = ::mmap(nullptr, size_, PROT_READ, MAP_PRIVATE | (populate ? MAP_POPULATE : 0), fd, 0);
    if (p == MAP_FAILED) {
      ::close(fd);
      throw InputError(path + ": cannot map the file: " + std::strerror(errno));
    }
    data_ = static_cast<const char*>(p);
  }
  ::close(fd);
}

MappedFile::~MappedFile() {
  if (data_) ::munmap(const_cast<char*>(data_), size_);
}

ZipReader::ZipReader(const std::string& path) : path_(path), file_(path) {
  const std::string_view f = file_.bytes();
  const std::size_t n = f.size();
  auto bad = [&](const std::string& why) { return InputError(path + ": not a valid zip archive: " + why); };
  if (n < 22) throw bad("too short for an end-of-central-directory record");
  // The end record sits in the last 22 + 65535 bytes (its comment is at most 65535 bytes).
  std::size_t end = std::string_view::npos;
  for (std::size_t p = n - 22 + 1; p-- > (n > 22 + 65535 ? n - 22 - 65535 : 0);) {
    if (le(f.data() + p, 4) == kEndSig && p + 22 + le(f.data() + p + 20, 2) == n) {
      end = p;
      break;
    }
  }
  if (end == std::string_view::npos) throw bad("no end-of-central-directory record");
  const char* e = f.data() + end;
  if (le(e + 4, 2) != 0 || le(e + 6, 2) != 0) throw bad("multi-disk archives are not supported");
  std::uint64_t count = le(e + 10, 2), cdSize = le(e + 12, 4), cdOffset = le(e + 16, 4);
  if (count == 0xffff || cdSize == 0xffffffffu || cdOffset == 0xffffffffu) {
    if (end < 20 || le(f.data() + end - 20, 4) != kLocator64Sig) throw bad("ZIP64 locator missing");
    const std::uint64_t at = le(f.data() + end - 20 + 8, 8);
    if (n < 56 || at > n - 56 || le(f.data() + at, 4) != kEnd64Sig) throw bad("bad ZIP64 end record");
    count = le(f.data() + at + 32, 8);
    cdSize = le(f.data() + at + 40, 8);
    cdOffset = le(f.data() + at + 48, 8);
  }
  if (cdOffset > n || cdSize > n - cdOffset) throw bad("central directory lies outside the file");
  if (count > cdSize / 46) throw bad("entry count " + std::to_string(count) + " does not fit the directory");
  entries_.reserve(static_cast<std::size_t>(count));
  std::uint64_t p = cdOffset;
  for (std::uint64_t i = 0; i < count; ++i) {
    if (p + 46 > cdOffset + cdSize || le(f.data() + p, 4) != kCentralSig)
      throw bad("bad central directory entry " + std::to_string(i));
    const char* c = f.data() + p;
    const std::uint64_t nameLen = le(c + 28, 2), extraLen = le(c + 30, 2), commentLen = le(c + 32, 2);
    if (p + 46 + nameLen + extraLen + commentLen > cdOffset + cdSize)
      throw bad("central directory entry " + std::to_string(i) + " runs past the directory");
    Entry en;
    en.name.assign(c + 46, nameLen);
    const std::uint64_t flags = le(c + 8, 2);
    if (flags & 1) throw bad("entry '" + en.name + "' is encrypted");
    en.method = static_cast<std::uint16_t>(le(c + 10, 2));
    en.crc = static_cast<std::uint32_t>(le(c + 16, 4));
    en.compressedSize = le(c + 20, 4);
    en.size = le(c + 24, 4);
    std::uint64_t local = le(c + 42, 4);
    // ZIP64 extra field: the 0xffffffff fields, in order size, compressed size, offset.
    const char* x = c + 46 + nameLen;
    for (std::uint64_t k = 0; k + 4 <= extraLen;) {
      const std::uint64_t id = le(x + k, 2), len = le(x + k + 2, 2);
      if (k + 4 + len > extraLen) break;
      if (id == 1) {
        std::uint64_t q = k + 4;
        auto take = [&](std::uint64_t& v) {
          if (v != 0xffffffffu) return;
          if (q + 8 > k + 4 + len) throw bad("short ZIP64 field in entry '" + en.name + "'");
          v = le(x + q, 8);
          q += 8;
        };
        take(en.size);
        take(en.compressedSize);
        take(local);
      }
      k += 4 + len;
    }
    if (local > n || n - local < 30 || le(f.data() + local, 4) != kLocalSig)
      throw bad("entry '" + en.name + "' has no local header");
    const std::uint64_t dataAt = local + 30 + le(f.data() + local + 26, 2) + le(f.data() + local + 28, 2);
    if (dataAt > n || en.compressedSize > n - dataAt) throw bad("entry '" + en.name + "' runs past the file");
    en.dataOffset = dataAt;
    if (en.method == 0 && en.compressedSize != en.size)
      throw bad("stored entry '" + en.name + "' has different stored and real sizes");
    entries_.push_back(std::move(en));
    p += 46 + nameLen + extraLen + commentLen;
  }
}

std::string_view ZipReader::read(const Entry& e, std::string& storage) const {
  const char* src = file_.bytes().data() + e.dataOffset;
  std::string_view out;
  if (e.method == 0) {
    out = std::string_view(src, static_cast<std::size_t>(e.size));
  } else if (e.method == 8) {
    // Deflate expands at most about 1032:1; a larger claim is corrupt (and must not be allocated).
    if (e.size > e.compressedSize * 1032 + 1024)
      throw InputError(path_ + ": zip entry '" + e.name + "' claims " + std::to_string(e.size) + " bytes from " +
                       std::to_string(e.compressedSize) + " compressed (corrupt archive)");
    // A deflate bomb: beyond 256 MiB, more than 100-fold (tract coordinates compress a few-fold at most).
    if (e.size > (std::uint64_t(256) << 20) && e.size / 100 > e.compressedSize)
      throw InputError(path_ + ": zip entry '" + e.name + "' inflates to " + std::to_string(e.size) +
                       " bytes from " + std::to_string(e.compressedSize) +
                       " (over 100 times its size: a deflate bomb or a corrupt archive; refused)");
    // One call into a buffer of the declared size (libdeflate): a stream that gives more or fewer bytes, or
    // runs past the entry's compressed bytes, is refused.
    storage.resize(static_cast<std::size_t>(e.size));
    if (!detail::inflateRawExact(reinterpret_cast<const std::uint8_t*>(src), static_cast<std::size_t>(e.compressedSize),
                         reinterpret_cast<std::uint8_t*>(storage.data()), storage.size()))
      throw InputError(path_ + ": zip entry '" + e.name + "' has corrupt deflate data or the wrong size");
    out = storage;
  } else {
    throw InputError(path_ + ": zip entry '" + e.name + "' uses compression method " +
                     std::to_string(e.method) + " (only stored and deflated are supported)");
  }
  if (crcOf(out.data(), out.size()) != e.crc)
    throw InputError(path_ + ": zip entry '" + e.name + "' fails its CRC-32 check (corrupt archive)");
  return out;
}

void ZipWriter::add(const std::string& name, const void* data, std::size_t size) {
  if (name.size() > 0xffff) throw InputError("cannot write " + path_ + ": zip entry name too long");
  constexpr std::uint64_t kMax32 = 0xffffffffu;
  const bool zip64 = always64_ || size >= kMax32 || written_ >= kMax32;
  const std::uint32_t crc = crcOf(static_cast<const char*>(data), size);
  std::string h;
  putLe(h, kLocalSig, 4);
  putLe(h, zip64 ? 45 : 20, 2); // version needed
  putLe(h, 0, 2);               // flags
  putLe(h, 0, 2);               // stored
  putLe(h, 0, 2);               // time
  putLe(h, (1 << 5) | 1, 2);    // date 1980-01-01
  putLe(h, crc, 4);
  putLe(h, zip64 ? kMax32 : size, 4);
  putLe(h, zip64 ? kMax32 : size, 4);
  // The data start on a multiple of kDataAlignment bytes, so readers can use a mapped array in place: a
  // padding extra field (zipalign's id 0xd935: the alignment, then zeros) fills the gap.
  const std::uint64_t before = written_ + 30 + name.size() + (zip64 ? 20 : 0) + 6;
  const std::uint64_t zeros = (kDataAlignment - before % kDataAlignment) % kDataAlignment;
  putLe(h, name.size(), 2);
  putLe(h, (zip64 ? 20 : 0) + 6 + zeros, 2);
  h += name;
  if (zip64) { // the local ZIP64 extra field holds both sizes
    putLe(h, 1, 2);
    putLe(h, 16, 2);
    putLe(h, size, 8);
    putLe(h, size, 8);
  }
  putLe(h, 0xd935, 2);
  putLe(h, 2 + zeros, 2);
  putLe(h, kDataAlignment, 2);
  h.append(zeros, '\0');
  central_.push_back({name, crc, size, written_, zip64});
  out_.write(h.data(), static_cast<std::streamsize>(h.size()));
  if (size) out_.write(static_cast<const char*>(data), static_cast<std::streamsize>(size));
  written_ += h.size() + size;
  if (!out_) throw InputError("cannot write " + path_ + ": write failed (disk full?)");
}

void ZipWriter::finish() {
  constexpr std::uint64_t kMax32 = 0xffffffffu;
  std::string cd;
  for (const auto& c : central_) {
    // The fields past 32 bits (or every one under Always) move to the ZIP64 extra field, in the order
    // size, compressed size, offset.
    const bool bigSize = always64_ || c.size >= kMax32, bigOffset = always64_ || c.offset >= kMax32;
    std::string extra;
    if (bigSize) putLe(extra, c.size, 8), putLe(extra, c.size, 8);
    if (bigOffset) putLe(extra, c.offset, 8);
    const bool zip64 = !extra.empty() || c.zip64;
    putLe(cd, kCentralSig, 4);
    putLe(cd, zip64 ? 45 : 20, 2); // version made by
    putLe(cd, zip64 ? 45 : 20, 2); // version needed
    putLe(cd, 0, 2);
    putLe(cd, 0, 2);
    putLe(cd, 0, 2);
    putLe(cd, (1 << 5) | 1, 2);
    putLe(cd, c.crc, 4);
    putLe(cd, bigSize ? kMax32 : c.size, 4);
    putLe(cd, bigSize ? kMax32 : c.size, 4);
    putLe(cd, c.name.size(), 2);
    putLe(cd, extra.empty() ? 0 : extra.size() + 4, 2); // extra
    putLe(cd, 0, 2);                                    // comment
    putLe(cd, 0, 2);                                    // disk
    putLe(cd, 0, 2);                                    // internal attributes
    putLe(cd, 0, 4);                                    // external attributes
    putLe(cd, bigOffset ? kMax32 : c.offset, 4);
    cd += c.name;
    if (!extra.empty()) {
      putLe(cd, 1, 2);
      putLe(cd, extra.size(), 2);
      cd += extra;
    }
  }
  const std::uint64_t cdOffset = written_, count = central_.size();
  const bool zip64 = always64_ || count >= 0xffff || cdOffset >= kMax32 || cd.size() >= kMax32;
  std::string end;
  if (zip64) {
    const std::uint64_t end64At = cdOffset + cd.size();
    putLe(end, kEnd64Sig, 4);
    putLe(end, 44, 8); // size of the record after this field
    putLe(end, 45, 2);
    putLe(end, 45, 2);
    putLe(end, 0, 4); // this disk
    putLe(end, 0, 4); // the directory's disk
    putLe(end, count, 8);
    putLe(end, count, 8);
    putLe(end, cd.size(), 8);
    putLe(end, cdOffset, 8);
    putLe(end, kLocator64Sig, 4);
    putLe(end, 0, 4);
    putLe(end, end64At, 8);
    putLe(end, 1, 4); // disks
  }
  putLe(end, kEndSig, 4);
  putLe(end, 0, 2);
  putLe(end, 0, 2);
  putLe(end, zip64 ? 0xffff : count, 2);
  putLe(end, zip64 ? 0xffff : count, 2);
  putLe(end, zip64 ? kMax32 : cd.size(), 4);
  putLe(end, zip64 ? kMax32 : cdOffset, 4);
  putLe(end, 0, 2);
  out_.write(cd.data(), static_cast<std::streamsize>(cd.size()));
  out_.write(end.data(), static_cast<std::streamsize>(end.size()));
  out_.flush();
  if (!out_) throw InputError("cannot write " + path_ + ": write failed (disk full?)");
}

} // namespace dtf::io
