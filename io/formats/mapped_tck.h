// SPDX-License-Identifier: GPL-3.0-or-later
// A .tck file read in place: the file is mapped into memory and its Float32LE triplets are used as the
// positions without a copy (what ROI selection of a whole-brain tractogram needs: the positions are most of
// its memory). Only the line starts are built, by one scan that also checks the data as readTck does. A file
// whose data cannot be used in place (Float32BE, Float64, an offset not aligned to 4 bytes) is read into
// memory instead, with the same interface.
#pragma once

#include "io/formats/tracts.h"
#include "io/formats/zip_archive.h"

#include <cstdint>
#include <glm/glm.hpp>
#include <memory>
#include <string>
#include <vector>

namespace dtf::io {

class MappedTck {
public:
  // Throws InputError naming the file, for the same problems as readTck.
  explicit MappedTck(const std::string& path);
  bool inPlace() const { return static_cast<bool>(file_); } // false: converted into memory

  const TckInfo& info() const { return info_; }
  // Triplets of the data (separator triplets included); line i is points()[starts()[i] .. starts()[i+1] - 1).
  const glm::vec3* points() const { return points_; }
  const std::vector<std::uint64_t>& starts() const { return starts_; } // lineCount() + 1 entries
  std::size_t lineCount() const { return starts_.empty() ? 0 : starts_.size() - 1; }

  // Writes the lines listed in `lines` (ascending) of each of `sources` to a Float32LE .tck atomically,
  // copying their bytes; the header carries the first source's fields (other than its datatype, file and
  // counts) as tckedit does. Throws InputError naming `path`.
  static void writeLines(const std::string& path, const std::vector<const MappedTck*>& sources,
                         const std::vector<const std::vector<std::uint32_t>*>& lines);

private:
  std::string path_;
  std::unique_ptr<MappedFile> file_;
  std::vector<glm::vec3> owned_; // when not in place: the triplets, separators included
  const glm::vec3* points_ = nullptr;
  std::vector<std::uint64_t> starts_;
  TckInfo info_;
};

} // namespace dtf::io
