// SPDX-License-Identifier: GPL-3.0-or-later
// TRX tractograms (the tee-ar-ex format): a zip archive, or an unzipped folder, of little-endian typed
// arrays named `<name>[.<components>].<dtype>`:
//   header.json            VOXEL_TO_RASMM (4x4, row-major), DIMENSIONS, NB_STREAMLINES, NB_VERTICES
//   positions.3.<float16|float32|float64>   NB_VERTICES points, already in world RAS mm
//   offsets.<uint32|uint64>                 start of each streamline, with or without the end entry
//   dps/<name>.[n.]<dtype>, dpv/<name>.[n.]<dtype>   per-streamline / per-vertex data
//   groups/<name>.<integer dtype>           indices of the streamlines of each group
// Stored zip entries and folder files are memory-mapped and read in place; deflated entries are inflated.
// Data of any numeric dtype become float per-streamline/per-point data; data per group (dpg/) are skipped
// with a warning.
#pragma once

#include "io/model/geometry.h"
#include "io/model/grid.h"

#include <string>
#include <vector>

namespace dtf::io {

struct TrxInfo {
  bool folder = false;      // an unzipped folder rather than a zip archive
  glm::dmat4 voxToRas{1.0}; // VOXEL_TO_RASMM
  glm::ivec3 dims{0};       // DIMENSIONS
  long long nbStreamlines = 0, nbVertices = 0;
  std::string positionsDtype, offsetsDtype;
  bool offsetsHaveEnd = false;      // the offsets array holds NB_STREAMLINES + 1 entries
  int deflatedEntries = 0;          // zip entries that had to be inflated (the rest were mapped in place)
  std::vector<std::string> skipped; // entries not read (dpg/, unknown names)
};

// Reads a .trx archive or folder. Throws InputError naming the file and the reason: a bad zip, a missing
// or malformed header.json, positions or offsets missing, sizes that do not match the header, offsets
// that are not increasing or exceed NB_VERTICES, unknown dtypes, group indices out of range, entry paths
// escaping the folder, non-finite coordinates.
Polylines readTrx(const std::string& path, TrxInfo* info = nullptr);

// Writes a zip TRX (entries stored, so readers can map them) atomically: positions.3.float32, offsets.uint32
// with the end entry, dps/dpv float32, groups uint32, and a header from
// `reference` (VOXEL_TO_RASMM = its voxelToWorld, DIMENSIONS = its dims). Throws InputError.
void writeTrx(const std::string& path, const Polylines& lines, const Grid& reference);

} // namespace dtf::io
