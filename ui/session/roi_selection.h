// SPDX-License-Identifier: GPL-3.0-or-later
// The viewer's ROI selection (issue "Dissect in the viewer"): which streamlines of the tracts on screen the
// region set the user edits keeps. The session (ui/session/viewer_session.h) owns the region set and hands it
// to its ROI worker (ui/session/roi_worker.h), which builds the streamlines' TractIndex once per tract set and
// runs surfaces::selectLines off the UI thread, coalescing; the result lands here when the session's update()
// takes it.
//
// How a reader gets it: `ViewerSession::roiSelection()` (and `Viewer::session().roiSelection()`), on the UI
// thread, the thread that calls ViewerSession::update() and apply(). The struct is replaced as a whole only
// there; compare `generation` with the one last seen to learn of a change (it changes whenever `active`,
// `lines` or `tracts` change). The vectors behind the shared pointers are never modified once published, so
// a reader may copy the shared pointers and hand them to its own worker thread; it must not keep a reference
// to the struct itself across frames.
//
// What it means: `tracts` is the loaded (or tracked) set the indices refer to, every streamline in file
// order (ViewerSession::tracts(), before any group choice). When `active` is false no region applies and
// every streamline of `tracts` counts as selected (`lines` is then null); when true, `lines` holds the
// selected streamlines' indices into `tracts`, ascending (possibly none), exactly what `dtfabric select
// TRACTS --roi SET.json` keeps.
#pragma once

#include "io/model/geometry.h"

#include <algorithm>
#include <cstdint>
#include <memory>
#include <vector>

namespace dtf::session {

struct RoiSelection {
  std::shared_ptr<const Polylines> tracts;                 // the set the indices refer to; null: no tracts
  std::shared_ptr<const std::vector<std::uint32_t>> lines; // active: selected indices into *tracts, ascending
  bool active = false;         // a region (or a length range) applies; false: every streamline is selected
  std::uint64_t generation = 0; // changes with every change of the fields above
  bool pending = false;         // a newer selection is being computed; the fields above stay valid meanwhile

  // The number of selected streamlines (every streamline when not active).
  std::size_t count() const {
    return active ? (lines ? lines->size() : 0) : (tracts ? tracts->lineCount() : 0);
  }
  // Whether streamline i of *tracts is selected (binary search when active).
  bool selected(std::uint32_t i) const {
    return !active || (lines && std::binary_search(lines->begin(), lines->end(), i));
  }
};

} // namespace dtf::session
