// SPDX-License-Identifier: GPL-3.0-or-later
#include "ui/session/bids_participant.h"

#include "ui/session/check_run.h"
#include "ui/session/render_job.h"
#include "ui/session/surface_spec.h"
#include "ui/session/web_page.h"
#include "io/formats/atomic_file.h"
#include "io/formats/json.h"
#include "io/model/error.h"
#include "io/formats/png_io.h"
#include "render/camera.h"
#include "render/fabric_renderer.h"
#include "render/figure_furniture.h"
#include "render/gl_context.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

namespace fs = std::filesystem;

namespace dtf::session {

namespace {

constexpr double kWhiteMatterFa = 0.3; // as the orientation check's white matter
constexpr double kIsoFa =
    0.4; // the FA isosurface of the 3D views: the white-matter core (0.25 wraps the cortex)

double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

double median(std::vector<double> v) {
  if (v.empty()) return std::nan("");
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

double mean(const std::vector<double>& v) {
  if (v.empty()) return std::nan("");
  double s = 0;
  for (double x : v)
    s += x;
  return s / static_cast<double>(v.size());
}

std::string paramsText(const ParticipantOptions& o) {
  return "dtfabric " + o.version + "; figure " + std::to_string(o.figurePx) + " px; sheet panel " +
         std::to_string(o.sheetPanelPx) + " px; wm fa>=0.3; iso fa=0.4" +
         (o.webPx > 0 ? "; web " + std::to_string(o.webPx) + " px" : "");
}

// Removes the temporary siblings a killed run left beside this run's outputs (io::AtomicOutput names them
// ".<target>.tmp<pid>_<n>…"). Only this run's derivative names match: "sub-01_desc-fabric…" is not a prefix
// of another run's "sub-01_acq-x_desc-fabric…", which a parallel worker may be writing in the same folder.
void removeStaleTemporaries(const fs::path& dir, const std::string& stem) {
  std::error_code ec;
  const std::string prefix = "." + stem + "_desc-fabric";
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    const std::string name = e.path().filename().string();
    if (name.rfind(prefix, 0) == 0 && name.find(".tmp") != std::string::npos) fs::remove_all(e.path(), ec);
  }
}

void render(render::FabricRenderer& renderer, const Mesh& mesh, const std::string& view,
            const std::string& path) {
  renderer.setMesh(mesh);
  glm::vec3 lo, hi;
  mesh.bounds(lo, hi);
  const render::Camera camera =
      render::Camera::standard(render::parseView(view), glm::dvec3(lo), glm::dvec3(hi), 1.0, false, true);
  render::FabricParams params;
  Image img = renderer.renderStill(camera, params);
  render::drawFurniture(img, camera, renderer.frameView().pixelMm, {});
  io::writePng(path, img);
}

} // namespace

const std::vector<FigureKind>& figureKinds() {
  static const std::vector<FigureKind> kinds = {
      {"fabricAxial", "axial slice through the corpus callosum"},
      {"fabricCoronal", "coronal slice through the corticospinal tracts"},
      {"fabricIsoLeft", "FA 0.4 isosurface from the left"},
      {"fabricIsoSuperior", "FA 0.4 isosurface from above"},
      {"fabricCheck", "orientation check contact sheet"},
  };
  return kinds;
}

std::string metricsPath(const io::BidsRun& run, const std::string& outputRoot) {
  return (fs::path(outputRoot) / run.relDir / io::derivativeName(run, "fabricMetrics", "dwi", ".json"))
      .string();
}

namespace {

// Hashes of the run's files; a run whose files cannot be read fails here with the file named.
void hashInputs(const io::BidsRun& run, nlohmann::ordered_json& doc) {
  std::error_code ec;
  try {
    doc["input_hash_dwi"] = io::fileHash(run.dwi);
    if (fs::exists(run.bval, ec)) doc["input_hash_bval"] = io::fileHash(run.bval);
    if (fs::exists(run.bvec, ec)) doc["input_hash_bvec"] = io::fileHash(run.bvec);
  } catch (const std::exception& e) {
    doc["status"] = "failed";
    doc["message"] = e.what();
  }
}

// True (with `out` filled) when the metrics document at docPath is complete for the same parameters and
// inputs, and its figures exist.
bool completeAndUnchanged(const nlohmann::ordered_json& doc, const std::string& docPath, const fs::path& dir,
                          RunOutcome& out) {
  std::error_code ec;
  try {
    const nlohmann::ordered_json old = io::readJsonFile(docPath);
    bool complete = io::jsonString(old, "status") == "ok";
    for (const char* k : {"params", "input_hash_dwi", "input_hash_bval", "input_hash_bvec"})
      complete = complete && io::jsonString(old, k) == io::jsonString(doc, k);
    for (const auto& f : figureKinds())
      if (old.contains(std::string("figure_") + f.desc))
        complete = complete && fs::exists(dir / io::jsonString(old, std::string("figure_") + f.desc), ec);
    if (old.contains("web_page")) complete = complete && fs::exists(dir / io::jsonString(old, "web_page"), ec);
    if (!complete) return false;
    out.ok = true;
    out.skipped = true;
    out.verdict = io::jsonString(old, "check_verdict");
    out.message = "complete and unchanged";
    return true;
  } catch (const Error&) {
    return false; // an unreadable document is recomputed
  }
}

// Metrics over the white matter: valid voxels of the fit (its automatic brain mask) with FA >= 0.3; the
// orientation check's verdict and scores; the grid.
void setMetrics(const CheckRun& check, const MetricMaps& maps, nlohmann::ordered_json& doc) {
  const surfaces::OrientationReport& rep = check.report;
  std::vector<double> fa, md;
  std::size_t brain = 0;
  for (std::size_t i = 0; i < check.field.valid.size(); ++i) {
    if (!check.field.valid[i]) continue;
    ++brain;
    if (maps.fa.data[i] < kWhiteMatterFa) continue;
    fa.push_back(maps.fa.data[i]);
    md.push_back(maps.md.data[i] * 1e3); // 10^-3 mm^2/s
  }
  doc["fa_wm_mean"] = mean(fa);
  doc["fa_wm_median"] = median(fa);
  doc["md_wm_mean"] = mean(md);
  doc["md_wm_median"] = median(md);
  doc["md_units"] = "1e-3 mm^2/s";
  doc["wm_voxels"] = fa.size();
  doc["brain_voxels"] = brain;
  doc["wm_fraction"] = brain ? static_cast<double>(fa.size()) / static_cast<double>(brain) : 0;
  doc["check_verdict"] = surfaces::verdictName(rep.verdict);
  doc["check_correction"] = rep.correction.name();
  doc["check_best"] = rep.candidates[rep.best].transform.name();
  doc["check_score_given"] = rep.scoreGiven;
  doc["check_score_best"] = rep.scoreBest;
  doc["check_margin"] = rep.margin;
  doc["check_reason"] = rep.reason;
  const Grid& g = check.field.grid;
  doc["grid"] = std::to_string(g.dims.x) + "x" + std::to_string(g.dims.y) + "x" + std::to_string(g.dims.z) + " " +
                g.orientationCode();
  doc["volumes"] = check.bvals.size();
}

// The surfaces of the figures (desc, mesh, in figureKinds() order). Slice positions come from this run's
// data, not fixed indices: surfaces::chooseEvidenceSlices on the field the best-scoring table gives (left-
// right white matter counts need the right axes). Axial: the slice with the most left-right white matter
// near the midline (the callosal body); coronal: the slice with the most superior-inferior white matter
// (the corticospinal tracts in the internal capsules).
std::vector<std::pair<std::string, Mesh>> figureMeshes(const CheckRun& check, const MetricMaps& maps,
                                                       nlohmann::ordered_json& doc) {
  const surfaces::OrientationReport& rep = check.report;
  const TensorField best =
      surfaces::transformedField(check.field, check.tableToWorld, rep.candidates[rep.best].transform);
  const surfaces::EvidenceSlices slices = surfaces::chooseEvidenceSlices(best, nullptr, kWhiteMatterFa);
  doc["slice_axial"] = slices.axial;
  doc["slice_coronal"] = slices.coronal;
  SurfaceSpec axial, coronal, iso;
  axial.kind = coronal.kind = SurfaceSpec::Kind::Slice;
  axial.axis = "axial";
  axial.index = slices.axial;
  coronal.axis = "coronal";
  coronal.index = slices.coronal;
  iso.kind = SurfaceSpec::Kind::Fa;
  iso.value = kIsoFa;
  std::vector<std::pair<std::string, Mesh>> meshes;
  SurfaceBuildOptions figure;
  figure.dataEdgeCells = true;                 // the smooth data edge
  figure.clipToData = check.meanB0.data.empty(); // a DWI's slices cover the grid: its mean b=0 image around the data
  meshes.emplace_back("fabricAxial", buildSurface(axial, check.field, maps.fa, figure));
  meshes.emplace_back("fabricCoronal", buildSurface(coronal, check.field, maps.fa, figure));
  meshes.emplace_back("fabricIso", buildSurface(iso, check.field, maps.fa, figure));
  return meshes;
}

// The figures show the data with its given table (what a user of the data would see); the contact sheet
// shows the candidates side by side.
void writeFigures(const io::BidsRun& run, const fs::path& dir, const ParticipantOptions& o, const CheckRun& check,
                  const std::vector<std::pair<std::string, Mesh>>& meshes, nlohmann::ordered_json& doc) {
  render::GlContext::headless();
  render::FabricRenderer renderer;
  renderer.resize(o.figurePx, o.figurePx);
  renderer.setField(check.field);
  // The anatomy beneath (as `render` shows a DWI): the mean b=0 image of the fit, else FA.
  Background b0;
  b0.volume = check.meanB0;
  if (!b0.volume.data.empty() && windowByPercentiles(b0)) renderer.setBackground(&b0.volume, b0.lo, b0.hi);
  const std::vector<std::pair<std::string, std::pair<std::size_t, std::string>>> figures = {
      {"fabricAxial", {0, "axial"}},
      {"fabricCoronal", {1, "coronal"}},
      {"fabricIsoLeft", {2, "left"}},
      {"fabricIsoSuperior", {2, "superior"}}};
  for (const auto& [desc, how] : figures) {
    const std::string name = io::derivativeName(run, desc, "dwi", ".png");
    render(renderer, meshes[how.first].second, how.second, (dir / name).string());
    doc["figure_" + desc] = name;
  }
  if (check.report.verdict != surfaces::Verdict::Ok) {
    const std::string name = io::derivativeName(run, "fabricCheck", "dwi", ".png");
    const Image sheet = renderContactSheet(check, sheetRows(check.report), o.sheetPanelPx);
    io::writePng((dir / name).string(), sheet);
    doc["figure_fabricCheck"] = name;
  }
}

// The run's web page (dtfabric web) beside its figures, when asked for.
void writeRunWebPage(const io::BidsRun& run, const fs::path& dir, const ParticipantOptions& o, const CheckRun& check,
                     nlohmann::ordered_json& doc) {
  if (o.webPx <= 0) return;
  const std::string name = io::derivativeName(run, "fabricWeb", "dwi", "");
  WebPageRequest web;
  web.input = run.dwi;
  web.field = &check.field;
  web.size = o.webPx;
  web.output = (dir / name).string();
  web.force = true;
  web.title = run.stem;
  const WebPageResult written = writeWebPage(web);
  doc["web_page"] = name + "/index.html";
  doc["seconds_web"] = written.seconds;
}

// The check, metrics and figures of one run into `doc` (status ok), or its failure (status failed, the
// message naming the run's file when the error does not).
void analyseRun(const io::BidsRun& run, const fs::path& dir, const ParticipantOptions& o,
                std::chrono::steady_clock::time_point t0, nlohmann::ordered_json& doc, RunOutcome& out) {
  try {
    CheckRequest req;
    req.input = run.dwi;
    req.bval = run.bval;
    req.bvec = run.bvec;
    req.fitThreads = o.fitThreads;
    CheckRun check = runCheck(req);
    const surfaces::OrientationReport& rep = check.report;
    const MetricMaps maps = computeMetricMaps(check.field, false, false);
    setMetrics(check, maps, doc);
    const auto tf = std::chrono::steady_clock::now();
    writeFigures(run, dir, o, check, figureMeshes(check, maps, doc), doc);
    writeRunWebPage(run, dir, o, check, doc);
    doc["seconds_load"] = check.loadSeconds;
    doc["seconds_fit"] = check.fitSeconds;
    doc["seconds_check"] = check.checkSeconds;
    doc["seconds_figures"] = secondsSince(tf);
    doc["seconds_total"] = secondsSince(t0);
    doc["status"] = "ok";
    doc["message"] = std::string("verdict ") + surfaces::verdictName(rep.verdict) + ": " + rep.reason;
    out.verdict = surfaces::verdictName(rep.verdict);
  } catch (const std::bad_alloc&) {
    doc["status"] = "failed";
    doc["message"] = run.dwi + ": out of memory";
  } catch (const std::exception& e) {
    doc["status"] = "failed";
    const std::string what = e.what();
    // Errors name their file; add the run's when one does not.
    doc["message"] = what.find(fs::path(run.dwi).filename().string()) == std::string::npos &&
                             what.find(".bv") == std::string::npos
                         ? run.dwi + ": " + what
                         : what;
  }
}

} // namespace

RunOutcome processRun(const io::BidsRun& run, const std::string& outputRoot, const ParticipantOptions& optIn) {
  ParticipantOptions o = optIn;
  if (o.sheetPanelPx <= 0) o.sheetPanelPx = std::max(96, o.figurePx / 2);
  const auto t0 = std::chrono::steady_clock::now();
  const fs::path dir = fs::path(outputRoot) / run.relDir;
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw InputError("cannot create " + dir.string() + ": " + ec.message());
  removeStaleTemporaries(dir, run.stem);
  const std::string docPath = metricsPath(run, outputRoot);

  nlohmann::ordered_json doc;
  doc["source"] = fs::path(run.dwi).filename().string();
  doc["participant_id"] = "sub-" + run.subject;
  doc["session_id"] = run.session.empty() ? "n/a" : "ses-" + run.session;
  doc["dtfabric_version"] = o.version;
  doc["params"] = paramsText(o);
  RunOutcome out;
  hashInputs(run, doc);
  if (!o.force && !doc.contains("status") && fs::exists(docPath, ec) && completeAndUnchanged(doc, docPath, dir, out)) {
    out.seconds = secondsSince(t0);
    return out;
  }

  if (!doc.contains("status") && !run.problem.empty()) {
    doc["status"] = "failed";
    doc["message"] = run.dwi + ": " + run.problem;
  }
  if (!doc.contains("status")) analyseRun(run, dir, o, t0, doc, out);
  out.ok = io::jsonString(doc, "status") == "ok";
  out.message = io::jsonString(doc, "message");
  io::writeTextIfChanged(docPath, io::jsonText(doc, 2) + "\n"); // last: the run is complete once this exists
  out.seconds = secondsSince(t0);
  return out;
}

io::GroupRow readGroupRow(const io::BidsRun& run, const std::string& outputRoot) {
  io::GroupRow row;
  row.participant = "sub-" + run.subject;
  row.session = run.session.empty() ? "" : "ses-" + run.session;
  row.run = run.stem;
  row.metrics.assign(io::groupMetricColumns().size(), std::nan(""));
  const std::string path = metricsPath(run, outputRoot);
  std::error_code ec;
  if (!fs::exists(path, ec)) {
    row.message = "not processed: no " + path + " (run the participant level for sub-" + run.subject + ")";
    return row;
  }
  nlohmann::ordered_json doc;
  try {
    doc = io::readJsonFile(path);
  } catch (const Error& e) {
    row.message = e.what();
    return row;
  }
  if (!doc.is_object()) {
    row.message = path + ": not a JSON object (a metrics document)";
    return row;
  }
  row.ok = io::jsonString(doc, "status") == "ok";
  row.message = io::jsonString(doc, "message");
  row.verdict = io::jsonString(doc, "check_verdict");
  row.correction = io::jsonString(doc, "check_correction");
  row.seconds = io::jsonNumber(doc, "seconds_total");
  for (std::size_t c = 0; c < row.metrics.size(); ++c)
    row.metrics[c] = io::jsonNumber(doc, io::groupMetricColumns()[c]);
  const fs::path rel = fs::path(run.relDir);
  for (const auto& f : figureKinds()) {
    const std::string name = io::jsonString(doc, std::string("figure_") + f.desc);
    if (!name.empty()) row.figures.push_back({f.caption, (rel / name).generic_string()});
  }
  if (doc.contains("web_page")) row.webPage = (rel / io::jsonString(doc, "web_page")).generic_string();
  return row;
}

} // namespace dtf::session
