// SPDX-License-Identifier: GPL-3.0-or-later
// `dtfabric check`: the orientation check of a DWI's gradient table or a tensor file's frame (see
// surfaces/analyses/orientation_check.h and app/check_run.h).
#include "app/cli/commands.h"
#include "app/command/options.h"
#include "ui/session/check_run.h"
#include "ui/session/fibre_input.h"
#include "io/formats/atomic_file.h"
#include "io/formats/json.h"
#include "io/model/error.h"
#include "io/formats/png_io.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

namespace dtf::app {

namespace {

std::string matrixJson(const surfaces::AxisTransform& t) {
  std::string s = "[";
  for (int row = 0; row < 3; ++row) {
    s += row ? ", [" : "[";
    for (int col = 0; col < 3; ++col)
      s += (col ? ", " : "") + std::to_string(t.m[static_cast<std::size_t>(row * 3 + col)]);
    s += "]";
  }
  return s + "]";
}

nlohmann::ordered_json matrix(const surfaces::AxisTransform& t) {
  nlohmann::ordered_json m = nlohmann::ordered_json::array();
  for (std::size_t row = 0; row < 3; ++row)
    m.push_back({t.m[row * 3], t.m[row * 3 + 1], t.m[row * 3 + 2]});
  return m;
}

void printJson(const session::CheckRun& run, const std::string& input) {
  const surfaces::OrientationReport& r = run.report;
  nlohmann::ordered_json j = {{"input", input},
                              {"kind", run.dwi ? "dwi" : run.fibres ? "fibres" : "tensor"},
                              {"frame", run.frameName},
                              {"verdict", surfaces::verdictName(r.verdict)},
                              {"reason", r.reason}};
  if (!run.dwi) j["layout"] = run.layoutNote;
  j["correction"] = matrix(r.correction);
  j["correction_name"] = r.correction.name();
  j["score_given"] = r.scoreGiven;
  j["score_best"] = r.scoreBest;
  j["margin"] = r.margin;
  j["best"] = r.candidates[r.best].transform.name();
  j["runner_up"] = r.candidates[r.runnerUp].transform.name();
  j["mask_voxels"] = r.maskVoxels;
  j["white_matter_voxels"] = r.whiteMatterVoxels;
  j["white_matter_rule"] = r.whiteMatterRule;
  j["thresholds"] = {{"fa", r.options.faThreshold},
                     {"cos", r.options.cosThreshold},
                     {"min_white_matter", r.options.minWhiteMatter},
                     {"min_margin", r.options.minMargin}};
  j["seconds"] = {{"load", run.loadSeconds}, {"fit", run.fitSeconds}, {"check", run.checkSeconds}};
  nlohmann::ordered_json candidates = nlohmann::ordered_json::array();
  for (const auto& c : r.candidates)
    candidates.push_back(
        {{"name", c.transform.name()}, {"matrix", matrix(c.transform)}, {"score", c.score}, {"pairs", c.pairs}});
  j["candidates"] = candidates;
  std::printf("%s\n", io::jsonText(j).c_str());
}

void printText(const session::CheckRun& run, const std::string& input) {
  const surfaces::OrientationReport& r = run.report;
  const Grid& g = run.field.grid;
  if (run.dwi)
    std::printf("%s: DWI %dx%dx%d (%s), table %s, WLS fit %.3f s\n", input.c_str(), g.dims.x, g.dims.y,
                g.dims.z, g.orientationCode().c_str(), run.bvecPath.c_str(), run.fitSeconds);
  else if (run.fibres)
    std::printf("%s: fibre set %dx%dx%d (%s), %s; candidates act on the %s frame\n", input.c_str(), g.dims.x,
                g.dims.y, g.dims.z, g.orientationCode().c_str(), run.layoutNote.c_str(),
                run.frameName.c_str());
  else
    std::printf("%s: tensors %dx%dx%d (%s), %s; candidates act on world RAS\n", input.c_str(), g.dims.x,
                g.dims.y, g.dims.z, g.orientationCode().c_str(), run.layoutNote.c_str());
  std::printf("voxels: %zu %s, %zu white matter (%s)\n", r.maskVoxels,
              run.fibres ? "with fibres in the mask" : "in the mask", r.whiteMatterVoxels,
              r.whiteMatterRule.c_str());
  std::printf("thresholds: inconclusive below %zu white-matter voxels or a margin below %.1f%% "
              "(|cos| > %.3f)\n",
              r.options.minWhiteMatter, 100 * r.options.minMargin, r.options.cosThreshold);
  std::printf("score = coherent neighbour pairs per white-matter voxel (check %.1f ms):\n",
              1e3 * run.checkSeconds);
  std::vector<std::size_t> order(r.candidates.size());
  for (std::size_t i = 0; i < order.size(); ++i)
    order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return r.candidates[a].score > r.candidates[b].score;
  });
  for (std::size_t i : order)
    std::printf("  %-10s %.4f%s\n", r.candidates[i].transform.name().c_str(), r.candidates[i].score,
                i == 0 ? "  (given)" : "");
  std::printf("verdict: %s: %s\n", surfaces::verdictName(r.verdict), r.reason.c_str());
  std::printf("correction: %s (%s)%s\n", matrixJson(r.correction).c_str(), r.correction.name().c_str(),
              run.dwi      ? "  corrected bvec = M * given bvec"
              : run.fibres ? "  true stored direction = M * direction as read (stored frame)"
                           : "  corrected D = M D M^T (world)");
}

} // namespace

const OptionTable& checkOptions() {
  using O = CliOption;
  static const OptionTable table = [] {
    const surfaces::CheckOptions co;
    OptionTable t;
    t.command = "check";
    t.positionals = "INPUT";
    t.maxPositionals = 1;
    t.intro =
        "Checks the orientation of the diffusion directions: a gradient table with an axis negated or swapped, or a\n"
        "tensor file read in the wrong layout or frame, leaves DEC colours unchanged but turns every direction.\n"
        "Scores each of the 24 signed axis permutations of the table (a table and its negation measure the same)\n"
        "by fibre coherence (Schilling et al. 2019): the number of neighbouring white-matter voxel pairs (13\n"
        "neighbour directions) whose principal directions both lie within 30 degrees of the step between them, per\n"
        "white-matter voxel (FA >= 0.3). A DWI is fitted once (WLS); the other tables' tensors follow exactly as\n"
        "D' = G D G^T without refitting.\n"
        "\n"
        "INPUT is a DWI (4D with a volume count other than 6, or given --bval/--bvec; default tables: INPUT's\n"
        "sibling .bval/.bvec), a tensor file (its stored directions are judged in world RAS) or a fibre set\n"
        "(mrtrix-peaks, dipy-peaks, a bedpostx folder): its first (strongest) fibre per voxel is scored with the\n"
        "candidates acting on the file's stored frame (world for mrtrix-peaks, voxel for dipy-peaks, FSL for\n"
        "bedpostx), so a file read in the wrong layout or frame is flagged with the turn between the two frames.\n"
        "White matter of a fibre set: FA >= 0.3 of the paired --tensor, else voxels with a single dominant fibre (no\n"
        "second above half the first) whose first amplitude is at least the median over all voxels with fibres.\n"
        "\n"
        "Verdict\n"
        "  ok            the given table scores best, by at least the margin threshold\n"
        "  corrected     another table scores best by at least the margin: corrected bvec = M * given bvec\n"
        "  inconclusive  too little white matter or too small a margin to say\n"
        "The thresholds are printed with every result.";
    t.options = {
        bvalOption().alsoSays("; bvec 3xN or Nx3, frame: voxel axes, x negated when det(affine) > 0. Every "
                              "diffusion-weighted direction must be a unit vector"),
        bvecOption(),
        fitMaskOption().alsoSays(", and score only there; default: the fit's automatic mask"),
        layoutOption(LayoutNames::TensorOrFibre),
        pairedTensorOption("the FA that selects the white matter"),
        O::flag("json",
                "one JSON object: verdict, correction (M, 3x3 row-major), score_given, score_best, margin, "
                "candidates (matrix, score), mask and white-matter voxel counts, the white-matter rule, "
                "thresholds; tensor files and fibre sets: the layout and why"),
        O::text(
            "sheet", "OUT.png",
            "contact sheet: the fabric on the axial slice through the callosal body, the coronal slice "
            "through the corticospinal tracts and the midline sagittal slice (radiological), for the given "
            "table and the two best others, labelled with transform and score (DWIs and tensor files; not "
            "drawn for fibre sets)"),
        O::integer("sheet-size", "PX", 320, closedRange(64, 2048),
                   "edge of each contact-sheet panel in pixels")
            .hidden(),
        O::text("fix-bvec", "OUT.bvec",
                "write the corrected FSL table (DWI only; refused when inconclusive unless --force)"),
        O::flag("force", "replace existing outputs (never an input); --fix-bvec even when inconclusive"),
        O::number("min-margin", "F", co.minMargin, closedRange(0, 10),
                  "margin below which the verdict is inconclusive (0.07 = 7%)")
            .hidden(),
        O::integer("min-white-matter", "N", static_cast<int>(co.minWhiteMatter), closedRange(1, 2147483647),
                   "white-matter voxels below which it is inconclusive")
            .hidden(),
    };
    t.epilogue = "Exit codes: 0 the check ran (whatever the verdict), 1 usage, 2 bad input, 3 GL failure (--sheet).";
    return t;
  }();
  return table;
}

int cmdCheck(const CommandArgs& argv) {
  ParsedOptions args(checkOptions(), argv);
  if (args.printHelpIfAsked()) return 0;
  session::CheckRequest req;
  req.input = args.positional(0, "INPUT (see --help)");
  req.bval = args.text("bval");
  req.bvec = args.text("bvec");
  req.mask = args.text("mask");
  const std::string layoutText = args.text("layout");
  req.tensor = args.text("tensor");
  req.fibres = req.bval.empty() && req.bvec.empty() && session::isFibreSet(req.input, layoutText);
  if (req.fibres)
    req.fibreLayout = layoutText;
  else
    req.layout = io::parseLayout(layoutText);
  req.options.minMargin = args.number("min-margin");
  req.options.minWhiteMatter = static_cast<std::size_t>(args.integer("min-white-matter"));
  const bool json = args.flag("json");
  const bool force = args.flag("force");
  const std::string sheet = args.text("sheet");
  const std::string fix = args.text("fix-bvec");
  const int panelPx = args.integer("sheet-size");
  args.finish();

  namespace fs = std::filesystem;
  const std::vector<std::string> inputs{req.input, req.bval, req.bvec, req.mask, req.tensor};
  io::refuseSameOutputs({sheet, fix});
  for (const std::string& out : {sheet, fix}) {
    if (out.empty()) continue;
    io::refuseUnwritableOutput(out);
    io::refuseOverwritingInput(out, inputs);
    if (!force && io::outputExists(out)) throw InputError(out + " exists (use --force to replace it)");
  }
  if (!sheet.empty() && !(sheet.size() > 4 && sheet.compare(sheet.size() - 4, 4, ".png") == 0))
    throw UsageError("--sheet must name a .png file, got '" + sheet + "'");

  if (req.fibres && !sheet.empty())
    throw UsageError("--sheet is drawn for DWIs and tensor files only; " + req.input +
                     " is a fibre set (use `dtfabric render` with it to look at the fibres)");
  session::CheckRun run = session::runCheck(req);
  if (!fix.empty()) {
    // Checked again now that the sibling tables are known.
    io::refuseOverwritingInput(fix, {req.input, run.bvalPath, run.bvecPath, req.mask});
    if (!run.dwi)
      throw UsageError("--fix-bvec needs a DWI with its table; " + req.input + " is " +
                       (run.fibres ? "a fibre set" : "a tensor file"));
  }
  if (json)
    printJson(run, req.input);
  else
    printText(run, req.input);
  std::fflush(stdout);

  io::OutputBatch batch; // the corrected table and the sheet together, or neither
  std::string fixNote;
  if (!fix.empty()) {
    if (run.report.verdict == surfaces::Verdict::Inconclusive && !force)
      throw InputError("the check is inconclusive (" + run.report.reason + "): not writing " + fix +
                       " (use --force to write the best-scoring table anyway)");
    const surfaces::AxisTransform m = run.report.verdict == surfaces::Verdict::Inconclusive
                                          ? run.report.candidates[run.report.best].transform
                                          : run.report.correction;
    session::writeCorrectedBvec(fix, run.bvecs, m);
    fixNote = m.name();
  }
  Image img;
  if (!sheet.empty()) {
    img = session::renderContactSheet(run, session::sheetRows(run.report), panelPx);
    io::writePng(sheet, img);
  }
  batch.commit();
  if (!fix.empty())
    std::fprintf(stderr, "wrote %s (%s applied to %s)\n", fix.c_str(), fixNote.c_str(), run.bvecPath.c_str());
  if (!sheet.empty()) std::fprintf(stderr, "wrote %s (%dx%d)\n", sheet.c_str(), img.width, img.height);
  return 0;
}

} // namespace dtf::app
