// SPDX-License-Identifier: GPL-3.0-or-later
// The group level of `dtfabric bids`: one row per diffusion run from the participant level's metrics
// documents, the outlier flags, `group.tsv` and the self-contained `group_report.html` (inline CSS and
// JavaScript, figures referenced by relative path, so it works opened from the file system: no server).
#pragma once

#include <string>
#include <vector>

namespace dtf::io {

// The metrics columns of group.tsv, in order; each is a numeric key of the participant level's metrics JSON.
const std::vector<std::string>& groupMetricColumns();
// The metrics screened for outliers (a subset of groupMetricColumns()).
const std::vector<std::string>& outlierMetrics();

struct GroupFigure {
  std::string label; // "axial", "coronal", "iso left", "iso top", "check sheet"
  std::string path;  // relative to the output folder, '/'-separated
};

struct GroupRow {
  std::string participant; // "sub-01"
  std::string session;     // "ses-A" or "" (written "n/a")
  std::string run;         // source stem, e.g. "sub-01_ses-A_acq-b2500"
  bool ok = false;
  std::string verdict;         // ok | corrected | inconclusive; "" when failed
  std::string correction;      // the check's correction, e.g. "-x y z"
  std::vector<double> metrics; // groupMetricColumns() order; NaN when unknown
  double seconds = 0;          // participant-level wall time (report only, not group.tsv)
  std::string message;
  std::vector<GroupFigure> figures;
  std::string webPage; // the run's web page (index.html) relative to the output folder, "" none
  std::vector<std::string> outliers; // metric names flagged (filled by flagOutliers)
};

// Marks outlying metrics among the ok rows: robust z = 0.6745 (x - median) / MAD, flagged when |z| > 3.5
// (Iglewicz and Hoaglin's modified z-score). When the MAD is 0 (more than half the rows equal), the scale
// is 1.2533 times the mean absolute deviation from the median instead (their fallback); when that is 0 too,
// nothing is flagged. A value within 5% of the median is never flagged (near-identical cohorts have a tiny
// MAD). Needs at least 5 ok rows with a finite value; fewer: nothing is flagged.
void flagOutliers(std::vector<GroupRow>& rows);

// group.tsv: participant_id, session_id, run, status (ok|failed), check_verdict, check_correction, the
// metrics, outliers (comma-separated names), message. Missing values are "n/a". Deterministic: no times.
std::string groupTsv(const std::vector<GroupRow>& rows);

// The report page. `title` heads it; `generated` is a line such as "dtfabric 0.1.0, 2026-11-24 06:30 UTC".
// The page embeds a self-check that runs when opened with "#selfcheck": it waits for every image, then
// writes a JSON summary (images, loaded, broken, errors caught, the flagged rows per flag, the web page links, and the overlay
// opened by clicking the card with the most figures: its images loaded) into <pre id="dtf-selfcheck">, for
// headless-browser tests. With "#timing" it sorts the table by a metric twice and opens one run's figures,
// and writes the milliseconds into <pre id="dtf-timing"> (for `bench bids`).
std::string groupReportHtml(const std::vector<GroupRow>& rows, const std::string& title,
                            const std::string& generated);

// HTML text escaping.
std::string htmlEscape(const std::string& s);

} // namespace dtf::io
