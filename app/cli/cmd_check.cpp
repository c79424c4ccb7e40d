// `dtfabric check`: the orientation check of a DWI's gradient table or a tensor file's frame (see
// surfaces/analyses/orientation_check.h and app/check_run.h).
#include "app/cli/commands.h"
#include "app/cli/options.h"
#include "ui/session/check_run.h"
#include "ui/session/fibre_input.h"
#include "io/formats/atomic_file.h"
#include "io/model/error.h"
#include "io/formats/png_io.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
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

std::string jsonString(const std::string& s) {
  std::string o = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') o += '\\';
    if (static_cast<unsigned char>(c) < 0x20) continue;
    o += c;
  }
  return o + "\"";
}

void printJson(const session::CheckRun& run, const std::string& input) {
  const surfaces::OrientationReport& r = run.report;
  std::printf("{\"input\": %s, \"kind\": \"%s\", \"frame\": \"%s\", \"verdict\": \"%s\", \"reason\": %s,\n",
              jsonString(input).c_str(),
              run.dwi      ? "dwi"
              : run.fibres ? "fibres"
                           : "tensor",
              run.frameName.c_str(), surfaces::verdictName(r.verdict), jsonString(r.reason).c_str());
  if (!run.dwi) std::printf(" \"layout\": %s,\n", jsonString(run.layoutNote).c_str());
  std::printf(" \"correction\": %s, \"correction_name\": \"%s\",\n", matrixJson(r.correction).c_str(),
              r.correction.name().c_str());
  std::printf(
      " \"score_given\": %.6f, \"score_best\": %.6f, \"margin\": %.6f, \"best\": \"%s\", \"runner_up\": "
      "\"%s\",\n",
      r.scoreGiven, r.scoreBest, r.margin, r.candidates[r.best].transform.name().c_str(),
      r.candidates[r.runnerUp].transform.name().c_str());
  std::printf(" \"mask_voxels\": %zu, \"white_matter_voxels\": %zu, \"white_matter_rule\": %s,\n",
              r.maskVoxels, r.whiteMatterVoxels, jsonString(r.whiteMatterRule).c_str());
  std::printf(
      " \"thresholds\": {\"fa\": %.3f, \"cos\": %.3f, \"min_white_matter\": %zu, \"min_margin\": %.4f},\n",
      r.options.faThreshold, r.options.cosThreshold, r.options.minWhiteMatter, r.options.minMargin);
  std::printf(" \"seconds\": {\"load\": %.4f, \"fit\": %.4f, \"check\": %.4f},\n", run.loadSeconds,
              run.fitSeconds, run.checkSeconds);
  std::printf(" \"candidates\": [");
  for (std::size_t i = 0; i < r.candidates.size(); ++i) {
    const auto& c = r.candidates[i];
    std::printf("%s\n  {\"name\": \"%s\", \"matrix\": %s, \"score\": %.6f, \"pairs\": %zu}", i ? "," : "",
                c.transform.name().c_str(), matrixJson(c.transform).c_str(), c.score, c.pairs);
  }
  std::printf("]}\n");
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
        O::text("bval", "F",
                "the gradient table (FSL, with --bvec; bvec 3xN or Nx3, frame: voxel axes, x negated when "
                "det(affine) > 0). Every diffusion-weighted direction must be a unit vector"),
        O::text("bvec", "F", "the gradient directions beside --bval"),
        O::text("mask", "M", "fit and score only inside M (same grid); default: the fit's automatic mask"),
        O::text("layout", "L",
                "layout override: tensor files (fsl, mrtrix, symmatrix, dtitk) or fibre sets (mrtrix-peaks, "
                "dipy-peaks, bedpostx)",
                "auto"),
        O::text("tensor", "F", "fibre sets: a tensor on the same grid whose FA selects the white matter"),
        O::flag("json",
                "one JSON object: verdict, correction (M, 3x3 row-major), score_given, score_best, margin, "
                "candidates (matrix, score), mask and white-matter voxel counts, the white-matter rule, "
                "thresholds; tensor files and fibre sets: the layout and why"),
        O::text("sheet", "OUT.png",
                "contact sheet: the fabric on the axial slice through the callosal body, the coronal slice "
                "through the corticospinal tracts and the midline sagittal slice (radiological), for the given "
                "table and the two best others, labelled with transform and score (DWIs and tensor files; not "
                "drawn for fibre sets)"),
        O::integer("sheet-size", "PX", 320, closedRange(64, 2048), "edge of each contact-sheet panel in pixels")
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
  req.fibres = req.bval.empty() && req.bvec.empty() && session::isFibreInput(req.input, layoutText, true);
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
  for (const std::string& out : {sheet, fix}) {
    if (out.empty()) continue;
    io::refuseOverwritingInput(out, inputs);
    if (!force && fs::exists(out)) throw InputError(out + " exists (use --force to replace it)");
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

  if (!fix.empty()) {
    if (run.report.verdict == surfaces::Verdict::Inconclusive && !force)
      throw InputError("the check is inconclusive (" + run.report.reason + "): not writing " + fix +
                       " (use --force to write the best-scoring table anyway)");
    const surfaces::AxisTransform m = run.report.verdict == surfaces::Verdict::Inconclusive
                                          ? run.report.candidates[run.report.best].transform
                                          : run.report.correction;
    session::writeCorrectedBvec(fix, run.bvecs, m);
    std::fprintf(stderr, "wrote %s (%s applied to %s)\n", fix.c_str(), m.name().c_str(),
                 run.bvecPath.c_str());
  }
  if (!sheet.empty()) {
    const Image img = session::renderContactSheet(run, session::sheetRows(run.report), panelPx);
    io::writePng(sheet, img);
    std::fprintf(stderr, "wrote %s (%dx%d)\n", sheet.c_str(), img.width, img.height);
  }
  return 0;
}

} // namespace dtf::app
