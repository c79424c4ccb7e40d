// SPDX-License-Identifier: GPL-3.0-or-later
// The self-contained web page of `dtfabric web`: the fabric of every axial, coronal and sagittal slice that
// holds data, rendered headless once per slice (one renderer, one camera per axis framing the whole grid), as
// PNG files, plus a per-voxel table (FA and principal direction as bytes) and the grid's affine for the hover
// probe, and index.html with its script. The folder opens from file:// with no server and no network: the
// data are JavaScript files loaded by <script src>, the slices images loaded by <img>.
//
// Folder layout: index.html, viewer.js (the page's code), data.js (window.DTF_WEB: grid, cameras, slices),
// voxels.js (window.DTF_WEB_VOXELS: base64 of 4 bytes per voxel), slices/AXIS_NNN.png and, with tracts,
// slices/AXIS_tracts_NNN.png. Written into a temporary sibling folder renamed into place at the end.
#pragma once

#include "ui/session/tensor_input.h"

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace dtf {
struct TensorField;
}

namespace dtf::session {

struct WebPageRequest {
  std::string input;                  // tensor file or DWI (fitted)
  const TensorField* field = nullptr; // when set: these tensors instead of loading `input` (which then only
                                      // names them)
  TensorInputOptions tensorOptions;   // layout, bval/bvec, mask
  std::string tracts;                 // tract file drawn as a second image set, or empty
  double tractsNearMm = 3.0;          // tract segments within this distance of the slice's plane
  std::string background;             // fa | md | FILE grey background, or empty
  int size = 256;                     // pixels of each image's longer side
  std::string output;                 // the folder
  bool force = false;                 // replace an existing folder
  std::string title;                  // heads the page; default: the input's file name
  // Called with progress lines ("axial 12/39"), from the calling thread.
  std::function<void(const std::string&)> onProgress;
};

struct WebPageResult {
  int slices[3] = {0, 0, 0}; // axial, coronal, sagittal slices rendered
  std::size_t images = 0;    // PNG files written
  std::uintmax_t bytes = 0;  // size of the folder
  double seconds = 0;        // wall time
};

// Loads, renders and writes the folder. Throws UsageError (bad size, existing folder without force, output
// equal to an input), InputError (unreadable input, no data), GlError (no context, GL failure).
WebPageResult writeWebPage(const WebPageRequest& request);

// The per-voxel probe table: 4 bytes per voxel in the grid's index order (i fastest). Byte 0: 0 where the
// voxel holds no tensor, else 1 + round(FA * 254); bytes 1-3: the principal eigenvector (world RAS, unit,
// sign chosen so its largest component is positive) as round(127 * v) + 128.
std::vector<std::uint8_t> webVoxelTable(const TensorField& field);

// RFC 4648 base64 with padding.
std::string base64Encode(const std::vector<std::uint8_t>& bytes);

// The page's static text (ui/session/web_page_text.cpp): index.html (title escaped into it) and viewer.js.
std::string webIndexHtml(const std::string& title);
const char* webViewerJs();

} // namespace dtf::session
