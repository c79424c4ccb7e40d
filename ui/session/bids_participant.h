// SPDX-License-Identifier: GPL-3.0-or-later
// The participant level of `dtfabric bids` for one diffusion run: fit, orientation check, figure set and
// metrics document under OUTPUT/<relDir>/, with BIDS-derivative names. Idempotent and atomic: every file is
// written to a temporary sibling and renamed; the metrics document is written last and records the input
// hashes and the parameters, so a run is complete exactly when its document says so and its figures exist.
#pragma once

#include "io/bids/bids.h"
#include "io/bids/bids_report.h"

#include <string>
#include <vector>

namespace dtf::session {

struct ParticipantOptions {
  int figurePx = 512;   // edge of each figure in pixels
  int sheetPanelPx = 0; // contact-sheet panel edge; 0 = figurePx / 2 (at least 96)
  int fitThreads = 0;   // 0 = hardware concurrency
  bool force = false;   // recompute even when complete and unchanged
  int webPx = 0;        // > 0: also the run's web page (ui/session/web_page.h), images of this size
  std::string version;  // dtfabric's version, recorded and part of the parameters
};

// The figure descriptions (desc- entity values) and their captions, in report order. The contact sheet
// ("fabricCheck") exists only for runs whose verdict is not ok.
struct FigureKind {
  const char* desc;
  const char* caption;
};
const std::vector<FigureKind>& figureKinds();

struct RunOutcome {
  bool ok = false;
  bool skipped = false; // complete and unchanged: nothing recomputed
  std::string verdict;  // ok | corrected | inconclusive ("" when failed)
  std::string message;  // failed: the file and the reason; ok: a short summary
  double seconds = 0;
};

// Where the run's metrics document lives.
std::string metricsPath(const io::BidsRun& run, const std::string& outputRoot);

// Processes one run. Never throws for a problem of the run's data (a corrupt file, a missing table, a wrong
// volume count: recorded as failed in the metrics document, with the file and the reason) nor for a GL
// failure (recorded likewise); throws InputError only when the output folder cannot be written.
RunOutcome processRun(const io::BidsRun& run, const std::string& outputRoot,
                      const ParticipantOptions& options);

// The group row of `run` from its metrics document (failed with "not processed" when there is none).
io::GroupRow readGroupRow(const io::BidsRun& run, const std::string& outputRoot);

} // namespace dtf::session
