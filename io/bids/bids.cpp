#include "io/bids/bids.h"

#include "io/formats/atomic_file.h"
#include "io/model/error.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
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
    const std::string text = readTextFile(desc.string());
    const auto first = text.find_first_not_of(" \t\r\n");
    if (first == std::string::npos || text[first] != '{' || text.find('}') == std::string::npos)
      throw InputError(desc.string() + ": not a JSON object (BIDS dataset_description.json)");
    // Name is a plain string in every valid description; read it without a general JSON parser.
    const auto key = text.find("\"Name\"");
    if (key != std::string::npos) {
      const auto open = text.find('"', text.find(':', key) + 1);
      const auto close = open == std::string::npos ? open : text.find('"', open + 1);
      if (close != std::string::npos) ds.name = text.substr(open + 1, close - open - 1);
    }
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
  std::string text = "{\n";
  text +=
      "  \"Name\": " + jsonQuote("dtfabric QC" + (source.name.empty() ? "" : " of " + source.name)) + ",\n";
  text += "  \"BIDSVersion\": \"1.8.0\",\n";
  text += "  \"DatasetType\": \"derivative\",\n";
  text += "  \"GeneratedBy\": [{\"Name\": \"dtfabric\", \"Version\": " + jsonQuote(version) +
          ", \"Description\": \"tensor fit, gradient-orientation check and fabric figures per diffusion "
          "run\"}],\n";
  text += "  \"SourceDatasets\": [{\"URL\": " + jsonQuote("file://" + source.root) + "}]\n";
  text += "}\n";
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

std::string jsonQuote(const std::string& s) {
  std::string o = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') {
      o += '\\';
      o += c;
    } else if (c == '\n') {
      o += "\\n";
    } else if (c == '\t') {
      o += "\\t";
    } else if (static_cast<unsigned char>(c) >= 0x20) {
      o += c;
    }
  }
  return o + "\"";
}

void FlatJson::set(const std::string& key, const std::string& value) {
  if (!values_.count(key)) order_.push_back(key);
  values_[key] = {value, true};
}

void FlatJson::setNumber(const std::string& key, double value, int precision) {
  if (!values_.count(key)) order_.push_back(key);
  char buf[64];
  if (std::isfinite(value))
    std::snprintf(buf, sizeof buf, "%.*g", precision, value);
  else
    std::snprintf(buf, sizeof buf, "null");
  values_[key] = {buf, false};
}

void FlatJson::setBool(const std::string& key, bool value) {
  if (!values_.count(key)) order_.push_back(key);
  values_[key] = {value ? "true" : "false", false};
}

bool FlatJson::has(const std::string& key) const {
  return values_.count(key) > 0;
}

std::string FlatJson::get(const std::string& key) const {
  auto it = values_.find(key);
  return it == values_.end() ? "" : it->second.first;
}

double FlatJson::number(const std::string& key) const {
  auto it = values_.find(key);
  if (it == values_.end() || it->second.second) return std::nan("");
  char* end = nullptr;
  const double v = std::strtod(it->second.first.c_str(), &end);
  return end && *end == 0 && !it->second.first.empty() ? v : std::nan("");
}

std::string FlatJson::text() const {
  std::string o = "{\n";
  for (std::size_t i = 0; i < order_.size(); ++i) {
    const auto& [v, isString] = values_.at(order_[i]);
    o += "  " + jsonQuote(order_[i]) + ": " + (isString ? jsonQuote(v) : v) +
         (i + 1 < order_.size() ? ",\n" : "\n");
  }
  return o + "}\n";
}

FlatJson FlatJson::parse(const std::string& text, const std::string& origin) {
  FlatJson j;
  std::size_t i = 0;
  auto fail = [&](const std::string& what) -> void {
    throw InputError(origin + ": " + what + " at byte " + std::to_string(i) +
                     " (expected a flat JSON object)");
  };
  auto skip = [&] {
    while (i < text.size() && std::isspace(static_cast<unsigned char>(text[i])))
      ++i;
  };
  auto str = [&]() -> std::string {
    if (i >= text.size() || text[i] != '"') fail("no string");
    std::string s;
    for (++i; i < text.size() && text[i] != '"'; ++i) {
      if (text[i] == '\\' && i + 1 < text.size()) {
        const char e = text[++i];
        s += e == 'n' ? '\n' : e == 't' ? '\t' : e;
      } else {
        s += text[i];
      }
    }
    if (i >= text.size()) fail("unterminated string");
    ++i;
    return s;
  };
  skip();
  if (i >= text.size() || text[i] != '{') fail("no '{'");
  ++i;
  skip();
  if (i < text.size() && text[i] == '}') return j;
  while (true) {
    skip();
    const std::string key = str();
    skip();
    if (i >= text.size() || text[i] != ':') fail("no ':'");
    ++i;
    skip();
    if (i < text.size() && text[i] == '"') {
      j.set(key, str());
    } else {
      const std::size_t start = i;
      while (i < text.size() && text[i] != ',' && text[i] != '}' &&
             !std::isspace(static_cast<unsigned char>(text[i])))
        ++i;
      const std::string v = text.substr(start, i - start);
      if (v.empty() || v[0] == '{' || v[0] == '[') fail("a nested value");
      if (!j.values_.count(key)) j.order_.push_back(key);
      j.values_[key] = {v, false};
    }
    skip();
    if (i < text.size() && text[i] == ',') {
      ++i;
      continue;
    }
    if (i < text.size() && text[i] == '}') break;
    fail("no ',' or '}'");
  }
  return j;
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
