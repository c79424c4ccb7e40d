// SPDX-License-Identifier: GPL-3.0-or-later
// `dtfabric profile TRACTS... --scalar S -o OUT.tsv`: tract profiles (tractometry) as DIPY afq_profile and
// pyAFQ compute them (ui/session/tract_profiles.h over surfaces/analyses/tract_profile.h): one tidy table,
// optionally its JSON on stdout and a figure (render/profile_plot.h).
#include "app/cli/commands.h"
#include "app/command/options.h"
#include "io/formats/atomic_file.h"
#include "io/model/error.h"
#include "render/profile_plot.h"
#include "ui/session/tract_files.h"
#include "ui/session/tract_profiles.h"

#include <cstdio>
#include <fstream>

namespace dtf::app {

const OptionTable& profileOptions() {
  using O = CliOption;
  static const OptionTable table = [] {
    const surfaces::ProfileOptions po;
    OptionTable t;
    t.command = "profile";
    t.positionals = "TRACTS...";
    t.maxPositionals = OptionTable::kAnyNumber;
    t.intro =
        "Tract profiles (tractometry), as DIPY's afq_profile and pyAFQ compute them. Each tract file\n"
        "(.tck, .trk, .trk.gz, .trx, .vtk, .vtp), or each of its groups with --groups, is a bundle,\n"
        "named by the file's stem or the group. Its streamlines are oriented alike (flipped to agree\n"
        "with the bundle's first streamline, as DIPY orient_by_streamline; with --start, to start at the\n"
        "end nearer the region's centre), resampled to N nodes equally spaced by arc length, and every\n"
        "scalar is sampled at each node in world space (trilinear in the image's own voxel grid, the\n"
        "voxels outside it counting as 0, as DIPY values_from_volume). Per node: the mean over the\n"
        "streamlines weighted by --weights (gauss: DIPY gaussian_weights, each streamline's weight 1 /\n"
        "its Mahalanobis distance from the node's mean position, normalised per node; mean: equal\n"
        "weights; median: the plain median), the weighted standard deviation, a 95% interval from a\n"
        "seeded bootstrap over the streamlines, the core's position (the weighted mean of the node\n"
        "positions) and the streamline count.\n"
        "\n"
        "OUT.tsv is one tidy table, the header first: bundle scalar node x y z mean sd ci_low ci_high\n"
        "streamlines (tab-separated, NaN where a node has no value), read as it is by pandas and R.";
    t.options = {
        O::list("scalar", "S",
                "fa, md, ad or rd (of --tensor), or NAME=IMAGE: any scalar image on any grid, NAME written "
                "as it is "
                "(repeat the option or list several)")
            .required(),
        O::text("output", "OUT.tsv", "the tidy table (atomic; never over an input)").required(),
        O::text("groups", "all|G[,G...]",
                "profile the groups of each file (TRX groups) as bundles: all of them, or those named"),
        O::text("tensor", "T", "the tensor file, or a DWI fitted on the fly, of fa, md, ad and rd"),
        O::integer("nodes", "N", po.nodes, closedRange(2, 100000), "nodes along each bundle"),
        O::choice("weights", "W", {"gauss", "mean", "median"}, "gauss",
                  "how the streamlines are averaged at a node"),
        O::text(
            "start", "SPEC",
            "start every streamline at its end nearer this region's centre: X,Y,Z or a sphere X,Y,Z,R (world "
            "RAS mm); default: agree with the bundle's first streamline"),
        O::text("plot", "OUT.png|OUT.svg",
                "a figure: a panel per scalar, each bundle a line with its 95% band"),
        O::integer("bootstrap", "B", po.bootstrap, closedRange(0, 100000),
                   "bootstrap resamples for the interval (0: none, the interval is NaN)")
            .hidden(),
        O::integer("seed", "S", static_cast<int>(po.seed), closedRange(0, 2147483647), "the bootstrap's seed")
            .hidden(),
        layoutOption(LayoutNames::Tensor).alsoSays(" of --tensor").hidden(),
        O::text("bval", "F", "--tensor is a DWI: fit its tensors with this FSL b-value table (with --bvec)")
            .hidden(),
        O::text("bvec", "F", "the DWI's gradient directions (with --bval)").hidden(),
        O::text("mask", "M", "fit the DWI's tensors only where M is non-zero (same grid as the DWI)")
            .hidden(),
        O::flag("force", "overwrite existing outputs"),
        O::flag("json", "print the table's rows and the bundles' facts as JSON (-o is then optional)"),
    };
    return t;
  }();
  return table;
}

int cmdProfile(const CommandArgs& argv) {
  ParsedOptions args(profileOptions(), argv);
  if (args.printHelpIfAsked()) return 0;
  session::ProfileRequest r;
  r.tracts = args.positionals();
  r.scalars = args.list("scalar");
  const auto output = args.get("output");
  r.groups = args.text("groups");
  r.tensor = args.text("tensor");
  r.options.nodes = args.integer("nodes");
  const std::string weights = args.text("weights");
  r.options.weights = weights == "mean"     ? surfaces::ProfileWeights::Mean
                      : weights == "median" ? surfaces::ProfileWeights::Median
                                            : surfaces::ProfileWeights::Gauss;
  r.start = args.text("start");
  const auto plot = args.get("plot");
  r.options.bootstrap = args.integer("bootstrap");
  r.options.seed = static_cast<std::uint64_t>(args.integer("seed"));
  r.layout = args.text("layout");
  r.tensorOptions.bval = args.text("bval");
  r.tensorOptions.bvec = args.text("bvec");
  r.tensorOptions.mask = args.text("mask");
  const bool force = args.flag("force");
  const bool json = args.flag("json");
  args.finish();
  r.tensorOptions.quiet = json;

  for (const auto& s : r.scalars)
    if (s.find('=') == std::string::npos && session::isTractFileName(s))
      throw UsageError("--scalar '" + s +
                       "' is a tract file: put TRACTS before --scalar, or end its list with -o");
  if (r.tracts.empty()) throw UsageError("missing TRACTS (one or more tract files)");
  if (!output && !json) throw UsageError("missing -o OUT.tsv");
  if (!r.start.empty()) (void)session::startPointOf(r.start); // a typo fails before any reading
  render::PlotFormat format = render::PlotFormat::Png;
  if (plot && !render::plotFormatOf(*plot, format))
    throw UsageError("--plot '" + *plot + "': the figure is written as .png or .svg");
  const std::vector<std::string> inputs = session::profileInputs(r);
  std::vector<std::string> outputs;
  for (const auto* o : {&output, &plot})
    if (*o) {
      io::refuseOverwritingInput(**o, inputs);
      if (!force && io::outputExists(**o)) throw InputError(**o + " exists (use --force to overwrite)");
      io::refuseUnwritableOutput(**o);
      outputs.push_back(**o);
    }
  io::refuseSameOutputs(outputs);

  const session::ProfileResult result = session::runProfile(r);
  {
    io::OutputBatch batch;
    std::optional<io::AtomicOutput> table, figure;
    if (output) {
      table.emplace(*output);
      std::ofstream out(table->tempPath(), std::ios::binary);
      out << session::profileTable(result);
      out.close();
      if (!out) throw InputError(*output + ": cannot write the table");
      table->commit();
    }
    if (plot) {
      figure.emplace(*plot);
      render::writeProfilePlot(session::profileFigure(result), figure->tempPath(), format, *plot);
      figure->commit();
    }
    batch.commit();
  }
  if (json) {
    std::printf("%s\n", session::profileJson(result).c_str());
    return 0;
  }
  for (const auto& b : result.bundles)
    std::printf("%s: %zu streamlines (%zu flipped%s), %d nodes, %s\n", b.name.c_str(), b.profile.streamlines,
                b.profile.flipped,
                b.profile.skipped
                    ? (", " + std::to_string(b.profile.skipped) + " without length left out").c_str()
                    : "",
                r.options.nodes, b.axis.c_str());
  if (output) std::printf("table: %s\n", output->c_str());
  if (plot) std::printf("plot: %s\n", plot->c_str());
  return 0;
}

} // namespace dtf::app
