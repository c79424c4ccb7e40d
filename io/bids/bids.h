// SPDX-License-Identifier: GPL-3.0-or-later
// BIDS datasets as `dtfabric bids` reads and writes them: finding the diffusion runs of a raw dataset
// (`sub-*/[ses-*/]dwi/*_dwi.nii[.gz]` with their `.bval`/`.bvec`), naming derivatives (every entity of the
// source name kept, `desc-…` added before the suffix) and the derivative's `dataset_description.json`. Pure
// file-system work: no imaging here.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace dtf::io {

// One diffusion run of a raw BIDS dataset.
struct BidsRun {
  std::string subject; // label without "sub-", e.g. "01"
  std::string session; // label without "ses-"; empty when the dataset has no session level
  std::string relDir;  // folder relative to the dataset root, e.g. "sub-01/ses-A/dwi"
  std::string stem;    // source name without "_dwi.nii[.gz]", e.g. "sub-01_ses-A_acq-b2500_run-1"
  std::string dwi;     // absolute paths; bval/bvec name the expected siblings even when they are missing
  std::string bval, bvec;
  // Why the run cannot be processed as found (no .bval or .bvec, a name that breaks the entity rules);
  // empty when it can.
  std::string problem;
};

struct BidsDataset {
  std::string root;                  // absolute, normalised
  std::string name;                  // dataset_description.json's "Name" ("" when absent)
  std::vector<BidsRun> runs;         // sorted by relDir, then stem
  std::vector<std::string> subjects; // every sub-* folder's label, sorted (with or without a dwi run)
};

// Scans a raw BIDS dataset. Throws InputError naming the folder and the problem when it is not a folder, has
// no dataset_description.json (or one that is not a JSON object), or has no sub-* folder.
BidsDataset scanBidsDataset(const std::string& root);

// Keeps the runs of the given participant labels ("01" or "sub-01") and session labels (empty = all).
// Throws InputError naming every label that matches no participant (or session) of the dataset.
std::vector<BidsRun> selectRuns(const BidsDataset& ds, const std::vector<std::string>& participants,
                                const std::vector<std::string>& sessions);

// The derivative name of `run` with the description `desc` and the suffix and extension given, e.g.
// derivativeName(run, "fabricAxial", "dwi", ".png") = "sub-01_ses-A_acq-b2500_desc-fabricAxial_dwi.png".
std::string derivativeName(const BidsRun& run, const std::string& desc, const std::string& suffix,
                           const std::string& extension);

// Throws InputError when `output` is the dataset folder or lies inside it (a derivative written into its
// source dataset would be picked up as raw data), or when the dataset lies inside `output`'s sub-* folders.
void refuseOutputInsideInput(const std::string& bidsRoot, const std::string& output);

// Writes OUTPUT/dataset_description.json (BIDS 1.8 derivative: DatasetType, GeneratedBy dtfabric + version,
// SourceDatasets with the raw dataset's URL as file://), atomically, only when its content changes.
void writeDerivativeDescription(const std::string& outputRoot, const BidsDataset& source,
                                const std::string& version);

// A content hash of a file for change detection: zlib CRC-32 over the bytes and the byte count, as
// "crc32:XXXXXXXX:SIZE". Not cryptographic: it detects edits and replaced files, not tampering. Throws
// InputError when the file cannot be read.
std::string fileHash(const std::string& path);

// Writes `text` to `path` atomically unless the file already holds exactly that text. Returns true when it
// wrote. Throws InputError.
bool writeTextIfChanged(const std::string& path, const std::string& text);
// The whole file; throws InputError naming the path when it cannot be read.
std::string readTextFile(const std::string& path);

} // namespace dtf::io
