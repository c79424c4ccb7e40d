// SPDX-License-Identifier: GPL-3.0-or-later
// `dtfabric convert IN OUT`: any supported tractogram to any other (.tck, .trk, .trk.gz, .trx, .vtk, .vtp),
// keeping per-streamline/per-point data and groups where the target can hold them (warnings say what is
// dropped). .trk and .trx need a reference space: the source's own header when it has one, else
// --reference (a NIfTI image, or a .trk/.trx whose header is used).
#include "app/cli/commands.h"
#include "app/command/options.h"
#include "ui/session/tract_files.h"
#include "io/formats/atomic_file.h"
#include "io/model/error.h"

#include <cstdio>
#include <filesystem>

namespace dtf::app {

const OptionTable& convertOptions() {
  using O = CliOption;
  static const OptionTable table = [] {
    OptionTable t;
    t.command = "convert";
    t.positionals = "IN OUT";
    t.maxPositionals = 2;
    t.intro =
        "Converts a tractogram between .tck, .trk, .trk.gz, .trx (zip or folder in, zip out), .vtk (legacy)\n"
        "and .vtp (XML). Coordinates stay in world RAS mm; per-streamline and per-point data and groups are\n"
        "kept where the target format holds them, and a warning names what is dropped. The output is written\n"
        "atomically and never over an input.";
    t.options = {
        O::text("reference", "IMAGE",
                "the space (dims, affine) a .trk/.trx output is written on: a NIfTI image, or a .trk/.trx file "
                "whose header is used; default: IN's header when it has one"),
        O::flag("force", "overwrite an existing OUT"),
    };
    return t;
  }();
  return table;
}

int cmdConvert(const CommandArgs& argv) {
  ParsedOptions args(convertOptions(), argv);
  if (args.printHelpIfAsked()) return 0;
  const std::string in = args.positional(0, "IN (see --help)");
  const std::string out = args.positional(1, "OUT (see --help)");
  const auto reference = args.get("reference");
  const bool force = args.flag("force");
  args.finish();
  if (!session::isTractFileName(out))
    throw UsageError("OUT '" + out + "' has no tract file extension (.tck, .trk, .trk.gz, .trx, .vtk, .vtp)");
  io::refuseOverwritingInput(out, {in, reference.value_or("")});
  if (!force && io::outputExists(out)) throw InputError(out + " exists (use --force to overwrite)");

  session::TractFileFacts facts;
  const Polylines lines = session::readTracts(in, &facts);
  std::optional<Grid> grid = reference ? std::optional<Grid>(session::referenceGridOf(*reference)) : facts.grid;
  session::writeTracts(out, lines, grid ? &*grid : nullptr);
  std::printf(
      "%s: %zu streamlines, %zu points, %zu per-streamline and %zu per-point arrays, %zu groups -> %s\n",
      in.c_str(), lines.lineCount(), lines.points.size(), lines.perLine.size(), lines.perPoint.size(),
      lines.groups.size(), out.c_str());
  return 0;
}

} // namespace dtf::app
