// SPDX-License-Identifier: GPL-3.0-or-later
// The self-contained web page of `dtfabric web`: the fabric of every axial, coronal and sagittal slice that
// holds data in the render's default look (one headless session, one camera per axis framing the whole grid),
// a 3D view of an FA isosurface as frames around it (the movie's carried advection state, one image per
// azimuth and elevation) and an FA-threshold sweep of the isosurface, as PNG files, plus a per-voxel table
// (FA and principal direction as bytes) and the grid's affine for the hover probe, and index.html with its
// script. The folder opens from file:// with no server and no network: the data are JavaScript files loaded
// by <script src>, the images loaded by <img>.
//
// Folder layout: index.html, viewer.js (the page's code), data.js (window.DTF_WEB: grid, cameras, slices, the
// 3D view's and the sweep's frames), voxels.js (window.DTF_WEB_VOXELS: base64 of 4 bytes per voxel),
// slices/AXIS_NNN.png and, with tracts, slices/AXIS_tracts_NNN.png; 3d/view_EE_AAA.png (elevation EE,
// azimuth AAA) and fa/fa_NN.png, unless slices only. Written into a temporary sibling folder renamed into
// place at the end.
#pragma once

#include "render/camera.h"
#include "ui/session/tensor_input.h"

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace dtf {
struct TensorField;
struct Grid;
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
  int size = 512;                     // pixels of each image's longer side
  std::string surface = "fa=0.25";    // the 3D view's surface (a surface spec)
  bool slicesOnly = false;            // the slices alone: no 3D view, no FA sweep
  int azimuths = 36;                  // the 3D view's frames per turn
  std::vector<double> elevationsDeg{-15, 20, 55}; // the 3D view's camera heights above the horizontal plane
  int faSteps = 10;                   // the FA sweep's thresholds, from faLo to faHi
  double faLo = 0.15, faHi = 0.6;
  std::string output;                 // the folder
  bool force = false;                 // replace an existing folder
  std::string title;                  // heads the page; default: the input's file name
  // Called with progress lines ("axial 12/39"), from the calling thread.
  std::function<void(const std::string&)> onProgress;
};

struct WebPageResult {
  int slices[3] = {0, 0, 0}; // axial, coronal, sagittal slices rendered
  int frames3d = 0;          // the 3D view's frames
  int faFrames = 0;          // the FA sweep's frames
  std::size_t images = 0;    // PNG files written
  std::uintmax_t bytes = 0;  // size of the folder
  double seconds = 0;        // wall time
};

// Loads, renders and writes the folder. Throws UsageError (bad size, frame count or surface, existing folder
// without force, output equal to an input), InputError (unreadable input, no data, an empty surface), GlError
// (no context, GL failure).
WebPageResult writeWebPage(const WebPageRequest& request);

// The camera and image size of one axis's slices (0 axial, 1 coronal, 2 sagittal) on the page: the world box
// of the grid's voxel centres framed in an image whose longer side is `size` pixels (radiological).
struct WebSliceView {
  render::Camera camera;
  int width = 0, height = 0;
};
WebSliceView webSliceView(const Grid& grid, int axis, int size);

// The FA thresholds of the page's sweep: `steps` from lo to hi, rounded to 3 decimals.
std::vector<double> webFaThresholds(double lo, double hi, int steps);

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
