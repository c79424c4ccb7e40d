// SPDX-License-Identifier: GPL-3.0-or-later
#include "io/formats/mapped_tck.h"

#include "io/formats/atomic_file.h"
#include "io/model/error.h"
#include "io/model/huge_pages.h"
#include "io/model/log.h"

#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <thread>
#include <algorithm>

namespace dtf::io {

namespace {

// Checks the triplets and records where each line starts; returns whether an Inf triplet ended them and
// sets `used` to the triplets before it. Two or more workers scan equal parts; the first problem (in file
// order) is reported.
bool scanTriplets(const std::string& path, const glm::vec3* t, std::size_t n, std::vector<std::uint64_t>& starts,
                  std::size_t& used) {
  struct Part {
    std::vector<std::uint64_t> separators;
    std::size_t end = 0;     // the Inf triplet, or the part's end
    bool ended = false;
    std::size_t bad = 0;     // the first bad triplet
    int problem = 0;         // 1 partly non-finite, 2 absurd
  };
  const std::size_t workers = std::clamp<std::size_t>(std::thread::hardware_concurrency(), 1, 8);
  const std::size_t T = n < (1u << 20) ? 1 : workers;
  std::vector<Part> parts(T);
  auto scan = [&](std::size_t w) {
    Part& part = parts[w];
    const std::size_t b = n * w / T, e = n * (w + 1) / T;
    part.end = e;
    for (std::size_t k = b; k < e; ++k) {
      const glm::vec3 v = t[k];
      const int nans = std::isnan(v.x) + std::isnan(v.y) + std::isnan(v.z);
      if (nans == 3) {
        part.separators.push_back(k + 1);
        continue;
      }
      const int infs = std::isinf(v.x) + std::isinf(v.y) + std::isinf(v.z);
      if (infs == 3) {
        part.end = k;
        part.ended = true;
        return;
      }
      if (nans || infs || std::abs(v.x) > 1e7f || std::abs(v.y) > 1e7f || std::abs(v.z) > 1e7f) {
        part.bad = k;
        part.problem = nans || infs ? 1 : 2;
        return;
      }
    }
  };
  std::vector<std::thread> pool;
  for (std::size_t w = 1; w < T; ++w)
    pool.emplace_back(scan, w);
  scan(0);
  for (auto& th : pool)
    th.join();
  starts.clear();
  starts.push_back(0);
  for (const Part& part : parts) {
    if (part.problem)
      throw InputError(path + ": " + (part.problem == 1 ? "non-finite" : "absurd") + " coordinate in triplet " +
                       std::to_string(part.bad) + " of the .tck data");
    starts.insert(starts.end(), part.separators.begin(), part.separators.end());
    if (part.ended) {
      used = part.end;
      return true;
    }
  }
  used = n;
  return false;
}

} // namespace

MappedTck::MappedTck(const std::string& path) : path_(path) {
  if (const std::string why = notARegularFile(path); !why.empty())
    throw InputError(path + ": cannot read tract file: " + why);
  auto file = std::make_unique<MappedFile>(path, true);
  const std::string_view bytes = file->bytes();
  bool big = false;
  int width = 4;
  info_ = readTckHeader(path, bytes, big, width);
  // Float32LE on a little-endian host is used as it is; data at an offset not aligned to 4 bytes is first
  // copied into an aligned buffer (one copy, still without parsing); other datatypes are converted.
  const bool float32 = width == 4 && !big && std::endian::native == std::endian::little;
  if (!float32) {
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
  const char* data = bytes.data() + info_.dataOffset;
  if (reinterpret_cast<std::uintptr_t>(data) % alignof(glm::vec3) != 0) {
    assignAdvised(owned_, available / 12, glm::vec3(0.0f));
    std::memcpy(owned_.data(), data, owned_.size() * 12);
    points_ = owned_.data();
  } else {
    points_ = reinterpret_cast<const glm::vec3*>(data);
  }
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
  if (owned_.empty()) file_ = std::move(file); // else the copy holds the data and the mapping goes
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
  // Fixed-width digits, "\nEND\n", then spaces up to a multiple of 4 bytes, so readers can use the data in
  // place.
  const std::size_t offset = (head.size() + 10 + 5 + 3) / 4 * 4;
  char digits[24];
  std::snprintf(digits, sizeof digits, "%-10zu", offset);
  head += std::string(digits, 10) + "\nEND\n";
  head.resize(offset, ' ');

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
