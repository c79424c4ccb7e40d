// SPDX-License-Identifier: GPL-3.0-or-later
// `dtfabric select TRACTS... -o OUT`: ROI selection of streamlines (ui/session/tract_select.h) with
// tckedit's semantics, from regions given as flags (ui/session/region_spec.h) and/or a region set file.
#include "app/cli/commands.h"
#include "app/command/options.h"
#include "io/formats/atomic_file.h"
#include "io/formats/json.h"
#include "io/model/error.h"
#include "ui/session/region_spec.h"
#include "ui/session/tract_select.h"

#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>

namespace dtf::app {

namespace {

constexpr const char* kSpecHelp =
    "X,Y,Z,R (a sphere, world RAS mm), box:X0,Y0,Z0,X1,Y1,Z1, IMAGE (the non-zero voxels of a mask on any "
    "grid) or IMAGE:L[,L...] (the voxels of a parcellation holding one of the labels)";

} // namespace

// The region rows `select` and `track` share: each parses with session::parseRegionSpec.
std::vector<CliOption> regionOptions() {
  using O = CliOption;
  return {
      O::text("include", "SPEC",
              std::string("keep streamlines with a vertex in this region (all include regions must be hit): ") +
                  kSpecHelp)
          .repeats(),
      O::text("exclude", "SPEC", "drop streamlines with a vertex in this region").repeats(),
      O::text("include-ordered", "SPEC",
              "an include region that must be entered in the order given along the stored vertices (entering a "
              "later one before an earlier one, or an earlier one again after a later one, drops the streamline)")
          .repeats(),
  };
}

// The regions of those rows, in the order given per kind (ordered includes in theirs).
std::vector<surfaces::Region> regionsFrom(ParsedOptions& args) {
  std::vector<surfaces::Region> out;
  for (const auto& s : args.all("include"))
    out.push_back(session::parseRegionSpec(s, surfaces::RegionKind::Include));
  for (const auto& s : args.all("exclude"))
    out.push_back(session::parseRegionSpec(s, surfaces::RegionKind::Exclude));
  for (const auto& s : args.all("include-ordered"))
    out.push_back(session::parseRegionSpec(s, surfaces::RegionKind::IncludeOrdered));
  return out;
}

const OptionTable& selectOptions() {
  using O = CliOption;
  static const OptionTable table = [] {
    OptionTable t;
    t.command = "select";
    t.positionals = "TRACTS...";
    t.maxPositionals = OptionTable::kAnyNumber;
    t.intro =
        "ROI selection: keeps the streamlines of TRACTS (any tract format; several are concatenated) that pass\n"
        "through every include region and no exclude region, as MRtrix's tckedit does: the stored vertices are\n"
        "tested (a sphere holds a vertex within R of its centre, a mask the vertex whose nearest voxel is\n"
        "non-zero); --precise also tests the segments between vertices. Every vertex, every per-point and\n"
        "per-streamline value and the groups of the kept streamlines are written; .tck to .tck is selected in\n"
        "place without reading the whole file into memory.";
    t.options = {O::text("output", "OUT", "the tract file to write (.tck, .trk, .trk.gz, .trx, .vtk, .vtp)")
                     .required()};
    for (auto& o : regionOptions())
      t.options.push_back(std::move(o));
    t.options.front().group = "Output";
    t.options[1].group = "Regions (world RAS mm; give any number)";
    const std::vector<CliOption> more = {
        O::text("roi", "ROIS.json",
                "a region set file (as the viewer saves it: regions with kind, shape and parameters; ends-only "
                "and precise for the set); its regions come before those of the flags"),
        O::flag("ends-only", "test the regions on the two end points of each streamline only"),
        O::flag("precise", "also test the segments between vertices, so a region crossed between two vertices "
                           "is not missed"),
        O::number("min-length", "MM", 0, atLeast(0), "keep streamlines at least this long (arc length)")
            .measuredIn("mm")
            .under("Length (the streamlines kept; in `track`, --max-length stops tracking instead)"),
        O::number("max-length", "MM", 0, atLeast(0), "keep streamlines at most this long (arc length)")
            .measuredIn("mm")
            .noDefault(),
        O::text("as-group", "NAME",
                "write every input streamline to the .trx output, with the selection added as the group NAME")
            .under("Other"),
        O::text("reference", "IMAGE",
                "the space of a .trk/.trx output when the inputs record none: an image, or a .trk/.trx file"),
        O::integer("threads", "T", 0, atLeast(0), "worker threads").defaultSays("all cores"),
        O::flag("force", "overwrite an existing OUT"),
        O::flag("json", "print the report as one JSON object"),
    };
    t.options.insert(t.options.end(), more.begin(), more.end());
    return t;
  }();
  return table;
}

int cmdSelect(const CommandArgs& argv) {
  ParsedOptions args(selectOptions(), argv);
  if (args.printHelpIfAsked()) return 0;
  session::SelectRequest r;
  r.inputs = args.positionals();
  r.output = args.required("output");
  const auto roi = args.get("roi");
  const bool endsOnly = args.flag("ends-only"), precise = args.flag("precise");
  r.regions.minLengthMm = args.number("min-length");
  if (args.given("max-length")) r.regions.maxLengthMm = args.number("max-length");
  r.asGroup = args.text("as-group");
  r.reference = args.get("reference");
  r.threads = args.integer("threads");
  const bool force = args.flag("force"), json = args.flag("json");
  if (args.given("as-group") && r.asGroup.empty()) throw UsageError("--as-group needs a group name");
  // Flags are parsed after the usage checks so a typo in OUT fails first; regions read their images here.
  std::vector<surfaces::Region> flagged;
  if (r.inputs.empty()) throw UsageError("missing TRACTS (see --help)");
  if (roi) {
    r.regions = [&] {
      surfaces::RegionSet s = session::readRegionSetFile(*roi);
      s.minLengthMm = r.regions.minLengthMm;
      s.maxLengthMm = r.regions.maxLengthMm;
      return s;
    }();
  }
  flagged = regionsFrom(args);
  args.finish();
  r.regions.regions.insert(r.regions.regions.end(), flagged.begin(), flagged.end());
  r.regions.endsOnly = r.regions.endsOnly || endsOnly;
  r.regions.precise = r.regions.precise || precise;
  surfaces::validate(r.regions);
  session::checkSelectRequest(r);
  if (roi) io::refuseOverwritingInput(r.output, {*roi});
  if (!force && io::outputExists(r.output)) throw InputError(r.output + " exists (use --force to overwrite)");

  const session::SelectReport rep = session::runSelect(r);
  if (json) {
    nlohmann::ordered_json j = {{"output", r.output},
                                {"streamlines", rep.streamlines},
                                {"points", rep.points},
                                {"selected", rep.selected},
                                {"selected_points", rep.selectedPoints},
                                {"regions", r.regions.regions.size()},
                                {"ends_only", r.regions.endsOnly},
                                {"precise", r.regions.precise},
                                {"in_place", rep.inPlace},
                                {"read_s", rep.readSeconds},
                                {"select_s", rep.selectSeconds},
                                {"write_s", rep.writeSeconds}};
    if (!r.asGroup.empty()) j["group"] = r.asGroup;
    std::printf("%s\n", io::jsonText(j).c_str());
    return 0;
  }
  std::printf("ROI selection: %zu of %zu streamlines (%zu of %zu points) through %zu region%s%s%s -> %s%s\n",
              rep.selected, rep.streamlines, rep.selectedPoints, rep.points, r.regions.regions.size(),
              r.regions.regions.size() == 1 ? "" : "s", r.regions.endsOnly ? ", ends only" : "",
              r.regions.precise ? ", precise" : "", r.output.c_str(),
              r.asGroup.empty() ? "" : (" (as group '" + r.asGroup + "' of every streamline)").c_str());
  std::printf("read %.3f s, selected %.3f s, wrote %.3f s%s\n", rep.readSeconds, rep.selectSeconds,
              rep.writeSeconds, rep.inPlace ? " (in place)" : "");
  return 0;
}

} // namespace dtf::app
