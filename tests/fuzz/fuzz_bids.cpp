// SPDX-License-Identifier: GPL-3.0-or-later
// libFuzzer target: the BIDS layout scanner (io/bids/bids.h) on a folder tree built from the input, then the
// gradient tables of the runs it finds (io/diffusion/dwi.h). Each input line "PATH" makes a folder (when it
// ends in '/') or an empty file; "PATH=TEXT" makes a file holding TEXT ("\n" in TEXT is a line break). Paths
// are kept inside the scratch dataset: '..' and empty components are dropped, at most 64 entries and 8
// levels. "dataset_description.json" at the top is made like any other file, so the fuzzer also meets
// datasets without one. Any dtf::Error is an accepted outcome.
#include "fuzz_file.h"
#include "io/bids/bids.h"
#include "io/diffusion/dwi.h"
#include "io/model/error.h"
#include "io/model/log.h"

#include <fstream>
#include <sstream>

namespace fs = std::filesystem;

namespace {

// `rel` split on '/', without '.', '..' and empty parts; empty when it has more than 8 levels.
fs::path safeRelative(const std::string& rel) {
  fs::path out;
  std::stringstream ss(rel);
  int depth = 0;
  for (std::string part; std::getline(ss, part, '/');) {
    if (part.empty() || part == "." || part == ".." || part.find('\0') != std::string::npos) continue;
    if (++depth > 8) return {};
    out /= part;
  }
  return out;
}

void build(const fs::path& root, const std::string& spec) {
  std::stringstream lines(spec);
  int entries = 0;
  std::error_code ec;
  for (std::string line; std::getline(lines, line) && entries < 64; ++entries) {
    const auto eq = line.find('=');
    const std::string rel = line.substr(0, eq);
    const fs::path p = safeRelative(rel);
    if (p.empty()) continue;
    if (eq == std::string::npos && !rel.empty() && rel.back() == '/') {
      fs::create_directories(root / p, ec);
      continue;
    }
    fs::create_directories((root / p).parent_path(), ec);
    if (fs::is_directory(root / p, ec)) continue;
    std::string text = eq == std::string::npos ? "" : line.substr(eq + 1);
    for (std::size_t at = 0; (at = text.find("\\n", at)) != std::string::npos;)
      text.replace(at, 2, "\n");
    std::ofstream(root / p, std::ios::binary) << text;
  }
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const bool quiet = (dtf::setLogSink([](dtf::LogLevel, const std::string&) {}), true);
  (void)quiet;
  static const fs::path dir = dtf::fuzz::scratchDir("bids");
  dtf::fuzz::clearDir(dir);
  const fs::path root = dir / "ds";
  fs::create_directories(root);
  build(root, std::string(reinterpret_cast<const char*>(data), size));
  try {
    const dtf::io::BidsDataset ds = dtf::io::scanBidsDataset(root.string());
    // The scanner's promise: runs only under sub-* folders of the dataset, labels of letters and digits.
    for (const auto& r : ds.runs) {
      if (r.dwi.compare(0, ds.root.size(), ds.root) != 0) std::abort();
      if (r.subject.empty()) std::abort();
    }
    dtf::io::selectRuns(ds, {}, {});
    if (!ds.subjects.empty()) dtf::io::selectRuns(ds, {ds.subjects.front()}, {});
    dtf::io::refuseOutputInsideInput(ds.root, (dir / "out").string());
    for (const auto& r : ds.runs) {
      (void)dtf::io::derivativeName(r, "fabric", "dwi", ".png");
      if (!r.problem.empty()) continue;
      try {
        const auto bvals = dtf::io::readBvals(r.bval);
        dtf::io::readBvecs(r.bvec, bvals.size());
      } catch (const dtf::Error&) {
      }
    }
  } catch (const dtf::Error&) {
  }
  return 0;
}
