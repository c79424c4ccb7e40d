// SPDX-License-Identifier: GPL-3.0-or-later
#include "io/bids/bids.h"

#include "io/formats/atomic_file.h"
#include "io/formats/json.h"
#include "io/model/error.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <zlib.h>

namespace fs = std::filesystem;

namespace dtf::io {

namespace {

bool startsWith(const std::string& s, const std::string& p) {
  return s.compare(0, p.size(), p) == 0;
}
bool endsWith(const std::string& s, const std::string& p) {
  return s.size() >= p.size() && s.compare(s.size() - p.size(), p.size(), p) == 0;
}
bool alnum(const std::string& s) {
  return !s.empty() && std::all_of(s.begin(), s.end(), [](unsigned char c) { return std::isalnum(c); });
}

// Checks "sub-X[_ses-Y]_key-value…" against the folders; returns the problem or "".
std::string entityProblem(const std::string& stem, const std::string& subject, const std::string& session) {
  std::vector<std::string> parts;
  std::stringstream ss(stem);
  for (std::string p; std::getline(ss, p, '_');)
    parts.push_back(p);
  std::set<std::string> seen;
  for (const std::string& p : parts) {
    const auto dash = p.find('-');
    if (dash == std::string::npos || !alnum(p.substr(0, dash)) || !alnum(p.substr(dash + 1)))
      return "'" + p + "' is not a key-value entity (key-label, letters and digits)";
    if (!seen.insert(p.substr(0, dash)).second) return "entity '" + p.substr(0, dash) + "' appears twice";
  }
  if (parts.empty() || parts[0] != "sub-" + subject)
    return "the name does not start with sub-" + subject + " (its folder)";
  if (!session.empty() && (parts.size() < 2 || parts[1] != "ses-" + session))
    return "the name does not carry ses-" + session + " (its folder) after the subject";
  if (seen.count("desc")) return "a raw file must not carry desc-";
  return "";
}

void scanDwiFolder(const fs::path& dwiDir, const std::string& subject, const std::string& session,
                   const fs::path& root, std::vector<BidsRun>& runs) {
  std::error_code ec;
  if (!fs::is_directory(dwiDir, ec)) return;
  for (const auto& entry : fs::directory_iterator(dwiDir, ec)) {
    const std::string name = entry.path().filename().string();
    std::string stem;
    if (endsWith(name, "_dwi.nii.gz"))
      stem = name.substr(0, name.size() - 11);
    else if (endsWith(name, "_dwi.nii"))
      stem = name.substr(0, name.size() - 8);
    else
      continue;
    if (startsWith(name, ".")) continue;
    BidsRun r;
    r.subject = subject;
    r.session = session;
    r.relDir = fs::relative(dwiDir, root).generic_string();
    r.stem = stem;
    r.dwi = entry.path().string();
    r.bval = (dwiDir / (stem + "_dwi.bval")).string();
    r.bvec = (dwiDir / (stem + "_dwi.bvec")).string();
    r.problem = entityProblem(stem, subject, session);
    if (r.problem.empty()) {
      if (!fs::exists(r.bval, ec))
        r.problem = "no b-value file " + r.bval;
      else if (!fs::exists(r.bvec, ec))
        r.problem = "no gradient file " + r.bvec;
    }
    runs.push_back(std::move(r));
  }
}

std::string withoutPrefix(const std::string& label, const std::string& prefix) {
  return startsWith(label, prefix) ? label.substr(prefix.size()) : label;
}

// Strips a trailing separator so "a/b/" and "a/b" compare equal.
fs::path canonicalish(const std::string& p) {
  std::error_code ec;
  fs::path abs = fs::weakly_canonical(fs::absolute(p), ec);
  if (ec) abs = fs::absolute(p).lexically_normal();
  std::string s = abs.string();
  while (s.size() > 1 && s.back() == '/')
    s.pop_back();
  return s;
}

bool isWithin(const fs::path& inner, const fs::path& outer) {
  auto i = inner.begin(), o = outer.begin();
  for (; o != outer.end(); ++o, ++i)
    if (i == inner.end() || *i != *o) return false;
  return true;
}

} // namespace

BidsDataset scanBidsDataset(const std::string& rootArg) {
  std::error_code ec;
  if (!fs::exists(rootArg, ec)) throw InputError(rootArg + ": no such folder (the BIDS dataset)");
  if (!fs::is_directory(rootArg, ec)) throw InputError(rootArg + ": not a folder (the BIDS dataset)");
  const fs::path root = canonicalish(rootArg);
  BidsDataset ds;
  ds.root = root.string();
  const fs::path desc = root / "dataset_description.json";
  if (!fs::exists(desc, ec))
    throw InputError(rootArg + ": not a BIDS dataset: dataset_description.json is missing");
  {
    const nlohmann::ordered_json d = readJsonFile(desc.string());
    if (!d.is_object()) throw InputError(desc.string() + ": not a JSON object (BIDS dataset_description.json)");
    ds.name = jsonString(d, "Name");
  }
  for (const auto& entry : fs::directory_iterator(root, ec)) {
    const std::string name = entry.path().filename().string();
    if (!startsWith(name, "sub-") || !entry.is_directory()) continue;
    const std::string subject = name.substr(4);
    if (!alnum(subject)) continue;
    ds.subjects.push_back(subject);
    scanDwiFolder(entry.path() / "dwi", subject, "", root, ds.runs);
    for (const auto& sesEntry : fs::directory_iterator(entry.path(), ec)) {
      const std::string ses = sesEntry.path().filename().string();
      if (!startsWith(ses, "ses-") || !sesEntry.is_directory() || !alnum(ses.substr(4))) continue;
      scanDwiFolder(sesEntry.path() / "dwi", subject, ses.substr(4), root, ds.runs);
    }
  }
  if (ds.subjects.empty())
    throw InputError(rootArg + ": not a BIDS dataset: no sub-<label> folder (participants live in sub-*/)");
  std::sort(ds.subjects.begin(), ds.subjects.end());
  std::sort(ds.runs.begin(), ds.runs.end(), [](const BidsRun& a, const BidsRun& b) {
    return a.relDir != b.relDir ? a.relDir < b.relDir : a.stem < b.stem;
  });
  return ds;
}

std::vector<BidsRun> selectRuns(const BidsDataset& ds, const std::vector<std::string>& participants,
                                const std::vector<std::string>& sessions) {
  std::set<std::string> want, wantSes;
  std::string unknown;
  for (const auto& p : participants) {
    const std::string label = withoutPrefix(p, "sub-");
    if (!std::binary_search(ds.subjects.begin(), ds.subjects.end(), label))
      unknown += (unknown.empty() ? "" : ", ") + label;
    want.insert(label);
  }
  if (!unknown.empty())
    throw InputError(ds.root + ": no participant " + unknown + " (the dataset has " +
                     std::to_string(ds.subjects.size()) + ": sub-" + ds.subjects.front() +
                     (ds.subjects.size() > 1 ? " … sub-" + ds.subjects.back() : "") + ")");
  for (const auto& s : sessions)
    wantSes.insert(withoutPrefix(s, "ses-"));
  std::vector<BidsRun> out;
  std::set<std::string> sessionsSeen;
  for (const auto& r : ds.runs) {
    if (!want.empty() && !want.count(r.subject)) continue;
    sessionsSeen.insert(r.session);
    if (!wantSes.empty() && !wantSes.count(r.session)) continue;
    out.push_back(r);
  }
  for (const auto& s : wantSes)
    if (!sessionsSeen.count(s)) unknown += (unknown.empty() ? "" : ", ") + s;
  if (!unknown.empty())
    throw InputError(ds.root + ": no session " + unknown +
                     " with a dwi folder among the selected participants");
  return out;
}

std::string derivativeName(const BidsRun& run, const std::string& desc, const std::string& suffix,
                           const std::string& extension) {
  return run.stem + "_desc-" + desc + "_" + suffix + extension;
}

void refuseOutputInsideInput(const std::string& bidsRoot, const std::string& output) {
  const fs::path in = canonicalish(bidsRoot), out = canonicalish(output);
  if (isWithin(out, in))
    throw InputError(output + ": the output folder lies inside the BIDS dataset " + bidsRoot +
                     " (nothing is written into the input; choose a folder outside it, e.g. " +
                     (in.parent_path() / (in.filename().string() + "-dtfabric")).string() + ")");
  if (isWithin(in, out))
    throw InputError(output + ": the BIDS dataset " + bidsRoot + " lies inside the output folder");
}

void writeDerivativeDescription(const std::string& outputRoot, const BidsDataset& source,
                                const std::string& version) {
  const nlohmann::ordered_json d = {
      {"Name", "dtfabric QC" + (source.name.empty() ? "" : " of " + source.name)},
      {"BIDSVersion", "1.8.0"},
      {"DatasetType", "derivative"},
      {"GeneratedBy",
       {{{"Name", "dtfabric"},
         {"Version", version},
         {"Description", "tensor fit, gradient-orientation check and fabric figures per diffusion run"}}}},
      {"SourceDatasets", {{{"URL", "file://" + source.root}}}}};
  const std::string text = jsonText(d, 2) + "\n";
  writeTextIfChanged((fs::path(outputRoot) / "dataset_description.json").string(), text);
}

std::string fileHash(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot be read");
  uLong crc = crc32(0L, Z_NULL, 0);
  std::vector<char> buf(1 << 20);
  std::uint64_t size = 0;
  while (in) {
    in.read(buf.data(), static_cast<std::streamsize>(buf.size()));
    const auto n = static_cast<std::size_t>(in.gcount());
    if (n == 0) break;
    crc = crc32(crc, reinterpret_cast<const Bytef*>(buf.data()), static_cast<uInt>(n));
    size += n;
  }
  if (in.bad()) throw InputError(path + ": read error");
  char out[64];
  std::snprintf(out, sizeof out, "crc32:%08lx:%llu", static_cast<unsigned long>(crc),
                static_cast<unsigned long long>(size));
  return out;
}

std::string readTextFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot be read");
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

bool writeTextIfChanged(const std::string& path, const std::string& text) {
  std::error_code ec;
  if (fs::exists(path, ec)) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    if (in && ss.str() == text) return false;
  }
  AtomicOutput out(path);
  {
    std::ofstream os(out.tempPath(), std::ios::binary);
    os << text;
    os.flush();
    if (!os) throw InputError(path + ": write failed");
  }
  out.commit();
  return true;
}

} // namespace dtf::io
