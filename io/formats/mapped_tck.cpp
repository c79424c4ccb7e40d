// SPDX-License-Identifier: GPL-3.0-or-later
#include "io/formats/mapped_tck.h"

#include "io/formats/atomic_file.h"
#include "io/model/error.h"
#include "io/model/log.h"

#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>

namespace dtf::io {

namespace {

// Checks the triplets and records where each line starts; returns whether an Inf triplet ended them and
// sets `used` to the triplets before it.
bool scanTriplets(const std::string& path, const glm::vec3* t, std::size_t n, std::vector<std::uint64_t>& starts,
                  std::size_t& used) {
  starts.clear();
  starts.push_back(0);
  for (std::size_t k = 0; k < n; ++k) {
    const glm::vec3 v = t[k];
    const int nans = std::isnan(v.x) + std::isnan(v.y) + std::isnan(v.z);
    if (nans == 3) {
      starts.push_back(k + 1);
      continue;
    }
    const int infs = std::isinf(v.x) + std::isinf(v.y) + std::isinf(v.z);
    if (infs == 3) {
      used = k;
      return true;
    }
    if (nans || infs)
      throw InputError(path + ": non-finite coordinate in triplet " + std::to_string(k) + " of the .tck data");
    if (std::abs(v.x) > 1e7f || std::abs(v.y) > 1e7f || std::abs(v.z) > 1e7f)
      throw InputError(path + ": absurd coordinate in triplet " + std::to_string(k) + " of the .tck data");
  }
  used = n;
  return false;
}

} // namespace

MappedTck::MappedTck(const std::string& path) : path_(path) {
  if (const std::string why = notARegularFile(path); !why.empty())
    throw InputError(path + ": cannot read tract file: " + why);
  auto file = std::make_unique<MappedFile>(path);
  const std::string_view bytes = file->bytes();
  bool big = false;
  int width = 4;
  info_ = readTckHeader(path, bytes, big, width);
  const bool usable = width == 4 && !big && std::endian::native == std::endian::little &&
                      info_.dataOffset % alignof(float) == 0 &&
                      reinterpret_cast<std::uintptr_t>(bytes.data()) % alignof(float) == 0;
  if (!usable) {
    // Converted by the reader that handles every datatype; separators restored so the layout is the same.
    const Polylines lines = readTck(path);
    owned_.reserve(lines.points.size() + lines.lineCount());
    starts_.push_back(0);
    for (std::size_t l = 0; l < lines.lineCount(); ++l) {
      owned_.insert(owned_.end(), lines.points.begin() + lines.offsets[l], lines.points.begin() + lines.offsets[l + 1]);
      owned_.push_back(glm::vec3(std::numeric_limits<float>::quiet_NaN()));
      starts_.push_back(owned_.size());
    }
    points_ = owned_.data();
    return;
  }
  const std::size_t available = bytes.size() - info_.dataOffset;
  points_ = reinterpret_cast<const glm::vec3*>(bytes.data() + info_.dataOffset);
  static_assert(sizeof(glm::vec3) == 12, "glm::vec3 must be three packed floats");
  std::size_t used = 0;
  const bool terminated = scanTriplets(path, points_, available / 12, starts_, used);
  const std::size_t lines = starts_.size() - 1;
  if (!terminated) {
    if (available % 12 != 0)
      throw InputError(path + ": truncated .tck data (ends inside a triplet after " + std::to_string(lines) +
                       " streamlines)");
    if (starts_.back() != used)
      throw InputError(path + ": truncated .tck data (no end-of-file marker and the last streamline has no NaN "
                              "separator, after " + std::to_string(lines) + " streamlines)");
    logWarning(path + ": .tck data has no Inf end marker; read to the end of the file");
  }
  if (starts_.back() != used)
    throw InputError(path + ": truncated .tck data (the last streamline has no NaN separator)");
  if (info_.declaredCount >= 0 && static_cast<std::size_t>(info_.declaredCount) != lines)
    logWarning(path + ": header count " + std::to_string(info_.declaredCount) + " but " + std::to_string(lines) +
               " streamlines in the file (stale count; read to the end)");
  file_ = std::move(file);
}

void MappedTck::writeLines(const std::string& path, const std::vector<const MappedTck*>& sources,
                           const std::vector<const std::vector<std::uint32_t>*>& lines) {
  std::size_t count = 0;
  for (const auto* l : lines)
    count += l->size();
  std::string head = "mrtrix tracks\n";
  if (!sources.empty())
    for (const auto& [k, v] : sources.front()->info().fields)
      if (k != "datatype" && k != "file" && k != "count" && k != "total_count")
        head += k + ": " + v + "\n";
  head += "datatype: Float32LE\ncount: " + std::to_string(count) + "\ntotal_count: " + std::to_string(count) +
          "\nfile: . ";
  const std::size_t offset = head.size() + 10 + 5; // fixed-width digits + "\nEND\n"
  char digits[16];
  std::snprintf(digits, sizeof digits, "%-10zu", offset);
  head += std::string(digits, 10) + "\nEND\n";

  AtomicOutput out(path);
  {
    std::ofstream f(out.tempPath(), std::ios::binary);
    if (!f) throw InputError(path + ": cannot write the tract file");
    f.write(head.data(), static_cast<std::streamsize>(head.size()));
    for (std::size_t s = 0; s < sources.size(); ++s) {
      const MappedTck& src = *sources[s];
      const auto& ids = *lines[s];
      // Consecutive selected lines are contiguous in the source: write them in one piece.
      for (std::size_t k = 0; k < ids.size();) {
        std::size_t e = k + 1;
        while (e < ids.size() && ids[e] == ids[e - 1] + 1)
          ++e;
        const std::uint64_t from = src.starts_[ids[k]], to = src.starts_[ids[e - 1] + 1];
        f.write(reinterpret_cast<const char*>(src.points_ + from), static_cast<std::streamsize>((to - from) * 12));
        k = e;
      }
    }
    const float inf[3] = {std::numeric_limits<float>::infinity(), std::numeric_limits<float>::infinity(),
                          std::numeric_limits<float>::infinity()};
    f.write(reinterpret_cast<const char*>(inf), sizeof inf);
    if (!f.flush()) throw InputError(path + ": cannot write the tract file (disk full?)");
  }
  out.commit();
}

} // namespace dtf::io
