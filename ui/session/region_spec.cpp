// SPDX-License-Identifier: GPL-3.0-or-later
#include "ui/session/region_spec.h"

#include "io/formats/atomic_file.h"
#include "io/formats/json.h"
#include "io/formats/tensor_io.h"
#include "io/model/error.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

namespace fs = std::filesystem;

namespace dtf::session {

using surfaces::Region;
using surfaces::RegionKind;
using surfaces::RegionSet;
using surfaces::RegionShape;

namespace {

// Comma-separated finite numbers; false when a part is not one.
bool parseNumbers(const std::string& text, std::vector<double>& out) {
  out.clear();
  std::stringstream ss(text);
  std::string part;
  while (std::getline(ss, part, ',')) {
    const char* b = part.data();
    const char* e = b + part.size();
    while (b < e && *b == ' ')
      ++b;
    double v = 0;
    auto [ptr, ec] = std::from_chars(b, e, v);
    if (ec != std::errc() || ptr != e || b == e) return false;
    out.push_back(v);
  }
  if (!text.empty() && text.back() == ',') return false;
  return !out.empty();
}

bool parseLabels(const std::string& text, std::vector<int>& out) {
  out.clear();
  std::stringstream ss(text);
  std::string part;
  while (std::getline(ss, part, ',')) {
    int v = 0;
    auto [ptr, ec] = std::from_chars(part.data(), part.data() + part.size(), v);
    if (ec != std::errc() || ptr != part.data() + part.size() || part.empty()) return false;
    out.push_back(v);
  }
  if (!text.empty() && text.back() == ',') return false;
  return !out.empty();
}

std::string number(double v) {
  // The shortest text that reads back to v, in plain notation where that is shorter (20, not 2e+01).
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

bool isFile(const std::string& path) {
  std::error_code ec;
  return !path.empty() && fs::exists(path, ec);
}

// The mask of an image's non-zero voxels, or of the voxels holding one of `labels`.
Region maskRegion(const std::string& spec, const std::string& image, const std::vector<int>& labels) {
  ScalarVolume v;
  try {
    v = io::readScalarVolume(image);
  } catch (const InputError& e) {
    throw InputError("region '" + spec + "': " + e.what());
  }
  auto mask = std::make_shared<MaskVolume>(v.grid, 1);
  const std::size_t n = v.grid.voxelCount();
  const std::size_t stride = static_cast<std::size_t>(v.components);
  std::set<int> wanted(labels.begin(), labels.end()), found;
  for (std::size_t i = 0; i < n; ++i) {
    const float x = v.data[i * stride];
    if (!std::isfinite(x) || x == 0.0f) continue;
    if (labels.empty()) {
      mask->data[i] = 1;
      continue;
    }
    const double r = std::round(static_cast<double>(x));
    if (r != static_cast<double>(x) || r < std::numeric_limits<int>::min() || r > std::numeric_limits<int>::max())
      continue;
    if (wanted.count(static_cast<int>(r))) {
      mask->data[i] = 1;
      found.insert(static_cast<int>(r));
    }
  }
  for (int l : labels)
    if (!found.count(l))
      throw InputError("region '" + spec + "': label " + std::to_string(l) + " is not in " + image);
  Region r;
  r.shape = RegionShape::Mask;
  r.mask = std::move(mask);
  r.image = image;
  r.labels = labels;
  return r;
}

} // namespace

Region parseRegionSpec(const std::string& spec, RegionKind kind) {
  Region r;
  std::vector<double> v;
  if (spec.rfind("box:", 0) == 0) {
    if (!parseNumbers(spec.substr(4), v) || v.size() != 6)
      throw InputError("region '" + spec + "': a box is box:X0,Y0,Z0,X1,Y1,Z1 (six numbers, world RAS mm)");
    r.shape = RegionShape::Box;
    r.lo = {v[0], v[1], v[2]};
    r.hi = {v[3], v[4], v[5]};
  } else if (parseNumbers(spec, v)) {
    if (v.size() != 4)
      throw InputError("region '" + spec + "': a sphere is X,Y,Z,R (four numbers, world RAS mm), not " +
                       std::to_string(v.size()));
    r.shape = RegionShape::Sphere;
    r.centre = {v[0], v[1], v[2]};
    r.radius = v[3];
  } else if (isFile(spec)) {
    r = maskRegion(spec, spec, {});
  } else {
    const auto colon = spec.rfind(':');
    std::vector<int> labels;
    if (colon != std::string::npos && colon > 0 && isFile(spec.substr(0, colon)) &&
        parseLabels(spec.substr(colon + 1), labels))
      r = maskRegion(spec, spec.substr(0, colon), labels);
    else if (colon != std::string::npos && colon > 0 && isFile(spec.substr(0, colon)))
      throw InputError("region '" + spec + "': the labels after ':' must be integers separated by commas");
    else
      throw InputError("region '" + spec +
                       "': not a sphere X,Y,Z,R, a box:X0,Y0,Z0,X1,Y1,Z1, or an image file (no such file)");
  }
  r.kind = kind;
  r.name = spec;
  surfaces::validate(r);
  return r;
}

std::string regionSpecOf(const Region& r) {
  switch (r.shape) {
  case RegionShape::Sphere:
    return number(r.centre.x) + "," + number(r.centre.y) + "," + number(r.centre.z) + "," + number(r.radius);
  case RegionShape::Box:
    return "box:" + number(r.lo.x) + "," + number(r.lo.y) + "," + number(r.lo.z) + "," + number(r.hi.x) + "," +
           number(r.hi.y) + "," + number(r.hi.z);
  case RegionShape::Mask: {
    std::string s = r.image;
    for (std::size_t i = 0; i < r.labels.size(); ++i)
      s += (i ? "," : ":") + std::to_string(r.labels[i]);
    return s;
  }
  }
  return "";
}

// ---- the region set file

namespace {

constexpr const char* kFormat = "dtfabric-regions";
constexpr int kVersion = 1;

[[noreturn]] void bad(const std::string& origin, const std::string& what) {
  throw InputError(origin + ": " + what);
}

glm::dvec3 triple(const nlohmann::ordered_json& j, const std::string& origin, const std::string& where) {
  if (!j.is_array() || j.size() != 3) bad(origin, where + " must be an array of three numbers");
  glm::dvec3 v;
  for (int i = 0; i < 3; ++i) {
    if (!j[static_cast<std::size_t>(i)].is_number()) bad(origin, where + " must be an array of three numbers");
    v[i] = j[static_cast<std::size_t>(i)].get<double>();
  }
  return v;
}

bool flagOf(const nlohmann::ordered_json& doc, const char* key, const std::string& origin) {
  if (!doc.contains(key)) return false;
  if (!doc[key].is_boolean()) bad(origin, std::string("\"") + key + "\" must be true or false");
  return doc[key].get<bool>();
}

} // namespace

RegionSet parseRegionSet(const std::string& text, const std::string& origin, const std::string& folder) {
  const nlohmann::ordered_json doc = io::parseJson(text, origin);
  if (!doc.is_object()) bad(origin, "not a region set (a region set file holds one JSON object)");
  for (const auto& [key, value] : doc.items())
    if (key != "format" && key != "version" && key != "ends_only" && key != "precise" && key != "regions")
      bad(origin, "unknown member \"" + key + "\" (a region set has format, version, ends_only, precise, regions)");
  if (io::jsonString(doc, "format") != kFormat) bad(origin, std::string("not a region set (\"format\" must be \"") + kFormat + "\")");
  if (!doc.contains("version") || !doc["version"].is_number_integer())
    bad(origin, "\"version\" must be an integer");
  const auto version = doc["version"].get<long long>();
  if (version != kVersion)
    bad(origin, "region set version " + std::to_string(version) + " is not supported (this dtfabric reads version " +
                    std::to_string(kVersion) + ")");
  RegionSet set;
  set.endsOnly = flagOf(doc, "ends_only", origin);
  set.precise = flagOf(doc, "precise", origin);
  if (!doc.contains("regions") || !doc["regions"].is_array()) bad(origin, "\"regions\" must be an array");
  std::size_t n = 0;
  for (const auto& j : doc["regions"]) {
    const std::string where = "region " + std::to_string(n++);
    if (!j.is_object()) bad(origin, where + " is not an object");
    const std::string shape = io::jsonString(j, "shape"), kindText = io::jsonString(j, "kind");
    static const std::map<std::string, std::set<std::string>> kMembers = {
        {"sphere", {"centre", "radius"}}, {"box", {"min", "max"}}, {"mask", {"image", "labels"}}};
    const auto known = kMembers.find(shape);
    if (known == kMembers.end()) bad(origin, where + ": \"shape\" must be sphere, box or mask");
    for (const auto& [key, value] : j.items())
      if (key != "shape" && key != "kind" && key != "name" && key != "visible" && !known->second.count(key))
        bad(origin, where + ": unknown member \"" + key + "\" for a " + shape);
    RegionKind kind;
    if (kindText == "include")
      kind = RegionKind::Include;
    else if (kindText == "exclude")
      kind = RegionKind::Exclude;
    else if (kindText == "include-ordered")
      kind = RegionKind::IncludeOrdered;
    else
      bad(origin, where + ": \"kind\" must be include, exclude or include-ordered");
    if (j.contains("visible") && !j["visible"].is_boolean()) bad(origin, where + ": \"visible\" must be true or false");
    if (j.contains("name") && !j["name"].is_string()) bad(origin, where + ": \"name\" must be a string");
    Region r;
    try {
      if (shape == "sphere") {
        if (!j.contains("radius") || !j["radius"].is_number()) bad(origin, where + ": \"radius\" must be a number");
        r.shape = RegionShape::Sphere;
        r.centre = triple(j.value("centre", nlohmann::ordered_json()), origin, where + ": \"centre\"");
        r.radius = j["radius"].get<double>();
      } else if (shape == "box") {
        r.shape = RegionShape::Box;
        r.lo = triple(j.value("min", nlohmann::ordered_json()), origin, where + ": \"min\"");
        r.hi = triple(j.value("max", nlohmann::ordered_json()), origin, where + ": \"max\"");
      } else {
        if (!j.contains("image") || !j["image"].is_string() || j["image"].get<std::string>().empty())
          bad(origin, where + ": \"image\" must name an image file");
        std::vector<int> labels;
        if (j.contains("labels")) {
          if (!j["labels"].is_array() || j["labels"].empty()) bad(origin, where + ": \"labels\" must be a non-empty array of integers");
          for (const auto& l : j["labels"]) {
            if (!l.is_number_integer() || l.get<long long>() < std::numeric_limits<int>::min() ||
                l.get<long long>() > std::numeric_limits<int>::max())
              bad(origin, where + ": \"labels\" must be a non-empty array of integers");
            labels.push_back(static_cast<int>(l.get<long long>()));
          }
        }
        const std::string image = j["image"].get<std::string>();
        const std::string path = fs::path(image).is_absolute() || folder.empty() ? image : (fs::path(folder) / image).string();
        if (!isFile(path)) bad(origin, where + ": the image " + path + " does not exist");
        r = maskRegion(origin + " " + where, path, labels); // r.image: the path resolved from here
      }
      r.kind = kind;
      r.name = j.contains("name") ? j["name"].get<std::string>() : regionSpecOf(r);
      surfaces::validate(r);
    } catch (const InputError& e) {
      const std::string msg = e.what();
      if (msg.rfind(origin, 0) == 0) throw;
      bad(origin, where + ": " + msg);
    }
    set.regions.push_back(std::move(r));
  }
  return set;
}

RegionSet readRegionSetFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot read the region set file");
  std::ostringstream ss;
  ss << in.rdbuf();
  if (ss.str().size() > (64u << 20)) throw InputError(path + ": a region set file of more than 64 MB is not one");
  return parseRegionSet(ss.str(), path, fs::path(path).parent_path().string());
}

std::string regionSetText(const RegionSet& set, const std::string& folder) {
  nlohmann::ordered_json doc = {{"format", kFormat}, {"version", kVersion}, {"ends_only", set.endsOnly},
                                {"precise", set.precise}};
  nlohmann::ordered_json regions = nlohmann::ordered_json::array();
  for (const Region& r : set.regions) {
    nlohmann::ordered_json j = {{"name", r.name}, {"kind", surfaces::kindName(r.kind)}, {"shape", surfaces::shapeName(r.shape)}};
    switch (r.shape) {
    case RegionShape::Sphere:
      j["centre"] = {r.centre.x, r.centre.y, r.centre.z};
      j["radius"] = r.radius;
      break;
    case RegionShape::Box:
      j["min"] = {r.lo.x, r.lo.y, r.lo.z};
      j["max"] = {r.hi.x, r.hi.y, r.hi.z};
      break;
    case RegionShape::Mask: {
      std::error_code ec;
      std::string image = r.image;
      if (!folder.empty()) {
        const fs::path rel = fs::relative(fs::absolute(r.image, ec), fs::absolute(folder, ec), ec);
        if (!ec && !rel.empty()) image = rel.string();
      }
      j["image"] = image;
      if (!r.labels.empty()) j["labels"] = r.labels;
      break;
    }
    }
    regions.push_back(std::move(j));
  }
  doc["regions"] = std::move(regions);
  return io::jsonText(doc, 2) + "\n";
}

void writeRegionSetFile(const std::string& path, const RegionSet& set) {
  const std::string text = regionSetText(set, fs::path(path).parent_path().string());
  io::AtomicOutput out(path);
  {
    std::ofstream f(out.tempPath(), std::ios::binary);
    f << text;
    if (!f.flush()) throw InputError(path + ": cannot write the region set file");
  }
  out.commit();
}

} // namespace dtf::session
