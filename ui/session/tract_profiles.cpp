// SPDX-License-Identifier: GPL-3.0-or-later
#include "ui/session/tract_profiles.h"

#include "io/formats/json.h"
#include "io/formats/tensor_io.h"
#include "io/model/error.h"
#include "io/model/tensor_field.h"
#include "ui/session/region_spec.h"
#include "ui/session/tract_files.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <set>

namespace fs = std::filesystem;

namespace dtf::session {

namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

bool builtIn(const std::string& name) {
  const std::string n = lower(name);
  return n == "fa" || n == "md" || n == "ad" || n == "rd";
}

std::vector<std::string> splitList(const std::string& text) {
  std::vector<std::string> out;
  std::size_t b = 0;
  while (b <= text.size()) {
    const std::size_t e = std::min(text.find(',', b), text.size());
    if (e > b) out.push_back(text.substr(b, e - b));
    b = e + 1;
  }
  return out;
}

// The file's name without its tract extension: cst_left.trk.gz -> cst_left, a TRX folder -> its name.
std::string stemOf(const std::string& path) {
  std::string p = path;
  while (p.size() > 1 && p.back() == '/')
    p.pop_back();
  std::string name = fs::path(p).filename().string();
  const std::string l = lower(name);
  for (const char* ext : {".trk.gz", ".tck", ".trk", ".trx", ".vtk", ".vtp"}) {
    const std::string e = ext;
    if (l.size() > e.size() && l.compare(l.size() - e.size(), e.size(), e) == 0)
      return name.substr(0, name.size() - e.size());
  }
  return name;
}

std::string parentOf(const std::string& path) {
  std::string p = path;
  while (p.size() > 1 && p.back() == '/')
    p.pop_back();
  const std::string parent = fs::path(p).parent_path().filename().string();
  return parent.empty() ? "." : parent;
}

// Tab and line breaks would break the table's rows.
std::string tableSafe(std::string s) {
  for (char& c : s)
    if (c == '\t' || c == '\n' || c == '\r') c = ' ';
  return s;
}

} // namespace

ScalarVolume readScalarImage(const ScalarSpec& spec) {
  ScalarVolume v;
  try {
    v = io::readScalarVolume(spec.image);
  } catch (const Error&) {
    rethrowWithContext("--scalar " + spec.name + "=" + spec.image);
  }
  if (v.components != 1)
    throw InputError(spec.image + ": has " + std::to_string(v.components) +
                     " values per voxel; a --scalar image has one (scalar '" + spec.name + "')");
  if (v.data.empty()) throw InputError(spec.image + ": has no voxels (scalar '" + spec.name + "')");
  return v;
}

namespace {

std::string number(double v, const char* format) {
  if (!std::isfinite(v)) return "NaN";
  char buf[48];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

nlohmann::ordered_json jsonNumber(double v) {
  return std::isfinite(v) ? nlohmann::ordered_json(v) : nlohmann::ordered_json(nullptr);
}

const char* weightsName(surfaces::ProfileWeights w) {
  switch (w) {
  case surfaces::ProfileWeights::Gauss:
    return "gauss";
  case surfaces::ProfileWeights::Mean:
    return "mean";
  case surfaces::ProfileWeights::Median:
    return "median";
  }
  return "?";
}

} // namespace

ScalarSpec parseScalarSpec(const std::string& text) {
  ScalarSpec s;
  const std::size_t eq = text.find('=');
  if (eq == std::string::npos) {
    if (!builtIn(text))
      throw InputError("--scalar '" + text +
                       "': not fa, md, ad or rd, nor NAME=IMAGE (an image file as NAME)");
    s.name = text;
    return s;
  }
  s.name = text.substr(0, eq);
  s.image = text.substr(eq + 1);
  if (s.name.empty()) throw InputError("--scalar '" + text + "': no NAME before '=' (NAME=IMAGE)");
  if (s.image.empty()) throw InputError("--scalar '" + text + "': no IMAGE after '=' (NAME=IMAGE)");
  if (s.name.find_first_of("\t\n\r") != std::string::npos)
    throw InputError("--scalar '" + text + "': NAME holds a tab or line break");
  return s;
}

std::vector<std::string> profileInputs(const ProfileRequest& r) {
  std::vector<std::string> in = r.tracts;
  for (const auto& s : r.scalars) {
    const std::size_t eq = s.find('=');
    if (eq != std::string::npos && eq + 1 < s.size()) in.push_back(s.substr(eq + 1));
  }
  for (const std::string* p :
       {&r.tensor, &r.tensorOptions.bval, &r.tensorOptions.bvec, &r.tensorOptions.mask})
    if (!p->empty()) in.push_back(*p);
  if (!r.start.empty()) {
    // A mask or label image as the start region: its file, before any ":L,L" labels.
    const std::size_t colon = r.start.rfind(':');
    const std::string file = colon == std::string::npos ? r.start : r.start.substr(0, colon);
    std::error_code ec;
    if (fs::exists(r.start, ec))
      in.push_back(r.start);
    else if (fs::exists(file, ec))
      in.push_back(file);
  }
  return in;
}

glm::dvec3 startPointOf(const std::string& spec) {
  // X,Y,Z: a point (a sphere without its radius); anything else is a region (ui/session/region_spec.h).
  const auto parts = splitList(spec);
  if (parts.size() == 3 && spec.find(':') == std::string::npos) {
    glm::dvec3 p;
    for (int i = 0; i < 3; ++i) {
      char* end = nullptr;
      p[i] = std::strtod(parts[i].c_str(), &end);
      if (end == parts[i].c_str() || *end || !std::isfinite(p[i]))
        throw InputError("--start '" + spec + "': X,Y,Z must be three finite numbers (world RAS mm)");
    }
    return p;
  }
  try {
    return parseRegionSpec(spec).centreOf();
  } catch (const Error&) {
    rethrowWithContext("--start");
  }
  return {};
}

ProfileResult runProfile(const ProfileRequest& r) {
  if (r.tracts.empty()) throw UsageError("no tract file given");
  if (r.scalars.empty()) throw UsageError("no --scalar given (fa, md, ad, rd or NAME=IMAGE)");
  ProfileResult out;
  out.options = r.options;
  out.start = r.start;
  if (!r.start.empty()) out.options.start = startPointOf(r.start);

  // The scalars: the tensor's maps (loaded once, when one is asked for) and the images.
  std::vector<ScalarSpec> specs;
  std::set<std::string> names;
  bool needTensor = false;
  for (const auto& text : r.scalars) {
    specs.push_back(parseScalarSpec(text));
    if (!names.insert(specs.back().name).second)
      throw UsageError("--scalar: the name '" + specs.back().name + "' is given twice");
    needTensor = needTensor || specs.back().image.empty();
  }
  MetricMaps maps;
  if (needTensor) {
    if (r.tensor.empty())
      throw UsageError(
          "--scalar fa, md, ad and rd are the tensor's: give --tensor T (a tensor file or a DWI), "
          "or the map as NAME=IMAGE");
    TensorInputOptions in = r.tensorOptions;
    in.layout = io::parseLayout(r.layout);
    const io::LoadedTensors loaded = loadTensorInput(r.tensor, in);
    maps = computeMetricMaps(loaded.field, false, false);
  }
  std::vector<ScalarVolume> images;
  images.reserve(specs.size());
  std::vector<surfaces::ProfileScalar> scalars;
  for (const auto& s : specs) {
    const ScalarVolume* v = nullptr;
    if (s.image.empty()) {
      const std::string n = lower(s.name);
      v = n == "fa" ? &maps.fa : n == "md" ? &maps.md : n == "ad" ? &maps.ad : &maps.rd;
    } else {
      images.push_back(readScalarImage(s));
      v = &images.back();
    }
    scalars.push_back({s.name, v});
    out.scalars.push_back(s.name);
  }

  const std::vector<std::string> wanted =
      r.groups == "all" ? std::vector<std::string>{} : splitList(r.groups);
  if (!r.groups.empty() && r.groups != "all" && wanted.empty())
    throw UsageError("--groups '" + r.groups + "': no group named (all, or G[,G...])");
  for (const auto& file : r.tracts) {
    const Polylines lines = readTracts(file);
    auto profile = [&](const std::vector<std::uint32_t>* which, const std::string& group) {
      ProfiledBundle b;
      b.file = file;
      b.group = group;
      b.name = group.empty() ? stemOf(file) : group;
      try {
        b.profile = surfaces::profileBundle(lines, which, scalars, out.options);
      } catch (const Error&) {
        rethrowWithContext(file + (group.empty() ? "" : " (group '" + group + "')"));
      }
      b.axis = surfaces::nodeAxisLabel(b.profile.core.front(), b.profile.core.back());
      out.bundles.push_back(std::move(b));
    };
    if (r.groups.empty()) {
      profile(nullptr, "");
      continue;
    }
    if (lines.groups.empty()) throw InputError(file + ": has no groups (--groups " + r.groups + ")");
    std::string available;
    for (const auto& g : lines.groups)
      available += (available.empty() ? "" : ", ") + g.name;
    if (wanted.empty()) {
      for (const auto& g : lines.groups)
        profile(&g.lines, g.name);
      continue;
    }
    for (const auto& name : wanted) {
      const auto g = std::find_if(lines.groups.begin(), lines.groups.end(),
                                  [&](const TractGroup& t) { return t.name == name; });
      if (g == lines.groups.end())
        throw InputError(file + ": no group '" + name + "' (groups: " + available + ")");
      profile(&g->lines, g->name);
    }
  }

  // Names two bundles share are qualified: a file's by its folder, a group's by its file.
  std::map<std::string, int> uses;
  for (const auto& b : out.bundles)
    ++uses[b.name];
  for (auto& b : out.bundles)
    if (uses[b.name] > 1)
      b.name = b.group.empty() ? parentOf(b.file) + "/" + b.name : stemOf(b.file) + "/" + b.name;
  return out;
}

std::string profileTable(const ProfileResult& r) {
  std::string t = "bundle\tscalar\tnode\tx\ty\tz\tmean\tsd\tci_low\tci_high\tstreamlines\n";
  for (const auto& b : r.bundles) {
    const std::string bundle = tableSafe(b.name);
    for (const auto& s : b.profile.scalars)
      for (std::size_t k = 0; k < b.profile.core.size(); ++k) {
        const glm::dvec3 c = b.profile.core[k];
        t += bundle + "\t" + tableSafe(s.name) + "\t" + std::to_string(k) + "\t" + number(c.x, "%.3f") +
             "\t" + number(c.y, "%.3f") + "\t" + number(c.z, "%.3f") + "\t" + number(s.mean[k], "%.7g") +
             "\t" + number(s.sd[k], "%.7g") + "\t" + number(s.ciLow[k], "%.7g") + "\t" +
             number(s.ciHigh[k], "%.7g") + "\t" + std::to_string(s.streamlines[k]) + "\n";
      }
  }
  return t;
}

std::string profileJson(const ProfileResult& r) {
  using J = nlohmann::ordered_json;
  J bundles = J::array(), rows = J::array();
  for (const auto& b : r.bundles) {
    bundles.push_back({{"name", b.name},
                       {"file", b.file},
                       {"group", b.group.empty() ? J(nullptr) : J(b.group)},
                       {"streamlines", b.profile.streamlines},
                       {"skipped", b.profile.skipped},
                       {"flipped", b.profile.flipped},
                       {"axis", b.axis}});
    for (const auto& s : b.profile.scalars)
      for (std::size_t k = 0; k < b.profile.core.size(); ++k) {
        const glm::dvec3 c = b.profile.core[k];
        rows.push_back({{"bundle", b.name},
                        {"scalar", s.name},
                        {"node", k},
                        {"x", c.x},
                        {"y", c.y},
                        {"z", c.z},
                        {"mean", jsonNumber(s.mean[k])},
                        {"sd", jsonNumber(s.sd[k])},
                        {"ci_low", jsonNumber(s.ciLow[k])},
                        {"ci_high", jsonNumber(s.ciHigh[k])},
                        {"streamlines", s.streamlines[k]}});
      }
  }
  const J j = {{"nodes", r.options.nodes},
               {"weights", weightsName(r.options.weights)},
               {"bootstrap", r.options.bootstrap},
               {"seed", r.options.seed},
               {"confidence", r.options.confidence},
               {"start", r.start.empty() ? J(nullptr) : J(r.start)},
               {"scalars", r.scalars},
               {"bundles", bundles},
               {"rows", rows}};
  return io::jsonText(j);
}

render::ProfileFigure profileFigure(const ProfileResult& r) {
  render::ProfileFigure f;
  std::string common = r.bundles.empty() ? "" : r.bundles.front().axis;
  for (const auto& b : r.bundles)
    if (b.axis != common) common.clear();
  f.xLabel = common.empty() ? "node" : "node (" + common + ")";
  for (std::size_t s = 0; s < r.scalars.size(); ++s) {
    render::ProfilePanel p;
    p.yLabel = builtIn(r.scalars[s]) ? [](std::string n) {
      std::transform(n.begin(), n.end(), n.begin(), [](unsigned char c) { return static_cast<char>(std::toupper(c)); });
      return n;
    }(r.scalars[s])
                                     : r.scalars[s];
    for (const auto& b : r.bundles) {
      const auto& sp = b.profile.scalars[s];
      p.series.push_back(
          {common.empty() ? b.name + " (" + b.axis + ")" : b.name, sp.mean, sp.ciLow, sp.ciHigh});
    }
    f.panels.push_back(std::move(p));
  }
  return f;
}

} // namespace dtf::session
