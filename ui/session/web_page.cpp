// SPDX-License-Identifier: GPL-3.0-or-later
// `dtfabric web`: renders every slice's fabric, the 3D view's frames and the FA sweep with one headless
// session and writes the page's folder.
#include "ui/session/web_page.h"

#include "ui/session/movie_job.h"
#include "ui/session/render_job.h"
#include "io/formats/atomic_file.h"
#include "io/formats/json.h"
#include "io/formats/png_io.h"
#include "io/model/error.h"
#include "io/model/log.h"
#include "surfaces/slices.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <unistd.h>

namespace fs = std::filesystem;

namespace dtf::session {

std::vector<std::uint8_t> webVoxelTable(const TensorField& field) {
  const std::size_t n = field.grid.voxelCount();
  std::vector<std::uint8_t> out(n * 4, 0);
  auto byte = [](double v) {
    return static_cast<std::uint8_t>(std::clamp(std::lround(127.0 * v) + 128, 1L, 255L));
  };
  for (std::size_t i = 0; i < n; ++i) {
    if (!field.valid[i]) continue;
    const EigenSystem e = eigenDecompose(field.tensors[i]);
    const double fa = fractionalAnisotropy(e.values);
    glm::dvec3 v = e.vectors[0];
    const glm::dvec3 a = glm::abs(v);
    const int big = a.x >= a.y && a.x >= a.z ? 0 : (a.y >= a.z ? 1 : 2);
    if (v[big] < 0) v = -v;
    std::uint8_t* o = &out[i * 4];
    o[0] =
        static_cast<std::uint8_t>(1 + std::lround(std::clamp(std::isfinite(fa) ? fa : 0.0, 0.0, 1.0) * 254));
    o[1] = byte(v.x);
    o[2] = byte(v.y);
    o[3] = byte(v.z);
  }
  return out;
}

std::string base64Encode(const std::vector<std::uint8_t>& bytes) {
  static const char* kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const unsigned w = (unsigned(bytes[i]) << 16) | (unsigned(bytes[i + 1]) << 8) | bytes[i + 2];
    for (int s = 18; s >= 0; s -= 6)
      out += kAlphabet[(w >> s) & 63];
  }
  if (i < bytes.size()) {
    const bool two = i + 1 < bytes.size();
    const unsigned w = (unsigned(bytes[i]) << 16) | (two ? unsigned(bytes[i + 1]) << 8 : 0u);
    out += kAlphabet[(w >> 18) & 63];
    out += kAlphabet[(w >> 12) & 63];
    out += two ? kAlphabet[(w >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

namespace {

constexpr surfaces::SliceAxis kAxes[3] = {surfaces::SliceAxis::Axial, surfaces::SliceAxis::Coronal,
                                          surfaces::SliceAxis::Sagittal};
constexpr render::StandardView kViews[3] = {render::StandardView::Axial, render::StandardView::Coronal,
                                            render::StandardView::Sagittal};

// The folder is built in a hidden sibling and renamed into place; a failure removes it.
class FolderTransaction {
public:
  FolderTransaction(const fs::path& target, const std::vector<const char*>& subfolders) : target_(target) {
    const fs::path parent = target.has_parent_path() ? target.parent_path() : fs::path(".");
    std::error_code ec;
    if (!fs::is_directory(parent, ec))
      throw InputError("cannot write " + target.string() + ": directory " + parent.string() +
                       " does not exist");
    const std::string stem = "." + target.filename().string() + ".tmp" + std::to_string(::getpid());
    temp_ = parent / stem;
    old_ = parent / (stem + ".old");
    fs::remove_all(temp_, ec);
    for (const char* sub : subfolders)
      if (!fs::create_directories(temp_ / sub, ec) || ec)
        throw InputError("cannot write " + target.string() + ": " + ec.message());
  }
  ~FolderTransaction() {
    std::error_code ec;
    if (!committed_) fs::remove_all(temp_, ec);
  }
  FolderTransaction(const FolderTransaction&) = delete;
  FolderTransaction& operator=(const FolderTransaction&) = delete;

  const fs::path& dir() const { return temp_; }

  // Moves an existing target aside, renames the new folder into place, then removes the old one.
  void commit() {
    std::error_code ec;
    const bool replacing = fs::exists(target_, ec);
    if (replacing) {
      fs::rename(target_, old_, ec);
      if (ec) throw InputError("cannot replace " + target_.string() + ": " + ec.message());
    }
    fs::rename(temp_, target_, ec);
    if (ec) {
      std::error_code ignored;
      if (replacing) fs::rename(old_, target_, ignored);
      throw InputError("cannot write " + target_.string() + ": " + ec.message());
    }
    committed_ = true;
    if (replacing) fs::remove_all(old_, ec);
  }

private:
  fs::path target_, temp_, old_;
  bool committed_ = false;
};

void writeText(const fs::path& path, const std::string& text) {
  std::ofstream f(path, std::ios::binary);
  f << text;
  f.close();
  if (!f) throw InputError("cannot write " + path.string());
}

// Refuses a folder that is, or lies above, one of the inputs: replacing it would delete them.
void refuseFolderHoldingInputs(const fs::path& output, const std::vector<std::string>& inputs) {
  std::error_code ec;
  const fs::path out = fs::weakly_canonical(fs::absolute(output), ec);
  for (const auto& in : inputs) {
    if (in.empty()) continue;
    const fs::path p = fs::weakly_canonical(fs::absolute(in), ec);
    auto o = out.begin();
    auto q = p.begin();
    for (; o != out.end() && q != p.end() && *o == *q; ++o, ++q) {
    }
    if (o == out.end())
      throw UsageError("refusing to write " + output.string() + ": it holds the input " + in);
  }
}

// A folder this command wrote: index.html, data.js holding window.DTF_WEB, the slices folder (and the 3d
// and fa folders), and nothing else. --force replaces only such a folder (or an empty one), never a folder of other files.
bool isWebPageFolder(const fs::path& dir) {
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    const std::string name = e.path().filename().string();
    if (name != "index.html" && name != "viewer.js" && name != "data.js" && name != "voxels.js" &&
        name != "slices" && name != "3d" && name != "fa")
      return false;
  }
  std::ifstream data(dir / "data.js");
  std::string head(32, '\0');
  data.read(head.data(), static_cast<std::streamsize>(head.size()));
  return !ec && fs::is_directory(dir / "slices", ec) && fs::exists(dir / "index.html", ec) &&
         head.rfind("window.DTF_WEB = ", 0) == 0;
}

nlohmann::json vec(const glm::dvec3& v) {
  return {v.x, v.y, v.z};
}

// One axis of the page: camera, image size, the slices rendered.
struct AxisPlan {
  int voxelAxis = 0, count = 0;
  WebSliceView view;
  std::vector<int> slices;
};

AxisPlan planAxis(const TensorField& field, int a, int size, bool wholeSlices) {
  const Grid& g = field.grid;
  AxisPlan p;
  p.voxelAxis = surfaces::voxelAxisFor(g, kAxes[a]);
  p.count = surfaces::sliceCount(g, kAxes[a]);
  p.view = webSliceView(g, a, size);
  std::vector<char> has(static_cast<std::size_t>(p.count), wholeSlices ? 1 : 0);
  if (!wholeSlices) {
    for (int k = 0; k < g.dims.z; ++k)
      for (int j = 0; j < g.dims.y; ++j)
        for (int i = 0; i < g.dims.x; ++i)
          if (field.valid[g.index(i, j, k)])
            has[static_cast<std::size_t>(glm::ivec3(i, j, k)[p.voxelAxis])] = 1;
  }
  for (int s = 0; s < p.count; ++s)
    if (has[static_cast<std::size_t>(s)]) p.slices.push_back(s);
  return p;
}

std::string sliceFile(const char* axis, bool tracts, int slice) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "slices/%s%s_%03d.png", axis, tracts ? "_tracts" : "", slice);
  return buf;
}

std::uintmax_t folderBytes(const fs::path& dir) {
  std::uintmax_t total = 0;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file()) total += e.file_size();
  return total;
}

std::string numbered(const char* pattern, int a, int b = 0) {
  char buf[64];
  std::snprintf(buf, sizeof buf, pattern, a, b);
  return buf;
}

} // namespace

WebSliceView webSliceView(const Grid& g, int a, int size) {
  if (a < 0 || a > 2) throw UsageError("web: axis " + std::to_string(a) + " is not 0, 1 or 2");
  // Every slice of an axis is framed by the same camera: the world box of the grid's voxel centres.
  glm::dvec3 lo, hi;
  g.worldBounds(lo, hi);
  const render::Camera probe = render::Camera::standard(kViews[a], lo, hi, 1.0);
  const glm::dvec3 r = probe.right(), u = glm::cross(r, probe.forward());
  const double ex = std::abs(glm::dot(hi - lo, glm::abs(r))), ey = std::abs(glm::dot(hi - lo, glm::abs(u)));
  const double aspect = std::clamp(ex / std::max(ey, 1e-9), 1.0 / 16, 16.0);
  WebSliceView v;
  v.width = aspect >= 1 ? size : std::max(16, static_cast<int>(std::lround(size * aspect)));
  v.height = aspect >= 1 ? std::max(16, static_cast<int>(std::lround(size / aspect))) : size;
  v.camera = render::Camera::standard(kViews[a], lo, hi, double(v.width) / v.height);
  return v;
}

std::vector<double> webFaThresholds(double lo, double hi, int steps) {
  std::vector<double> t;
  for (int i = 0; i < steps; ++i)
    t.push_back(std::round(1000.0 * (steps > 1 ? lo + (hi - lo) * i / (steps - 1) : lo)) / 1000.0);
  return t;
}

WebPageResult writeWebPage(const WebPageRequest& r) {
  const auto t0 = std::chrono::steady_clock::now();
  if (r.size < 16 || r.size > 4096) throw UsageError("--size must be in [16, 4096] pixels");
  if (r.output.empty()) throw UsageError("missing -o DIR");
  if (!r.slicesOnly) {
    if (r.azimuths < 4 || r.azimuths > 360) throw UsageError("--azimuths must be in [4, 360]");
    if (r.elevationsDeg.empty() || r.elevationsDeg.size() > 9)
      throw UsageError("the 3D view needs 1 to 9 elevations");
    for (double e : r.elevationsDeg)
      if (!(std::abs(e) <= 89)) throw UsageError("the 3D view's elevations must be in [-89, 89] degrees");
    if (r.faSteps < 2 || r.faSteps > 64) throw UsageError("--fa-steps must be in [2, 64]");
    if (!(r.faLo > 0 && r.faHi < 1 && r.faLo < r.faHi))
      throw UsageError("the FA sweep needs thresholds 0 < LO < HI < 1");
  }
  const SurfaceSpec surface = parseSurfaceSpec(r.slicesOnly ? "slice=axial" : r.surface);
  const fs::path output(r.output);
  const std::vector<std::string> inputs{r.input,
                                        r.tensorOptions.bval,
                                        r.tensorOptions.bvec,
                                        r.tensorOptions.mask,
                                        r.tracts,
                                        r.background == "fa" || r.background == "md" ? "" : r.background};
  refuseFolderHoldingInputs(output, inputs);
  std::error_code ec;
  if (io::outputExists(r.output)) {
    if (!fs::is_directory(output, ec))
      throw InputError(r.output + " exists and is not a folder: refusing to replace it");
    if (!r.force) throw InputError(r.output + " exists (use --force to replace it)");
    if (!fs::is_empty(output, ec) && !isWebPageFolder(output))
      throw InputError(r.output + " exists and is not a page dtfabric web wrote: refusing to replace it");
  }
  auto progress = [&](const std::string& s) {
    if (r.onProgress) r.onProgress(s);
  };

  // One session: the data, its FA, the background and the tracts loaded once; the render's default look.
  RenderRequest rr;
  rr.input = r.input;
  rr.field = r.field;
  rr.tensorOptions = r.tensorOptions;
  rr.background = r.background;
  rr.surface = surface;
  rr.width = rr.height = r.size;
  rr.furniture = {false, false, false, false, 0}; // the page draws the slices' letters itself
  rr.tracts = r.tracts;
  rr.tractsNear = r.tractsNearMm;
  rr.tractWidth = 1.5;
  rr.output = r.output;
  if (!r.field) progress("loading " + r.input);
  FrameSession session(rr);
  const TensorField& field = session.field();
  if (std::none_of(field.valid.begin(), field.valid.end(), [](unsigned char v) { return v != 0; }))
    throw InputError(r.input + " holds no valid tensor");
  if (!r.tracts.empty() && !session.hasTracts())
    logWarning(r.tracts + " holds no streamline: the page has no tract overlay");
  const bool withTracts = session.hasTracts();

  FolderTransaction folder(output, r.slicesOnly ? std::vector<const char*>{"slices"}
                                                : std::vector<const char*>{"slices", "3d", "fa"});
  auto writeImage = [&](const std::string& relative, const Image& image, WebPageResult& result) {
    io::writePng((folder.dir() / relative).string(), image);
    ++result.images;
  };

  WebPageResult result;
  nlohmann::json axes = nlohmann::json::array();
  for (int a = 0; a < 3; ++a) {
    const char* name = surfaces::sliceAxisName(kAxes[a]);
    const AxisPlan plan = planAxis(field, a, r.size, session.hasBackground());
    const render::Camera& cam = plan.view.camera;
    std::vector<int> written;
    const std::size_t step = std::max<std::size_t>(1, plan.slices.size() / 8);
    for (std::size_t n = 0; n < plan.slices.size(); ++n) {
      const int s = plan.slices[n];
      const SurfaceSpec spec = sliceSweepSpec(name, s);
      Mesh mesh;
      try {
        mesh = session.build(spec);
      } catch (const InputError&) {
        // A slice whose few voxels with data make no cell: nothing to show.
      }
      if (!mesh.empty()) {
        Image overlay;
        const Image fabric = session.still(mesh, spec, cam, plan.view.width, plan.view.height, rr.furniture,
                                           withTracts ? &overlay : nullptr);
        writeImage(sliceFile(name, false, s), fabric, result);
        if (withTracts) writeImage(sliceFile(name, true, s), overlay, result);
        written.push_back(s);
      }
      if ((n + 1) % step == 0 || n + 1 == plan.slices.size())
        progress(std::string(name) + " " + std::to_string(n + 1) + "/" + std::to_string(plan.slices.size()));
    }
    result.slices[a] = static_cast<int>(written.size());
    axes.push_back({{"name", name},
                    {"voxelAxis", plan.voxelAxis},
                    {"count", plan.count},
                    {"slices", written},
                    {"width", plan.view.width},
                    {"height", plan.view.height},
                    {"centre", vec(cam.target)},
                    {"right", vec(cam.right())},
                    {"up", vec(glm::normalize(glm::cross(cam.right(), cam.forward())))},
                    {"forward", vec(cam.forward())},
                    {"mmPerPixel", 2.0 * cam.orthoHalfHeight / plan.view.height},
                    {"image", std::string("slices/") + name + "_"},
                    {"tractImage", withTracts ? std::string("slices/") + name + "_tracts_" : std::string()}});
  }

  nlohmann::json view3d = nullptr, faSweep = nullptr;
  if (!r.slicesOnly) {
    // The 3D view: turntables of the surface (one per elevation) from the front, the advection state
    // carried from frame to frame as a movie's, with the orientation legend (from 256 pixels: below, it
    // would cover a large part of the image).
    render::FigureFurniture legend;
    legend.letters = legend.scaleBar = legend.colourBar = false;
    legend.legend = r.size >= 256;
    session.setMesh(session.surface());
    glm::vec3 lo, hi;
    session.surface().bounds(lo, hi);
    std::vector<render::Camera> sweepCameras; // the FA sweep's: the elevation nearest 20 degrees
    double sweepElevation = 0;
    for (std::size_t e = 0; e < r.elevationsDeg.size(); ++e) {
      const auto cams = turntableCameras(render::StandardView::Anterior, glm::dvec3(lo), glm::dvec3(hi), 1.0,
                                         r.azimuths, r.elevationsDeg[e], false, true);
      if (sweepCameras.empty() || std::abs(r.elevationsDeg[e] - 20) < std::abs(sweepElevation - 20)) {
        sweepCameras = cams;
        sweepElevation = r.elevationsDeg[e];
      }
      for (int i = 0; i < r.azimuths; ++i) {
        Image frame = session.frame(cams[static_cast<std::size_t>(i)], i == 0);
        render::drawFurniture(frame, cams[static_cast<std::size_t>(i)], 0, legend);
        writeImage(numbered("3d/view_%02d_%03d.png", static_cast<int>(e), i), frame, result);
        ++result.frames3d;
      }
      progress("3D view, elevation " + std::to_string(static_cast<int>(std::lround(r.elevationsDeg[e]))) +
               ": " + std::to_string(r.azimuths) + " frames");
    }
    view3d = {{"surface", describeSurface(surface)},
              {"azimuths", r.azimuths},
              {"elevations", r.elevationsDeg},
              {"width", r.size},
              {"height", r.size},
              {"image", "3d/view_"}};

    // The FA sweep: the isosurface at each threshold from one oblique camera (45 degrees round from the
    // front, the elevation nearest 20 degrees), the state carried from one threshold to the next.
    const std::vector<double> thresholds = webFaThresholds(r.faLo, r.faHi, r.faSteps);
    const render::Camera& sweepCamera = sweepCameras[static_cast<std::size_t>(r.azimuths / 8)];
    std::vector<double> shown;
    for (std::size_t i = 0; i < thresholds.size(); ++i) {
      Mesh mesh;
      try {
        mesh = session.build(faSweepSpec(thresholds[i], thresholds[i], 0, 1));
      } catch (const InputError&) {
        logWarning("web: no voxel reaches FA " + std::to_string(thresholds[i]) + ": the sweep ends before it");
        break;
      }
      session.setMesh(mesh);
      Image frame = session.frame(sweepCamera, i == 0);
      render::drawFurniture(frame, sweepCamera, 0, legend);
      writeImage(numbered("fa/fa_%02d.png", static_cast<int>(i)), frame, result);
      shown.push_back(thresholds[i]);
      ++result.faFrames;
    }
    progress("FA sweep: " + std::to_string(shown.size()) + " thresholds");
    faSweep = {{"thresholds", shown}, {"width", r.size}, {"height", r.size}, {"image", "fa/fa_"}};
  }

  progress("writing the probe table and the page");
  const Grid& g = field.grid;
  nlohmann::json affine = nlohmann::json::array();
  for (int row = 0; row < 4; ++row)
    affine.push_back(
        {g.voxelToWorld[0][row], g.voxelToWorld[1][row], g.voxelToWorld[2][row], g.voxelToWorld[3][row]});
  const std::string title = r.title.empty() ? fs::path(r.input).filename().string() : r.title;
  const nlohmann::json data = {
      {"title", title},
      {"input", fs::path(r.input).filename().string()},
      {"dims", {g.dims.x, g.dims.y, g.dims.z}},
      {"affine", affine},
      {"orientation", g.orientationCode()},
      {"background", r.background},
      {"tracts", withTracts ? fs::path(r.tracts).filename().string() : std::string()},
      {"axes", axes},
      {"view3d", view3d},
      {"faSweep", faSweep}};
  writeText(folder.dir() / "data.js", "window.DTF_WEB = " + io::jsonText(data) + ";\n");
  writeText(folder.dir() / "voxels.js",
            "window.DTF_WEB_VOXELS = \"" + base64Encode(webVoxelTable(field)) + "\";\n");
  writeText(folder.dir() / "viewer.js", webViewerJs());
  writeText(folder.dir() / "index.html", webIndexHtml(title));
  result.bytes = folderBytes(folder.dir());
  folder.commit();
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return result;
}

} // namespace dtf::session
