// SPDX-License-Identifier: GPL-3.0-or-later
// `dtfabric info`: describes a NIfTI volume the way the readers see it (header facts, chosen affine,
// detected tensor layout and why, value ranges, NaN/non-positive counts, FA statistics) or one voxel's
// world tensor and eigen-system. Text for people, --json for scripts (the voxel keys are a fixed interface).
#include "app/cli/commands.h"
#include "app/command/args.h"
#include "app/command/options.h"
#include "io/model/error.h"
#include "io/model/tensor.h"
#include "io/formats/formats.h"
#include "io/formats/json.h"
#include "io/formats/tensor_io.h"
#include "io/diffusion/uncertainty.h"
#include "ui/session/fibre_input.h"
#include "ui/session/tract_files.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

namespace dtf::app {

namespace {

const char* kComponentNames[6] = {"xx", "xy", "xz", "yy", "yz", "zz"};

using Json = nlohmann::ordered_json; // members in the order written; NaN and infinities print as null

Json vec(const glm::dvec3& v) {
  return Json::array({v.x, v.y, v.z});
}

void printJson(const Json& j) {
  std::printf("%s\n", io::jsonText(j).c_str());
}

// The smallest and largest value seen.
struct MinMax {
  double lo = std::numeric_limits<double>::infinity(), hi = -std::numeric_limits<double>::infinity();
  void add(double v) {
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  [[nodiscard]] bool empty() const { return lo > hi; }
};

std::string num(double v, int precision = 6) {
  if (!std::isfinite(v)) return "n/a";
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.*g", precision, v);
  return buf;
}

std::string dimsText(const std::vector<long long>& dims) {
  std::string s;
  for (std::size_t i = 0; i < dims.size(); ++i)
    s += (i ? " x " : "") + std::to_string(dims[i]);
  return s;
}

// A tensor volume by shape: 4D x 6 or 5D x 1 x 6 (trailing 1s ignored), or SYMMATRIX intent.
bool looksLikeTensor(const io::VolumeHeader& h) {
  std::vector<long long> extra(h.dims.begin() + std::min<std::ptrdiff_t>(3, std::ssize(h.dims)),
                               h.dims.end());
  while (!extra.empty() && extra.back() == 1)
    extra.pop_back();
  return h.intentCode == 1005 || (extra.size() == 1 && extra[0] == 6) ||
         (extra.size() == 2 && extra[0] == 1 && extra[1] == 6);
}

void headerJson(Json& j, const io::VolumeHeader& h) {
  j["file"] = h.path;
  j["file_format"] = h.format;
  j["format_reason"] = h.formatReason;
  j["nifti_version"] = h.niftiVersion;
  j["dims"] = h.dims;
  j["voxel_size"] = vec(h.grid.spacing);
  Json affine = Json::array();
  for (int r = 0; r < 4; ++r)
    affine.push_back({h.grid.voxelToWorld[0][r], h.grid.voxelToWorld[1][r], h.grid.voxelToWorld[2][r],
                      h.grid.voxelToWorld[3][r]});
  j["affine"] = affine;
  j["affine_source"] = h.affineSource;
  j["qform_code"] = h.qformCode;
  j["sform_code"] = h.sformCode;
  j["orientation"] = h.grid.orientationCode();
  j["datatype"] = h.datatypeName;
  j["intent_code"] = h.intentCode;
  j["intent_name"] = h.intentName;
  j["scl_slope"] = h.sclSlope;
  j["scl_inter"] = h.sclInter;
}

void headerText(const io::VolumeHeader& h) {
  std::printf("file:         %s\n", h.path.c_str());
  if (h.niftiVersion > 0)
    std::printf("format:       NIfTI-%d, datatype %s, intent %d%s\n", h.niftiVersion, h.datatypeName.c_str(),
                h.intentCode, h.intentName.empty() ? "" : (" (" + h.intentName + ")").c_str());
  else
    std::printf("format:       %s, datatype %s%s\n", h.format.c_str(), h.datatypeName.c_str(),
                h.intentName.empty() ? "" : (" (" + h.intentName + ")").c_str());
  if (!h.formatReason.empty()) std::printf("format why:   %s\n", h.formatReason.c_str());
  std::printf("dims:         %s\n", dimsText(h.dims).c_str());
  std::printf("voxel size:   %s x %s x %s mm\n", num(h.grid.spacing.x).c_str(), num(h.grid.spacing.y).c_str(),
              num(h.grid.spacing.z).c_str());
  if (h.niftiVersion > 0)
    std::printf("affine:       %s (qform_code %d, sform_code %d), voxel -> world RAS mm\n",
                h.affineSource.c_str(), h.qformCode, h.sformCode);
  else
    std::printf("affine:       %s, voxel -> world RAS mm\n", h.affineSource.c_str());
  for (int r = 0; r < 4; ++r) {
    std::printf("             ");
    for (int c = 0; c < 4; ++c) {
      double a = h.grid.voxelToWorld[c][r];
      std::printf(" %11.5f", std::abs(a) < 5e-6 ? 0.0 : a); // no "-0.00000" for tiny rounding residues
    }
    std::printf("\n");
  }
  std::printf("orientation:  %s\n", h.grid.orientationCode().c_str());
  if (!(h.sclSlope == 0 || (h.sclSlope == 1 && h.sclInter == 0)))
    std::printf("scaling:      value * %s + %s\n", num(h.sclSlope).c_str(), num(h.sclInter).c_str());
}

void warningsOut(Json* j, const std::vector<std::string>& warnings) {
  if (j) {
    (*j)["warnings"] = warnings;
    return;
  }
  for (const auto& w : warnings)
    std::printf("warning:      %s\n", w.c_str());
}

int describeTensors(const io::LoadedTensors& t, bool json) {
  const TensorField& f = t.field;
  MinMax ranges[6];
  std::vector<double> fa;
  std::size_t valid = 0;
  for (std::size_t i = 0; i < f.tensors.size(); ++i) {
    if (!f.valid[i]) continue;
    ++valid;
    auto c = f.tensors[i].components();
    for (int k = 0; k < 6; ++k)
      ranges[k].add(c[k]);
    fa.push_back(computeMetrics(eigenDecompose(f.tensors[i])).fa);
  }
  double faMean = std::numeric_limits<double>::quiet_NaN(), faMedian = faMean, faMax = faMean;
  if (!fa.empty()) {
    double sum = 0;
    for (double v : fa)
      sum += v;
    faMean = sum / double(fa.size());
    faMax = *std::max_element(fa.begin(), fa.end());
    auto mid = fa.begin() + static_cast<std::ptrdiff_t>(fa.size() / 2);
    std::nth_element(fa.begin(), mid, fa.end());
    faMedian = *mid;
  }
  if (json) {
    Json j;
    headerJson(j, t.header);
    j["is_tensor"] = true;
    j["layout"] = io::layoutName(t.layout);
    j["layout_reason"] = t.layoutReason;
    j["units"] = "mm^2/s";
    j["frame"] = "world RAS";
    j["voxels"] = f.tensors.size();
    j["valid_voxels"] = valid;
    j["nan_voxels"] = t.nanVoxels;
    j["non_positive_voxels"] = t.nonPositiveVoxels;
    Json comps = Json::object();
    for (int k = 0; k < 6; ++k)
      comps[kComponentNames[k]] = {ranges[k].empty() ? NAN : ranges[k].lo, ranges[k].empty() ? NAN : ranges[k].hi};
    j["component_ranges"] = comps;
    j["fa"] = {{"mean", faMean}, {"median", faMedian}, {"max", faMax}};
    warningsOut(&j, t.warnings);
    printJson(j);
    return 0;
  }
  headerText(t.header);
  std::printf("tensor layout: %s (%s)\n", io::layoutName(t.layout), t.layoutReason.c_str());
  std::printf("units:        mm^2/s, world RAS, components xx xy xz yy yz zz\n");
  std::printf("voxels:       %zu valid of %zu; %zu NaN/Inf; %zu not positive definite\n", valid,
              f.tensors.size(), t.nanVoxels, t.nonPositiveVoxels);
  std::printf("ranges (valid voxels):\n");
  for (int k = 0; k < 6; ++k)
    std::printf("  %s  %12s .. %-12s\n", kComponentNames[k], num(ranges[k].lo).c_str(),
                num(ranges[k].hi).c_str());
  std::printf("FA:           mean %s, median %s, max %s\n", num(faMean, 4).c_str(), num(faMedian, 4).c_str(),
              num(faMax, 4).c_str());
  warningsOut(nullptr, t.warnings);
  return 0;
}

int describeScalar(const ScalarVolume& v, const io::VolumeHeader& h, bool json) {
  std::vector<MinMax> ranges(static_cast<std::size_t>(v.components));
  std::size_t nonFinite = 0;
  for (std::size_t i = 0; i < v.data.size(); ++i) {
    float x = v.data[i];
    if (!std::isfinite(x)) {
      ++nonFinite;
      continue;
    }
    ranges[i % static_cast<std::size_t>(v.components)].add(x);
  }
  MinMax all;
  for (const auto& r : ranges)
    if (!r.empty()) all.add(r.lo), all.add(r.hi);
  if (json) {
    Json j;
    headerJson(j, h);
    j["is_tensor"] = false;
    j["components"] = v.components;
    j["value_range"] = {all.empty() ? NAN : all.lo, all.empty() ? NAN : all.hi};
    Json comps = Json::array();
    for (const auto& r : ranges)
      comps.push_back({r.empty() ? NAN : r.lo, r.empty() ? NAN : r.hi});
    j["component_ranges"] = comps;
    j["nan_values"] = nonFinite;
    warningsOut(&j, h.warnings);
    printJson(j);
    return 0;
  }
  headerText(h);
  std::printf("not a tensor volume: %d component(s) per voxel (a tensor volume has 6)\n", v.components);
  std::printf("value range:  %s .. %s%s\n", num(all.lo).c_str(), num(all.hi).c_str(),
              v.components > 1 ? " (all components)" : "");
  if (nonFinite) std::printf("NaN/Inf:      %zu values\n", nonFinite);
  warningsOut(nullptr, h.warnings);
  return 0;
}

// The cones of uncertainty (degrees) at world position `world` from a cone map (one value) or a bedpostx
// folder with samples (one per population), nearest voxel; NaN outside its grid or its mask.
std::vector<double> conesAt(const std::string& conePath, const glm::dvec3& world) {
  std::vector<ScalarVolume> maps;
  try {
    if (io::isBedpostxSamplesPath(conePath))
      maps = io::readBedpostxSamples(conePath).cone;
    else
      maps.push_back(io::readConeMap(conePath));
  } catch (...) {
    rethrowWithContext("while reading the uncertainty map " + conePath);
  }
  std::vector<double> out;
  for (const auto& m : maps) {
    const glm::dvec3 ijk = glm::dvec3(glm::inverse(m.grid.voxelToWorld) * glm::dvec4(world, 1.0));
    const int i = static_cast<int>(std::lround(ijk.x)), j = static_cast<int>(std::lround(ijk.y)),
              k = static_cast<int>(std::lround(ijk.z));
    out.push_back(m.grid.contains(i, j, k) ? m.data[m.grid.index(i, j, k)] : std::nan(""));
  }
  return out;
}

void printCones(const std::vector<double>& cones, const std::string& conePath, Json* j) {
  if (conePath.empty()) return;
  if (j) {
    (*j)["cone_deg"] = cones; // NaN is written as null
    return;
  }
  std::printf("cone95:      ");
  for (double c : cones)
    std::printf(" %s", std::isfinite(c) ? (num(c) + " deg").c_str() : "none");
  std::printf(" (95 %% cone of uncertainty of the principal direction%s, %s)\n",
              cones.size() > 1 ? ", per population" : "", conePath.c_str());
}

int describeVoxel(const std::string& path, const io::VolumeHeader& h, const io::LoadedTensors* t,
                  const ScalarVolume* v, const int ijk[3], bool json, const std::string& conePath) {
  const Grid& g = h.grid;
  if (!g.contains(ijk[0], ijk[1], ijk[2]))
    throw UsageError("voxel " + std::to_string(ijk[0]) + "," + std::to_string(ijk[1]) + "," +
                     std::to_string(ijk[2]) + " is outside the grid " + std::to_string(g.dims.x) + "x" +
                     std::to_string(g.dims.y) + "x" + std::to_string(g.dims.z));
  glm::dvec3 world = g.toWorld(glm::dvec3(ijk[0], ijk[1], ijk[2]));
  const std::vector<double> cones = conePath.empty() ? std::vector<double>{} : conesAt(conePath, world);
  Json j;
  if (json) {
    j["file"] = path;
    j["voxel"] = {ijk[0], ijk[1], ijk[2]};
    j["world"] = vec(world);
  } else {
    std::printf("file:         %s\n", path.c_str());
    std::printf("voxel:        %d, %d, %d\n", ijk[0], ijk[1], ijk[2]);
    std::printf("world:        %s, %s, %s mm (RAS)\n", num(world.x).c_str(), num(world.y).c_str(),
                num(world.z).c_str());
  }
  if (!t) {
    int comps = v->components;
    if (json) {
      j["is_tensor"] = false;
      Json values = Json::array();
      for (int c = 0; c < comps; ++c)
        values.push_back(static_cast<double>(v->at(ijk[0], ijk[1], ijk[2], c)));
      j["values"] = values;
      printCones(cones, conePath, &j);
      printJson(j);
    } else {
      std::printf("values:      ");
      for (int c = 0; c < comps; ++c)
        std::printf(" %s", num(v->at(ijk[0], ijk[1], ijk[2], c)).c_str());
      std::printf("\n");
      printCones(cones, conePath, nullptr);
    }
    return 0;
  }
  std::size_t idx = g.index(ijk[0], ijk[1], ijk[2]);
  bool valid = t->field.valid[idx] != 0;
  glm::dmat3 m = t->field.tensors[idx].toMat();
  EigenSystem e = eigenDecompose(m);
  TensorMetrics mt = computeMetrics(e);
  if (json) {
    j["is_tensor"] = true;
    j["layout"] = io::layoutName(t->layout);
    j["valid"] = valid;
    j["units"] = "mm^2/s";
    j["tensor_world"] = {vec({m[0][0], m[1][0], m[2][0]}), vec({m[0][1], m[1][1], m[2][1]}),
                         vec({m[0][2], m[1][2], m[2][2]})};
    j["eigenvalues"] = vec(e.values);
    j["eigenvectors"] = {vec(e.vectors[0]), vec(e.vectors[1]), vec(e.vectors[2])};
    j["fa"] = mt.fa;
    j["md"] = mt.md;
    j["ad"] = mt.ad;
    j["rd"] = mt.rd;
    printCones(cones, conePath, &j);
    printJson(j);
    return 0;
  }
  std::printf("layout:       %s\n", io::layoutName(t->layout));
  if (!valid) std::printf("note:         this voxel holds no valid tensor (zero, NaN or outside the mask)\n");
  std::printf("tensor (world RAS, mm^2/s):\n");
  for (int r = 0; r < 3; ++r)
    std::printf("  %13.6e %13.6e %13.6e\n", m[0][r], m[1][r], m[2][r]);
  std::printf("eigenvalues:  %.6e %.6e %.6e mm^2/s\n", e.values.x, e.values.y, e.values.z);
  for (int i = 0; i < 3; ++i)
    std::printf("eigenvector %d: %8.5f %8.5f %8.5f (world RAS)\n", i + 1, e.vectors[i].x, e.vectors[i].y,
                e.vectors[i].z);
  std::printf("FA %.4f  MD %.4e  AD %.4e  RD %.4e\n", mt.fa, mt.md, mt.ad, mt.rd);
  printCones(cones, conePath, nullptr);
  return 0;
}

std::string fibreNum(double v) {
  if (!std::isfinite(v)) return "null";
  char b[32];
  std::snprintf(b, sizeof b, "%.9g", v);
  return b;
}
std::string fibreVec(const glm::dvec3& v) {
  return "[" + fibreNum(v.x) + ", " + fibreNum(v.y) + ", " + fibreNum(v.z) + "]";
}

// `dtfabric info` for a fibre file: summary, or with ijk the voxel's fibres ("fibres": [{"direction": [x, y,
// z], "amplitude": a}, ...], unit world RAS, strongest first) and, with a paired tensor, its FA and e1.
int describeFibreInput(const io::OpenedInput& opened, const std::string& tensorPath, const int* ijk, bool json) {
  const std::string& path = opened.path;
  session::FibreInput in = session::loadFibreInput(opened, tensorPath, true);
  const FibreSet& s = in.fibres.set;
  const Grid& g = s.grid;
  const std::string layout = io::fibreLayoutName(in.fibres.layout);
  if (!ijk) {
    if (json) {
      printJson({{"file", path},
                 {"is_tensor", false},
                 {"is_fibres", true},
                 {"fibre_layout", layout},
                 {"layout_reason", in.fibres.layoutReason},
                 {"dims", {g.dims.x, g.dims.y, g.dims.z}},
                 {"orientation", g.orientationCode()},
                 {"max_fibres", s.maxFibres},
                 {"voxels_with_fibres", s.occupiedVoxels()},
                 {"max_amplitude", s.maxAmplitude()}});
      return 0;
    }
    std::printf("file:         %s\n", path.c_str());
    std::printf("fibre set:    %s (%s)\n", layout.c_str(), in.fibres.layoutReason.c_str());
    std::printf("dims:         %d x %d x %d, %s, up to %d fibres per voxel\n", g.dims.x, g.dims.y, g.dims.z,
                g.orientationCode().c_str(), s.maxFibres);
    std::printf("voxels:       %zu with fibres; largest amplitude %s\n", s.occupiedVoxels(),
                fibreNum(s.maxAmplitude()).c_str());
    for (const std::string& w : in.fibres.warnings)
      std::printf("warning:      %s\n", w.c_str());
    return 0;
  }
  if (!g.contains(ijk[0], ijk[1], ijk[2]))
    throw UsageError("voxel " + std::to_string(ijk[0]) + "," + std::to_string(ijk[1]) + "," +
                     std::to_string(ijk[2]) + " is outside the grid " + std::to_string(g.dims.x) + "x" +
                     std::to_string(g.dims.y) + "x" + std::to_string(g.dims.z));
  const glm::dvec3 world = g.toWorld(glm::dvec3(ijk[0], ijk[1], ijk[2]));
  const Fibre* f = s.at(ijk[0], ijk[1], ijk[2]);
  const int n = s.count(g.index(ijk[0], ijk[1], ijk[2]));
  Json j = {{"file", path},
            {"voxel", {ijk[0], ijk[1], ijk[2]}},
            {"world", vec(world)},
            {"is_fibres", true},
            {"fibre_layout", layout}};
  Json fibres = Json::array();
  for (int k = 0; k < n; ++k)
    fibres.push_back({{"direction", vec(glm::dvec3(f[k].direction))}, {"amplitude", f[k].amplitude}});
  j["fibres"] = fibres;
  std::string tensorText;
  if (in.tensor) {
    const std::size_t idx = g.index(ijk[0], ijk[1], ijk[2]);
    const EigenSystem e = eigenDecompose(in.tensor->field.tensors[idx].toMat());
    const double fa = in.tensor->field.valid[idx] ? computeMetrics(e).fa : 0.0;
    j["is_tensor"] = true;
    j["tensor_file"] = tensorPath;
    j["valid"] = in.tensor->field.valid[idx] != 0;
    j["fa"] = fa;
    j["eigenvalues"] = vec(e.values);
    j["eigenvectors"] = {vec(e.vectors[0]), vec(e.vectors[1]), vec(e.vectors[2])};
    tensorText = "tensor:       " + tensorPath + ": FA " + fibreNum(fa) + ", e1 " + fibreVec(e.vectors[0]) + "\n";
  } else {
    j["is_tensor"] = false;
    if (!in.fa.data.empty()) {
      const double fa = in.fa.data[g.index(ijk[0], ijk[1], ijk[2])];
      j["fa"] = fa;
      j["fa_file"] = in.faSource;
      tensorText = "FA:           " + fibreNum(fa) + " (" + in.faSource + ")\n";
    }
  }
  if (json) {
    printJson(j);
    return 0;
  }
  std::printf("file:         %s\n", path.c_str());
  std::printf("voxel:        %d, %d, %d\n", ijk[0], ijk[1], ijk[2]);
  std::printf("world:        %s mm (RAS)\n", fibreVec(world).c_str());
  std::printf("fibre layout: %s\n", layout.c_str());
  if (n == 0) std::printf("note:         no fibre in this voxel\n");
  for (int k = 0; k < n; ++k)
    std::printf("fibre %d:      direction %8.5f %8.5f %8.5f (unit, world RAS), amplitude %s\n", k + 1,
                f[k].direction.x, f[k].direction.y, f[k].direction.z, fibreNum(f[k].amplitude).c_str());
  std::fputs(tensorText.c_str(), stdout);
  return 0;
}

} // namespace

const OptionTable& infoOptions() {
  using O = CliOption;
  static const OptionTable table = [] {
    OptionTable t;
    t.command = "info";
    t.positionals = "FILE";
    t.maxPositionals = 1;
    t.intro =
        "Describes a volume: NIfTI-1/NIfTI-2 (.nii, .nii.gz), MRtrix (.mif, .mif.gz, .mih), NRRD (.nrrd,\n"
        ".nhdr), an FSL dtifit set (basename or a member file), a DSI Studio .src.gz; the format and why it was\n"
        "chosen are shown. For a tensor volume (4D with 6 volumes, or\n"
        "5D SYMMATRIX) it shows the detected layout and the reason, the voxel-to-world affine and where it\n"
        "came from, per-component ranges of the world RAS tensors (mm^2/s), NaN and non-positive-definite\n"
        "voxel counts and FA statistics. Other volumes get header facts and value ranges.\n"
        "A tractogram (.tck, .trk, .trk.gz, .trx, .vtk, .vtp) gets its format, header facts, streamline and\n"
        "point counts, length statistics, data arrays and groups (`dtfabric info TRACTS --help`).\n"
        "\n"
        "Fibre sets (crossing-fibre peaks: MRtrix sh2peaks, DIPY peaks, an FSL bedpostx folder or dyadsN file; a\n"
        "DSI Studio .fib.gz; an FSL dtifit set with V1 but no L1-L3, the last two with their own FA) are\n"
        "detected (or named with --layout mrtrix-peaks|dipy-peaks|bedpostx); --voxel then lists the voxel's fibres\n"
        "(unit world RAS directions with amplitudes, strongest first; JSON key \"fibres\").";
    t.options = {
        layoutOption(LayoutNames::TensorOrFibre)
            .alsoSays("; a tensor layout reads FILE as tensors and fails when it is not a tensor volume"),
        pairedTensorOption("its FA and eigenvectors, shown beside the fibres"),
        O::flag("json", "print one JSON object instead of text"),
        O::text("voxel", "I,J,K",
                "one voxel (0-based): world position, world tensor, eigenvalues (descending, mm^2/s), "
                "eigenvectors (rows, world RAS, principal first), FA, MD, AD, RD; a fibre set's fibres")
            .checkedBy(checkTriple),
        O::text("uncertainty", "CONE",
                "with --voxel: also the 95 % cone of uncertainty there (degrees; JSON key \"cone_deg\", a "
                "list) from a cone map (fit --bootstrap N --cone CONE) or a bedpostx folder with samples (one "
                "per population); nearest voxel of CONE's grid"),
    };
    return t;
  }();
  return table;
}

int cmdInfo(const CommandArgs& argv) {
  for (const auto& a : argv)
    if (!a.empty() && a[0] != '-' && session::isTractFileName(a)) return cmdTractInfo(argv);
  ParsedOptions args(infoOptions(), argv);
  if (args.printHelpIfAsked()) return 0;
  const std::string path = args.positional(0, "FILE (see --help)");
  std::string layoutText = args.text("layout");
  const std::string tensorPath = args.text("tensor");
  bool json = args.flag("json");
  auto voxelText = args.get("voxel");
  int ijk[3] = {0, 0, 0};
  if (voxelText) parseTriple(*voxelText, ijk);
  const std::string conePath = args.text("uncertainty");
  args.finish();
  if (!conePath.empty() && !voxelText)
    throw UsageError("--uncertainty reports a voxel's cone: give --voxel I,J,K");
  // Only whether the file is a fibre set is asked of the opener: any other volume is described as it is
  // (a 4D volume without gradient files too).
  io::InputRequest request;
  request.path = path;
  request.layout = layoutText;
  const io::FormatGuess format = io::detectFormat(path);
  if (const auto fibres = io::openFibreSet(request, format))
    return describeFibreInput(*fibres, tensorPath, voxelText ? ijk : nullptr, json);
  if (!tensorPath.empty()) throw UsageError("--tensor pairs a tensor with a fibre set; " + path + " is not one");
  io::TensorLayout layout = io::parseLayout(layoutText);

  io::VolumeHeader h = io::readHeader(path, format);
  // Any file of a complete FSL dtifit set stands for the set's tensor, as `render` reads it.
  if (layout != io::TensorLayout::Auto || looksLikeTensor(h) || io::isDtifitTensorSet(path)) {
    io::LoadedTensors t = io::readTensorVolume(path, format, layout);
    if (voxelText) return describeVoxel(path, t.header, &t, nullptr, ijk, json, conePath);
    return describeTensors(t, json);
  }
  ScalarVolume v = io::readScalarVolume(path, format, &h);
  if (voxelText) return describeVoxel(path, h, nullptr, &v, ijk, json, conePath);
  return describeScalar(v, h, json);
}

} // namespace dtf::app
