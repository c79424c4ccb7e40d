// SPDX-License-Identifier: GPL-3.0-or-later
// `dtfabric info TRACTS`: a tractogram's format, header facts (space, voxel order, dimensions, affine),
// streamline and point counts, length statistics, per-streamline/per-point data with their shapes and
// ranges, and groups. Text for people, --json for scripts.
#include "app/cli/commands.h"
#include "app/command/options.h"
#include "io/formats/json.h"
#include "io/model/error.h"
#include "ui/session/tract_files.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

namespace dtf::app {

namespace {

using Json = nlohmann::ordered_json;

struct Stats {
  double min = 0, max = 0, mean = 0, median = 0;
};

Stats statsOf(std::vector<double> v) {
  Stats s;
  if (v.empty()) return s;
  double sum = 0;
  for (double x : v)
    sum += x;
  s.mean = sum / static_cast<double>(v.size());
  auto mid = v.begin() + static_cast<long>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  s.median = *mid;
  if (v.size() % 2 == 0) s.median = 0.5 * (s.median + *std::max_element(v.begin(), mid));
  auto [lo, hi] = std::minmax_element(v.begin(), v.end());
  s.min = *lo;
  s.max = *hi;
  return s;
}

// Null when there was nothing to measure (no streamline), as a score of 0 would be read as a measurement.
Json statsJson(const Stats& s, bool measured) {
  if (!measured) return nullptr;
  return {{"min", s.min}, {"mean", s.mean}, {"median", s.median}, {"max", s.max}};
}

} // namespace

const OptionTable& tractInfoOptions() {
  static const OptionTable table = [] {
    OptionTable t;
    t.command = "info";
    t.positionals = "TRACTS";
    t.maxPositionals = 1;
    t.intro =
        "Describes a tractogram (.tck, .trk, .trk.gz, .trx zip or folder, .vtk, .vtp) as dtfabric reads\n"
        "it into world RAS mm: format, header facts (space, voxel order, dimensions, affine), streamline\n"
        "and point counts, streamline lengths in mm, per-streamline (dps) and per-point (dpv) data with\n"
        "shapes and ranges, and groups with their sizes.";
    t.options = {CliOption::flag("json", "one JSON object; keys include streamlines, points, dps, dpv and groups (names)")};
    return t;
  }();
  return table;
}

namespace {

// What `info TRACTS` reports besides the file's own facts.
struct TractSummary {
  Stats length, pointsPerLine;
  glm::vec3 lo{std::numeric_limits<float>::max()}, hi{std::numeric_limits<float>::lowest()}; // bounds, mm
};

TractSummary summarise(const Polylines& lines) {
  std::vector<double> lengths, counts;
  lengths.reserve(lines.lineCount());
  counts.reserve(lines.lineCount());
  for (std::size_t l = 0; l < lines.lineCount(); ++l) {
    double len = 0;
    for (std::uint32_t i = lines.offsets[l] + 1; i < lines.offsets[l + 1]; ++i)
      len += glm::length(glm::dvec3(lines.points[i]) - glm::dvec3(lines.points[i - 1]));
    lengths.push_back(len);
    counts.push_back(lines.offsets[l + 1] - lines.offsets[l]);
  }
  TractSummary s;
  s.length = statsOf(lengths);
  s.pointsPerLine = statsOf(counts);
  for (const auto& p : lines.points)
    s.lo = glm::min(s.lo, p), s.hi = glm::max(s.hi, p);
  return s;
}

// The finite range of a data array.
std::pair<double, double> valueRange(const TractValues& d) {
  float a = std::numeric_limits<float>::infinity(), b = -a;
  for (float v : d.values)
    if (std::isfinite(v)) a = std::min(a, v), b = std::max(b, v);
  return {a, b};
}

std::string fmtRange(double a, double b) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%g .. %g", a, b);
  return buf;
}

void gridJson(Json& o, const Grid& g) {
  o["dimensions"] = {g.dims.x, g.dims.y, g.dims.z};
  o["voxel_size"] = {g.spacing.x, g.spacing.y, g.spacing.z};
  o["orientation"] = g.orientationCode();
  Json affine = Json::array();
  for (int r = 0; r < 4; ++r)
    affine.push_back({g.voxelToWorld[0][r], g.voxelToWorld[1][r], g.voxelToWorld[2][r], g.voxelToWorld[3][r]});
  o["affine"] = affine;
}

void dataJson(Json& o, const Polylines& lines) {
  auto names = [&](const auto& items) {
    Json n = Json::array();
    for (const auto& d : items)
      n.push_back(d.name);
    return n;
  };
  o["dps"] = names(lines.perLine);
  o["dpv"] = names(lines.perPoint);
  o["groups"] = names(lines.groups);
  Json data = Json::array();
  for (int per = 0; per < 2; ++per)
    for (const auto& d : per ? lines.perPoint : lines.perLine) {
      const auto [a, b] = valueRange(d);
      const std::size_t items = d.values.size() / static_cast<std::size_t>(d.components);
      data.push_back({{"name", d.name},
                      {"per", per ? "point" : "streamline"},
                      {"shape", {items, d.components}},
                      {"min", a},
                      {"max", b}});
    }
  o["data"] = data;
  Json sizes = Json::object();
  for (const auto& g : lines.groups)
    sizes[g.name] = g.lines.size();
  o["group_sizes"] = sizes;
}

std::string tractsJson(const std::string& path, const session::TractFileFacts& facts, const Polylines& lines,
                       const TractSummary& s) {
  Json o = {{"file", path},
            {"format", facts.format},
            {"streamlines", lines.lineCount()},
            {"points", lines.points.size()},
            {"declared_count", facts.declaredCount}};
  Json header = Json::object();
  for (const auto& [k, v] : facts.fields)
    header[k] = v;
  o["header"] = header;
  if (facts.grid) gridJson(o, *facts.grid);
  o["length_mm"] = statsJson(s.length, lines.lineCount() > 0);
  o["points_per_streamline"] = statsJson(s.pointsPerLine, lines.lineCount() > 0);
  if (!lines.points.empty())
    o["bounds_mm"] = {{s.lo.x, s.lo.y, s.lo.z}, {s.hi.x, s.hi.y, s.hi.z}};
  dataJson(o, lines);
  return io::jsonText(o) + "\n";
}

std::string tractsText(const std::string& path, const session::TractFileFacts& facts, const Polylines& lines,
                       const TractSummary& s) {
  std::ostringstream o;
  char buf[256];
  o << path << "\n  format:        " << facts.format << "\n";
  for (const auto& [k, v] : facts.fields) {
    std::snprintf(buf, sizeof buf, "  %-14s %s\n", (k + ":").c_str(), v.c_str());
    o << buf;
  }
  if (facts.grid) {
    const Grid& g = *facts.grid;
    std::snprintf(buf, sizeof buf, "  dimensions:    %d x %d x %d, voxel %g x %g x %g mm, orientation %s\n",
                  g.dims.x, g.dims.y, g.dims.z, g.spacing.x, g.spacing.y, g.spacing.z, g.orientationCode().c_str());
    o << buf << "  affine:\n";
    for (int r = 0; r < 4; ++r) {
      std::snprintf(buf, sizeof buf, "    %10.4f %10.4f %10.4f %10.4f\n", g.voxelToWorld[0][r],
                    g.voxelToWorld[1][r], g.voxelToWorld[2][r], g.voxelToWorld[3][r]);
      o << buf;
    }
  }
  std::snprintf(buf, sizeof buf, "  streamlines:   %zu%s\n  points:        %zu\n", lines.lineCount(),
                facts.declaredCount >= 0 && static_cast<std::size_t>(facts.declaredCount) != lines.lineCount()
                    ? (" (header says " + std::to_string(facts.declaredCount) + ")").c_str()
                    : "",
                lines.points.size());
  o << buf;
  const Stats& len = s.length;
  if (lines.lineCount() == 0) {
    o << "  length (mm):   none (no streamline)\n";
  } else {
    std::snprintf(buf, sizeof buf, "  length (mm):   min %.2f  mean %.2f  median %.2f  max %.2f\n", len.min,
                  len.mean, len.median, len.max);
    o << buf;
    std::snprintf(buf, sizeof buf, "  points/line:   min %.0f  mean %.1f  max %.0f\n", s.pointsPerLine.min,
                  s.pointsPerLine.mean, s.pointsPerLine.max);
    o << buf;
  }
  if (!lines.points.empty()) {
    std::snprintf(buf, sizeof buf, "  bounds (mm):   [%.2f %.2f %.2f] .. [%.2f %.2f %.2f]\n", s.lo.x, s.lo.y, s.lo.z,
                  s.hi.x, s.hi.y, s.hi.z);
    o << buf;
  }
  for (int per = 0; per < 2; ++per)
    for (const auto& d : per ? lines.perPoint : lines.perLine) {
      const auto [a, b] = valueRange(d);
      const std::string range = a <= b ? fmtRange(a, b) : std::string("none (no finite value)");
      std::snprintf(buf, sizeof buf, "  %s '%s': %zu x %d, range %s\n", per ? "dpv" : "dps", d.name.c_str(),
                    d.values.size() / static_cast<std::size_t>(d.components), d.components, range.c_str());
      o << buf;
    }
  for (const auto& g : lines.groups)
    o << "  group '" << g.name << "': " << g.lines.size() << " streamlines\n";
  return o.str();
}

} // namespace

int cmdTractInfo(const CommandArgs& argv) {
  ParsedOptions args(tractInfoOptions(), argv);
  if (args.printHelpIfAsked()) return 0;
  const std::string path = args.positional(0, "TRACTS (see --help)");
  const bool json = args.flag("json");
  args.finish();

  session::TractFileFacts facts;
  const Polylines lines = session::readTracts(path, &facts);
  const TractSummary summary = summarise(lines);
  std::fputs((json ? tractsJson(path, facts, lines, summary) : tractsText(path, facts, lines, summary)).c_str(),
             stdout);
  return 0;
}

} // namespace dtf::app
