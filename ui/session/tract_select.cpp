// SPDX-License-Identifier: GPL-3.0-or-later
#include "ui/session/tract_select.h"

#include "io/formats/atomic_file.h"
#include "io/formats/mapped_tck.h"
#include "io/model/error.h"
#include "io/model/log.h"
#include "surfaces/selection/tract_selection.h"
#include "ui/session/tract_files.h"

#include <algorithm>
#include <chrono>
#include <cctype>
#include <map>
#include <memory>

namespace dtf::session {

namespace {

bool isTck(const std::string& path) {
  std::string p = path;
  std::transform(p.begin(), p.end(), p.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return p.size() >= 4 && p.compare(p.size() - 4, 4, ".tck") == 0;
}

bool isTrx(const std::string& path) {
  std::string p = path;
  std::transform(p.begin(), p.end(), p.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return p.size() >= 4 && p.compare(p.size() - 4, 4, ".trx") == 0;
}

double since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

std::string joined(const std::vector<std::string>& names) {
  std::string s;
  for (const auto& n : names)
    s += (s.empty() ? "'" : ", '") + n + "'";
  return s;
}

} // namespace

void checkSelectRequest(const SelectRequest& r) {
  if (r.inputs.empty()) throw UsageError("give at least one tract file to select from");
  if (!isTractFileName(r.output))
    throw UsageError("output '" + r.output + "' has no tract file extension (.tck, .trk, .trk.gz, .trx, .vtk, .vtp)");
  if (!r.asGroup.empty() && !isTrx(r.output))
    throw UsageError("--as-group writes a group into a TRX file: the output must end in .trx");
  std::vector<std::string> inputs = r.inputs;
  if (r.reference) inputs.push_back(*r.reference);
  for (const surfaces::Region& reg : r.regions.regions)
    if (!reg.image.empty()) inputs.push_back(reg.image);
  io::refuseOverwritingInput(r.output, inputs);
  io::refuseUnwritableOutput(r.output);
}

Polylines concatenateTracts(std::vector<Polylines> parts, const std::vector<std::string>& names) {
  if (parts.size() == 1) return std::move(parts.front());
  Polylines out;
  out.offsets.push_back(0);
  // The arrays every part holds with the same components.
  auto common = [&](auto member) {
    std::vector<std::pair<std::string, int>> keep;
    for (const TractValues& v : parts.front().*member) {
      bool all = true;
      for (std::size_t p = 1; p < parts.size() && all; ++p) {
        const auto& list = parts[p].*member;
        all = std::any_of(list.begin(), list.end(),
                          [&](const TractValues& w) { return w.name == v.name && w.components == v.components; });
      }
      if (all) keep.emplace_back(v.name, v.components);
    }
    std::vector<std::string> dropped;
    for (const Polylines& p : parts)
      for (const TractValues& v : p.*member)
        if (std::none_of(keep.begin(), keep.end(), [&](const auto& k) { return k.first == v.name; }) &&
            std::find(dropped.begin(), dropped.end(), v.name) == dropped.end())
          dropped.push_back(v.name);
    if (!dropped.empty())
      logWarning("the inputs do not all hold " + joined(dropped) + ": dropped from the concatenation");
    return keep;
  };
  const auto lineArrays = common(&Polylines::perLine), pointArrays = common(&Polylines::perPoint);
  for (const auto& [n, c] : lineArrays)
    out.perLine.push_back({n, c, {}});
  for (const auto& [n, c] : pointArrays)
    out.perPoint.push_back({n, c, {}});
  std::map<std::string, std::size_t> groupAt;
  for (std::size_t p = 0; p < parts.size(); ++p) {
    const Polylines& part = parts[p];
    const auto base = static_cast<std::uint32_t>(out.lineCount());
    const auto pointBase = static_cast<std::uint64_t>(out.points.size());
    if (pointBase + part.points.size() >= std::numeric_limits<std::uint32_t>::max())
      throw InputError(names[p] + ": the inputs together hold too many points for one tract set");
    out.points.insert(out.points.end(), part.points.begin(), part.points.end());
    for (std::size_t l = 1; l < part.offsets.size(); ++l)
      out.offsets.push_back(static_cast<std::uint32_t>(pointBase + part.offsets[l]));
    auto append = [](std::vector<TractValues>& to, const std::vector<TractValues>& from) {
      for (TractValues& t : to)
        for (const TractValues& f : from)
          if (f.name == t.name) t.values.insert(t.values.end(), f.values.begin(), f.values.end());
    };
    append(out.perLine, part.perLine);
    append(out.perPoint, part.perPoint);
    for (const TractGroup& g : part.groups) {
      auto [it, added] = groupAt.emplace(g.name, out.groups.size());
      if (added) out.groups.push_back({g.name, {}});
      for (std::uint32_t i : g.lines)
        out.groups[it->second].lines.push_back(base + i);
    }
  }
  return out;
}

std::vector<std::uint32_t> selectIndices(const Polylines& lines, const surfaces::RegionSet& set, bool indexed,
                                         int threads) {
  const surfaces::TractView view = surfaces::viewOf(lines);
  const surfaces::RegionTester tester(set);
  if (!indexed) return surfaces::selectLines(view, tester, nullptr, threads);
  const surfaces::TractIndex index(view, 0.0, threads);
  return surfaces::selectLines(view, tester, &index, threads);
}

LoadedTracts readTractInputs(const std::vector<std::string>& inputs, const std::optional<std::string>& reference) {
  LoadedTracts out;
  std::vector<Polylines> parts;
  for (const auto& in : inputs) {
    TractFileFacts facts;
    parts.push_back(readTracts(in, &facts));
    if (!out.grid && facts.grid) out.grid = facts.grid;
  }
  if (reference) out.grid = referenceGridOf(*reference);
  out.lines = concatenateTracts(std::move(parts), inputs);
  return out;
}

void writeSelection(const std::string& output, LoadedTracts& in, std::vector<std::uint32_t> keep,
                    const std::string& asGroup, const std::string& inputName) {
  const Grid* grid = in.grid ? &*in.grid : nullptr;
  if (asGroup.empty()) {
    writeTracts(output, surfaces::subsetWithGroups(in.lines, keep), grid);
    return;
  }
  auto& groups = in.lines.groups;
  if (std::any_of(groups.begin(), groups.end(), [&](const TractGroup& g) { return g.name == asGroup; }))
    throw InputError(inputName + ": already holds a group '" + asGroup + "' (choose another --as-group)");
  groups.push_back({asGroup, std::move(keep)});
  writeTracts(output, in.lines, grid);
  groups.pop_back();
}

SelectReport runSelect(const SelectRequest& r) {
  SelectReport rep;
  const surfaces::RegionTester tester(r.regions);
  const bool allTck = isTck(r.output) && r.asGroup.empty() &&
                      std::all_of(r.inputs.begin(), r.inputs.end(), [](const std::string& p) { return isTck(p); });
  if (allTck) {
    // In place: map each input, select, copy the kept streamlines' bytes.
    rep.inPlace = true;
    auto t = std::chrono::steady_clock::now();
    std::vector<std::unique_ptr<io::MappedTck>> maps;
    for (const auto& in : r.inputs)
      maps.push_back(std::make_unique<io::MappedTck>(in));
    rep.readSeconds = since(t);
    t = std::chrono::steady_clock::now();
    std::vector<std::vector<std::uint32_t>> kept(maps.size());
    for (std::size_t m = 0; m < maps.size(); ++m) {
      surfaces::TractView v;
      v.points = maps[m]->points();
      v.starts64 = maps[m]->starts().data();
      v.lineCount = maps[m]->lineCount();
      v.gap = 1;
      surfaces::SelectionStats st;
      kept[m] = surfaces::selectLines(v, tester, nullptr, r.threads, &st);
      rep.streamlines += v.lineCount;
      rep.points += v.pointCount();
      rep.candidates += st.walked;
      rep.selected += kept[m].size();
      for (std::uint32_t i : kept[m])
        rep.selectedPoints += v.size(i);
    }
    rep.selectSeconds = since(t);
    t = std::chrono::steady_clock::now();
    std::vector<const io::MappedTck*> sources;
    std::vector<const std::vector<std::uint32_t>*> lists;
    for (std::size_t m = 0; m < maps.size(); ++m) {
      sources.push_back(maps[m].get());
      lists.push_back(&kept[m]);
    }
    io::MappedTck::writeLines(r.output, sources, lists);
    rep.writeSeconds = since(t);
    return rep;
  }

  auto t = std::chrono::steady_clock::now();
  LoadedTracts in = readTractInputs(r.inputs, r.reference);
  rep.readSeconds = since(t);
  rep.streamlines = in.lines.lineCount();
  rep.points = in.lines.points.size();

  t = std::chrono::steady_clock::now();
  const surfaces::TractView view = surfaces::viewOf(in.lines);
  surfaces::SelectionStats st;
  std::vector<std::uint32_t> keep = surfaces::selectLines(view, tester, nullptr, r.threads, &st);
  rep.candidates = st.walked;
  rep.selected = keep.size();
  for (std::uint32_t i : keep)
    rep.selectedPoints += view.size(i);
  rep.selectSeconds = since(t);

  t = std::chrono::steady_clock::now();
  writeSelection(r.output, in, std::move(keep), r.asGroup, r.inputs.front());
  rep.writeSeconds = since(t);
  return rep;
}

} // namespace dtf::session
