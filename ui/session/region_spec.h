// SPDX-License-Identifier: GPL-3.0-or-later
// Regions of interest as users write them, for `dtfabric select`, `profile --start`, targeted `track`, the
// Python module and the viewer's region lines: a SPEC on the command line, and the region set file (JSON)
// that the viewer saves and `select --roi` reads. They become surfaces::Region values (world RAS mm; masks
// resolved to their voxels), which surfaces/selection tests.
//
// SPEC forms:
//   X,Y,Z,R                  a sphere, centre and radius in world RAS mm (as tckedit takes it)
//   box:X0,Y0,Z0,X1,Y1,Z1    an axis-aligned box between two corners, world RAS mm
//   IMAGE                    the non-zero voxels of a mask in any image format dtfabric reads, on any grid
//   IMAGE:L[,L...]           the voxels of a parcellation (an atlas, a FreeSurfer segmentation in the
//                            subject's space) whose value is one of the integer labels L
//
// The region set file, version 1 (world RAS mm; image paths relative to the file's folder, or absolute):
//   {"format": "dtfabric-regions", "version": 1, "ends_only": false, "precise": false,
//    "regions": [
//      {"name": "M1", "kind": "include", "shape": "sphere", "centre": [x, y, z], "radius": r},
//      {"kind": "exclude", "shape": "box", "min": [x0, y0, z0], "max": [x1, y1, z1]},
//      {"kind": "include-ordered", "shape": "mask", "image": "aparc+aseg.nii.gz", "labels": [1024]}]}
// "kind" is include, exclude or include-ordered; "name" (default: the region's SPEC) and "visible" (default
// true, for the viewer) are optional; "labels" is optional for masks. Readers refuse another format or version
// and any member they do not know, naming the file and the member.
#pragma once

#include "surfaces/selection/regions.h"

#include <string>

namespace dtf::session {

// A region from its SPEC. Throws InputError naming the SPEC (and the file) for a malformed spec, an image
// that cannot be read, a label the image does not hold, or a region that validate() refuses.
surfaces::Region parseRegionSpec(const std::string& spec,
                                 surfaces::RegionKind kind = surfaces::RegionKind::Include);
// The SPEC that parseRegionSpec reads back to the same region (numbers with round-trip precision).
std::string regionSpecOf(const surfaces::Region& region);

// Reads a region set file. Throws InputError naming the file and what is wrong.
surfaces::RegionSet readRegionSetFile(const std::string& path);
// The file's text for a set. Mask images are written relative to `folder` (the file's folder) when given,
// so a set saved beside its images stays movable; as held otherwise.
std::string regionSetText(const surfaces::RegionSet& set, const std::string& folder = "");
// Writes the set atomically (mask images relative to the file's folder). Throws InputError when it cannot be
// written.
void writeRegionSetFile(const std::string& path, const surfaces::RegionSet& set);
// Parses a region set from text; `origin` names it in errors and `folder` resolves relative image paths.
surfaces::RegionSet parseRegionSet(const std::string& text, const std::string& origin, const std::string& folder);

} // namespace dtf::session
