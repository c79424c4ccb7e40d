// SPDX-License-Identifier: GPL-3.0-or-later
#include "ui/session/check_run.h"

#include "ui/session/fibre_input.h"
#include "ui/session/surface_spec.h"
#include "ui/session/tensor_input.h"
#include "io/formats/atomic_file.h"
#include "io/diffusion/dwi.h"
#include "io/model/error.h"
#include "render/text.h"
#include "render/camera.h"
#include "render/fabric_renderer.h"
#include "render/gl_context.h"
#include "surfaces/slices.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

namespace dtf::session {

namespace {

constexpr double kB0Threshold = 50.0; // s/mm^2, as `dtfabric fit`

double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

std::string gridText(const Grid& g) {
  return std::to_string(g.dims.x) + "x" + std::to_string(g.dims.y) + "x" + std::to_string(g.dims.z);
}

MaskVolume readMaskOn(const std::string& path, const Grid& grid, const std::string& dataPath) {
  ScalarVolume m;
  try {
    m = io::readScalarVolume(path);
  } catch (...) {
    rethrowWithContext("while reading mask " + path);
  }
  if (m.components != 1)
    throw InputError(path + ": a mask must be 3D; it has " + std::to_string(m.components) + " volumes");
  double affineDiff = 0;
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      affineDiff = std::max(affineDiff, std::abs(m.grid.voxelToWorld[c][r] - grid.voxelToWorld[c][r]));
  if (m.grid.dims != grid.dims || affineDiff > 1e-3)
    throw InputError(
        path + ": the mask is on another grid (" + gridText(m.grid) +
        (m.grid.dims == grid.dims ? ", affine differs by " + std::to_string(affineDiff) + " mm" : "") +
        ") than " + dataPath + " (" + gridText(grid) + ")");
  MaskVolume mask(m.grid, 1, 0);
  for (std::size_t i = 0; i < m.data.size(); ++i)
    mask.data[i] = m.data[i] != 0 && std::isfinite(m.data[i]) ? 1 : 0;
  return mask;
}

} // namespace

CheckRun runCheck(const CheckRequest& r) {
  namespace fs = std::filesystem;
  CheckRun run;
  const auto t0 = std::chrono::steady_clock::now();
  if (r.fibres) {
    if (!r.bval.empty() || !r.bvec.empty())
      throw UsageError("--bval/--bvec apply to a DWI, not to a fibre set");
    FibreInput in = loadFibreInput(r.input, r.fibreLayout.empty() ? "auto" : r.fibreLayout, r.tensor, true);
    run.fibres = true;
    const io::FibreLayout layout = in.fibres.layout;
    run.layoutNote = std::string(io::fibreLayoutName(layout)) + " layout: " + in.fibres.layoutReason;
    run.frameName = layout == io::FibreLayout::MrtrixPeaks ? "world"
                    : layout == io::FibreLayout::Bedpostx  ? "fsl"
                                                           : "voxel";
    run.tableToWorld = io::fibreFrameToWorld(in.fibres.set.grid, layout);
    if (!r.mask.empty()) run.mask = readMaskOn(r.mask, in.fibres.set.grid, r.input);
    run.loadSeconds = secondsSince(t0);
    const auto t1 = std::chrono::steady_clock::now();
    run.report = surfaces::checkFibreOrientation(in.fibres.set, run.tableToWorld,
                                                 run.mask.data.empty() ? nullptr : &run.mask,
                                                 in.tensor ? &in.fa : nullptr, r.options);
    run.checkSeconds = secondsSince(t1);
    run.field = std::move(in.carrier);
    return run;
  }
  if (!r.tensor.empty()) throw UsageError("--tensor applies to a fibre set INPUT");
  std::string bval = r.bval, bvec = r.bvec;
  bool dwi = !bval.empty() || !bvec.empty();
  if (!dwi) {
    const io::VolumeHeader h = io::readHeader(r.input);
    dwi = h.dims.size() == 4 && h.dims[3] > 1 && h.dims[3] != 6 && h.intentCode != 1005;
  }
  if (dwi && r.layout != io::TensorLayout::Auto)
    throw UsageError("--layout applies to tensor files, not to a DWI");
  if (!dwi) {
    io::LoadedTensors t = io::readTensorVolume(r.input, r.layout);
    run.layoutNote = std::string(io::layoutName(t.layout)) + " layout: " + t.layoutReason;
    run.field = std::move(t.field);
    run.tableToWorld = glm::dmat3(1.0);
    run.frameName = "world";
    if (!r.mask.empty()) run.mask = readMaskOn(r.mask, run.field.grid, r.input);
    run.loadSeconds = secondsSince(t0);
  } else {
    if (bval.empty()) bval = io::gradientSibling(r.input, ".bval");
    if (bvec.empty()) bvec = io::gradientSibling(r.input, ".bvec");
    if (!fs::exists(bval))
      throw InputError(r.input + ": no b-value file (looked for " + bval + "; give --bval)");
    if (!fs::exists(bvec))
      throw InputError(r.input + ": no gradient file (looked for " + bvec + "; give --bvec)");
    run.dwi = true;
    run.bvalPath = bval;
    run.bvecPath = bvec;
    run.frameName = "bvec";
    ScalarVolume signal = io::readScalarVolume(r.input);
    run.bvals = io::readBvals(bval);
    run.bvecs = io::readBvecs(bvec);
    if (run.bvals.size() != run.bvecs.size())
      throw InputError(bval + " holds " + std::to_string(run.bvals.size()) + " b-values but " + bvec +
                       " holds " + std::to_string(run.bvecs.size()) + " directions");
    if (static_cast<std::size_t>(signal.components) != run.bvals.size())
      throw InputError(r.input + " has " + std::to_string(signal.components) + " volumes but " + bval +
                       " holds " + std::to_string(run.bvals.size()) + " b-values");
    std::size_t weighted = 0;
    for (std::size_t n = 0; n < run.bvals.size(); ++n) {
      if (!(run.bvals[n] > kB0Threshold)) continue;
      ++weighted;
      const glm::dvec3& g = run.bvecs[n];
      const double norm = glm::length(g);
      if (!std::isfinite(norm) || std::abs(norm - 1.0) > 0.1) {
        char buf[160];
        std::snprintf(buf, sizeof buf, ": direction %zu (b = %g s/mm^2) has length %g, not a unit vector", n,
                      run.bvals[n], norm);
        throw InputError(bvec + buf +
                         " (the check needs unit directions; multi-shell tables encoded in the "
                         "vector length are not supported)");
      }
    }
    if (weighted == 0)
      throw InputError(bval +
                       ": every volume is b=0 (b <= " + std::to_string(static_cast<int>(kB0Threshold)) +
                       " s/mm^2): there is no gradient direction to check");
    io::Dwi d = io::makeDwi(std::move(signal), run.bvals, run.bvecs, kB0Threshold, r.input, bval, bvec);
    run.meanB0 = meanLowestB(d);
    if (!r.mask.empty()) run.mask = readMaskOn(r.mask, d.signal.grid, r.input);
    run.tableToWorld = io::bvecFrameToWorld(d.signal.grid);
    run.loadSeconds = secondsSince(t0);
    const auto t1 = std::chrono::steady_clock::now();
    io::FitOptions fo;
    fo.b0Threshold = kB0Threshold;
    fo.threads = r.fitThreads;
    try {
      run.field = io::fitTensors(d, run.mask.data.empty() ? nullptr : &run.mask, fo);
    } catch (...) {
      rethrowWithContext("while fitting " + r.input);
    }
    run.fitSeconds = secondsSince(t1);
  }
  const auto t2 = std::chrono::steady_clock::now();
  run.report = surfaces::checkOrientation(run.field, run.tableToWorld,
                                          run.mask.data.empty() ? nullptr : &run.mask, r.options);
  run.checkSeconds = secondsSince(t2);
  return run;
}

void writeCorrectedBvec(const std::string& path, const std::vector<glm::dvec3>& bvecs,
                        const surfaces::AxisTransform& m) {
  std::vector<glm::dvec3> out(bvecs.size());
  for (std::size_t n = 0; n < bvecs.size(); ++n) {
    const glm::dvec3& g = bvecs[n];
    const bool finite = std::isfinite(g.x) && std::isfinite(g.y) && std::isfinite(g.z);
    // Integer matrix entries: the product is exact, so a corrected table differs from the true one only in
    // the signs and order of the printed digits.
    out[n] = finite ? m.apply(g) : g;
  }
  io::AtomicOutput file(path);
  {
    std::ofstream os(file.tempPath());
    if (!os) throw InputError(path + ": cannot write the corrected table");
    for (int row = 0; row < 3; ++row) {
      for (std::size_t n = 0; n < out.size(); ++n) {
        char buf[40];
        const double v = out[n][row] == 0 ? 0.0 : out[n][row]; // no "-0"
        std::snprintf(buf, sizeof buf, "%s%.10g", n ? " " : "", v);
        os << buf;
      }
      os << "\n";
    }
    os.flush();
    if (!os) throw InputError(path + ": writing the corrected table failed");
  }
  file.commit();
}

std::vector<std::size_t> sheetRows(const surfaces::OrientationReport& report, std::size_t count) {
  std::vector<std::size_t> order(report.candidates.size());
  for (std::size_t i = 0; i < order.size(); ++i)
    order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return report.candidates[a].score > report.candidates[b].score;
  });
  std::vector<std::size_t> rows{0};
  for (std::size_t i : order)
    if (rows.size() < count && i != 0) rows.push_back(i);
  return rows;
}

namespace {

// The contact sheet's text: 10 pixels to the em per font scale.
render::FontSize sheetFont(int fontScale) {
  return render::FontSize(10.0 * fontScale);
}

} // namespace

SheetLayout sheetLayout(int panelPx) {
  SheetLayout l;
  l.panel = panelPx;
  l.fontScale = panelPx >= 180 ? 2 : 1;
  const render::FontSize font = sheetFont(l.fontScale);
  const int line = render::textHeight(font) + render::textDescent(font);
  l.header = line * 2 + 6 * l.fontScale;
  l.label = line + 6 * l.fontScale;
  return l;
}

Image renderContactSheet(const CheckRun& run, const std::vector<std::size_t>& rows, int panelPx,
                         bool headlessContext) {
  using surfaces::SliceAxis;
  const surfaces::OrientationReport& rep = run.report;
  const TensorField bestField =
      surfaces::transformedField(run.field, run.tableToWorld, rep.candidates[rep.best].transform);
  const MaskVolume* mask = run.mask.data.empty() ? nullptr : &run.mask;
  const surfaces::EvidenceSlices slices =
      surfaces::chooseEvidenceSlices(bestField, mask, rep.options.faThreshold);
  const ScalarVolume fa = computeFaMap(run.field); // the same for every candidate (FA is rotation invariant)

  struct Column {
    const char* axis;
    int index;
  };
  const std::array<Column, 3> columns{
      {{"axial", slices.axial}, {"coronal", slices.coronal}, {"sagittal", slices.sagittal}}};
  std::array<Mesh, 3> meshes;
  for (std::size_t c = 0; c < columns.size(); ++c) {
    SurfaceSpec spec;
    spec.kind = SurfaceSpec::Kind::Slice;
    spec.axis = columns[c].axis;
    spec.index = columns[c].index;
    meshes[c] = buildSurface(spec, run.field, fa);
  }

  const SheetLayout layout = sheetLayout(panelPx);
  const int scale = layout.fontScale, header = layout.header, label = layout.label;
  Image sheet(panelPx * 3, header + static_cast<int>(rows.size()) * (label + panelPx));
  render::fillRect(sheet, 0, 0, sheet.width, sheet.height, 0, 0, 0);
  char text[160];
  std::snprintf(text, sizeof text, "verdict %s  margin %.1f%%  WM %zu vox",
                surfaces::verdictName(rep.verdict), 100 * rep.margin, rep.whiteMatterVoxels);
  const render::FontSize font = sheetFont(scale);
  const int line = render::textHeight(font) + render::textDescent(font);
  render::drawText(sheet, 4 * scale, 2 * scale, text, font, 255, 255, 255);
  for (std::size_t c = 0; c < columns.size(); ++c) {
    std::snprintf(text, sizeof text, "%s %d", columns[c].axis, columns[c].index);
    render::drawText(sheet, static_cast<int>(c) * panelPx + 4 * scale, 4 * scale + line, text, font, 200, 200,
                     200);
  }

  if (headlessContext) render::GlContext::headless();
  render::FabricRenderer renderer;
  renderer.resize(panelPx, panelPx);
  render::FabricParams params;
  params.look = render::Look::Plain; // the evidence is the threads, in every tissue
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const surfaces::CandidateScore& cand = rep.candidates[rows[r]];
    const TensorField field = surfaces::transformedField(run.field, run.tableToWorld, cand.transform);
    const int y0 = header + static_cast<int>(r) * (label + panelPx);
    const bool given = rows[r] == 0;
    std::snprintf(text, sizeof text, "%s[%s]  score %.3f%s", given ? "given " : "",
                  cand.transform.name().c_str(), cand.score, rows[r] == rep.best ? "  best" : "");
    const bool highlight = rows[r] == rep.best;
    render::drawText(sheet, 4 * scale, y0 + 3 * scale, text, font, 255, highlight ? 255 : 200,
                     highlight ? 120 : 200);
    renderer.setField(field);
    for (std::size_t c = 0; c < columns.size(); ++c) {
      renderer.setMesh(meshes[c]);
      glm::vec3 lo, hi;
      meshes[c].bounds(lo, hi);
      const render::Camera camera = render::Camera::standard(
          render::parseView(columns[c].axis), glm::dvec3(lo), glm::dvec3(hi), 1.0, false, true);
      const Image panel = renderer.renderStill(camera, params);
      for (int y = 0; y < panelPx; ++y)
        for (int x = 0; x < panelPx; ++x) {
          const std::uint8_t* src = panel.pixel(x, y);
          std::uint8_t* dst = sheet.pixel(static_cast<int>(c) * panelPx + x, y0 + label + y);
          dst[0] = src[0];
          dst[1] = src[1];
          dst[2] = src[2];
          dst[3] = 255;
        }
    }
  }
  return sheet;
}

} // namespace dtf::session
