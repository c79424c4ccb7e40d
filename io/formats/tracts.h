// SPDX-License-Identifier: GPL-3.0-or-later
// Streamline files in and out: MRtrix .tck and TrackVis .trk. Tracts enter and leave
// the pipeline here as dtf::Polylines in world RAS millimetres, the same frame as TensorField and Mesh, so
// tracking output, comparison and rendering never see a file's own convention. Legacy VTK polylines are
// read and written in surfaces/polyline_io.h (io does not link VTK).
//
// .tck: text header starting "mrtrix tracks", ending "END", with `datatype: Float32LE|Float32BE|Float64LE|
//       Float64BE` and `file: . OFFSET`; from OFFSET on, xyz triplets in world RAS mm, a NaN triplet after
//       each streamline and an Inf triplet at the end of the file.
// .trk: TrackVis v1/v2, a 1000-byte little- or big-endian header, optionally gzip-compressed (.trk.gz).
//       Points are in "voxmm" space of the header's grid with the half-voxel corner convention: voxel
//       index = p / voxel_size - 0.5, then nibabel's orientation rules (see readTrk).
// All readers throw dtf::InputError whose message starts with the file name; counts are checked against
// the file size before anything is allocated.
#pragma once

#include "io/model/geometry.h"
#include "io/model/grid.h"

#include <string>
#include <string_view>
#include <vector>

namespace dtf::io {

// Facts from a .tck header (besides the points).
struct TckInfo {
  std::string datatype;                                    // e.g. "Float32LE"
  std::size_t dataOffset = 0;                              // byte offset of the first triplet
  long long declaredCount = -1;                            // `count:` (-1 when absent)
  std::vector<std::pair<std::string, std::string>> fields; // every "key: value" line, in order
};

// Reads a .tck file into world RAS mm. Throws InputError (bad magic, missing END/datatype/file, bad offset,
// unsupported datatype, partial triplet, coordinates that are partly NaN/Inf, a missing end marker).
// A `count:` that disagrees with the streamlines found is logged as a warning (tckgen leaves 0 there when
// interrupted, MATLAB writers leave stale counts), as is data that ends after a NaN triplet without the Inf
// end marker: the file is read to the end of its data, as nibabel does.
Polylines readTck(const std::string& path, TckInfo* info = nullptr);
// The header of a .tck file whose bytes (the whole file, e.g. a mapping) are `bytes`: its fields, datatype
// and data offset, with the byte order and bytes per coordinate. Throws InputError as readTck.
TckInfo readTckHeader(const std::string& path, std::string_view bytes, bool& bigEndian, int& width);
// Writes Float32LE .tck atomically (per-streamline/per-point data and groups are dropped with a warning).
// Throws InputError when the file cannot be written or a point is not finite.
void writeTck(const std::string& path, const Polylines& lines);

// Facts from a .trk header.
struct TrkInfo {
  int version = 0;
  bool bigEndian = false;
  bool gzipped = false;
  glm::ivec3 dims{0};
  glm::dvec3 voxelSize{0.0};
  glm::dvec3 origin{0.0};
  std::string voxelOrder;       // as stored, or "LPS" when the header has none
  glm::dmat4 voxToRas{0.0};     // as stored (all zero when not recorded)
  glm::dmat4 voxToRasUsed{1.0}; // the stored one, or the identity when not recorded
  bool voxToRasRecorded = true;
  std::string affineOrder;      // axis codes of voxToRasUsed
  glm::dmat4 indexToWorld{1.0}; // stored-order voxel index -> world RAS mm, all rules applied
  int nScalars = 0, nProperties = 0;
  long long declaredCount = 0; // n_count (0 = unknown)
};

// Reads a .trk file, plain or gzip-compressed (v1 or v2, either byte order), into world RAS mm as nibabel
// does: points in voxel-mm of the stored voxel_order (corner of voxel 0 at 0), flipped within the
// dimensions to the orientation of vox_to_ras when voxel_order differs from it, then through vox_to_ras
// (the identity when not recorded, with a warning; a missing voxel_order is LPS). Per-point scalars become
// per-point data and per-track properties per-streamline data, named from the header. Throws InputError
// (bad magic, header size or version, absurd dims/voxel size/counts, truncated or corrupt data, non-finite
// coordinates, a singular affine).
Polylines readTrk(const std::string& path, TrkInfo* info = nullptr);
// The affine from a file's voxel-mm coordinates to world RAS mm that readTrk applied.
glm::dmat4 trkVoxmmToWorldOf(const TrkInfo& info);
// Writes a little-endian TrackVis v2 file atomically on `reference`'s grid: dim, voxel_size = its
// spacing, vox_to_ras = its voxelToWorld, voxel_order = its orientation code; gzip-compressed when the
// name ends in .gz. Per-point data go to scalars, per-streamline data to properties (what does not fit
// the header is dropped with a warning, as are groups). Throws InputError.
void writeTrk(const std::string& path, const Polylines& lines, const Grid& reference);

} // namespace dtf::io
