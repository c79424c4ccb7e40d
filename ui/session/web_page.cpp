// SPDX-License-Identifier: GPL-3.0-or-later
// `dtfabric web`: renders every slice's fabric with one headless renderer and writes the page's folder.
#include "ui/session/web_page.h"

#include "ui/session/render_job.h"
#include "ui/session/tract_files.h"
#include "ui/session/tract_overlay.h"
#include "io/formats/atomic_file.h"
#include "io/model/error.h"
#include "io/model/log.h"
#include "io/formats/png_io.h"
#include "render/fabric_renderer.h"
#include "render/gl_context.h"
#include "render/tract_renderer.h"
#include "surfaces/slices.h"
#include "io/formats/json.h"

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
  explicit FolderTransaction(const fs::path& target) : target_(target) {
    const fs::path parent = target.has_parent_path() ? target.parent_path() : fs::path(".");
    std::error_code ec;
    if (!fs::is_directory(parent, ec))
      throw InputError("cannot write " + target.string() + ": directory " + parent.string() +
                       " does not exist");
    const std::string stem = "." + target.filename().string() + ".tmp" + std::to_string(::getpid());
    temp_ = parent / stem;
    old_ = parent / (stem + ".old");
    fs::remove_all(temp_, ec);
    if (!fs::create_directories(temp_ / "slices", ec) || ec)
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

// A folder this command wrote: index.html, data.js holding window.DTF_WEB, the slices folder, and nothing
// else. --force replaces only such a folder (or an empty one), never a folder of other files.
bool isWebPageFolder(const fs::path& dir) {
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    const std::string name = e.path().filename().string();
    if (name != "index.html" && name != "viewer.js" && name != "data.js" && name != "voxels.js" &&
        name != "slices")
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
  int width = 0, height = 0;
  render::Camera camera;
  std::vector<int> slices;
};

AxisPlan planAxis(const TensorField& field, int a, int size, bool wholeSlices) {
  const Grid& g = field.grid;
  AxisPlan p;
  p.voxelAxis = surfaces::voxelAxisFor(g, kAxes[a]);
  p.count = surfaces::sliceCount(g, kAxes[a]);
  // Every slice of an axis is framed by the same camera: the world box of the grid's voxel centres.
  glm::dvec3 lo, hi;
  g.worldBounds(lo, hi);
  const render::Camera probe = render::Camera::standard(kViews[a], lo, hi, 1.0);
  const glm::dvec3 r = probe.right(), u = glm::cross(r, probe.forward());
  const double ex = std::abs(glm::dot(hi - lo, glm::abs(r))), ey = std::abs(glm::dot(hi - lo, glm::abs(u)));
  const double aspect = std::clamp(ex / std::max(ey, 1e-9), 1.0 / 16, 16.0);
  p.width = aspect >= 1 ? size : std::max(16, static_cast<int>(std::lround(size * aspect)));
  p.height = aspect >= 1 ? std::max(16, static_cast<int>(std::lround(size / aspect))) : size;
  p.camera = render::Camera::standard(kViews[a], lo, hi, double(p.width) / p.height);
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

} // namespace

WebPageResult writeWebPage(const WebPageRequest& r) {
  const auto t0 = std::chrono::steady_clock::now();
  if (r.size < 16 || r.size > 4096) throw UsageError("--size must be in [16, 4096] pixels");
  if (r.output.empty()) throw UsageError("missing -o DIR");
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

  io::LoadedTensors loaded;
  if (!r.field) {
    progress("loading " + r.input);
    loaded = loadTensorInput(r.input, r.tensorOptions);
  }
  const TensorField& field = r.field ? *r.field : loaded.field;
  if (std::none_of(field.valid.begin(), field.valid.end(), [](unsigned char v) { return v != 0; }))
    throw InputError(r.input + " holds no valid tensor");
  const ScalarVolume fa = computeFaMap(field);
  const Background background = loadBackground(r.background, "", field, fa);
  Polylines tracts;
  if (!r.tracts.empty()) tracts = readTracts(r.tracts);

  FolderTransaction folder(output);
  render::GlContext::headless();
  render::FabricRenderer renderer;
  renderer.setField(field);
  if (!background.volume.data.empty())
    renderer.setBackground(&background.volume, background.lo, background.hi);
  std::optional<render::TractRenderer> tractLayer;
  if (tracts.lineCount() > 0) {
    tractLayer.emplace();
    tractLayer->upload(tractOverlayDisplay(tracts));
  } else if (!r.tracts.empty()) {
    logWarning(r.tracts + " holds no streamline: the page has no tract overlay");
  }
  ScalarVolume clip(field.grid, 1);
  for (std::size_t i = 0; i < field.grid.voxelCount(); ++i)
    clip.data[i] = field.valid[i] ? 1.0f : 0.0f;
  surfaces::SliceOptions sliceOptions;
  if (background.volume.data.empty()) sliceOptions.clip = &clip;
  // The paper's look: every data voxel drawn (the page's probe carries FA; the anatomy look is not applied).
  render::FabricParams params;
  params.look = render::Look::Plain;

  WebPageResult result;
  nlohmann::json axes = nlohmann::json::array();
  for (int a = 0; a < 3; ++a) {
    const char* name = surfaces::sliceAxisName(kAxes[a]);
    AxisPlan plan = planAxis(field, a, r.size, !background.volume.data.empty());
    renderer.resize(plan.width, plan.height);
    std::vector<int> written;
    const std::size_t step = std::max<std::size_t>(1, plan.slices.size() / 8);
    for (std::size_t n = 0; n < plan.slices.size(); ++n) {
      const int s = plan.slices[n];
      const Mesh mesh = surfaces::makeSlice(field.grid, kAxes[a], s, sliceOptions);
      if (!mesh.empty()) {
        renderer.setMesh(mesh);
        const Image fabric = renderer.renderStill(plan.camera, params);
        io::writePng((folder.dir() / sliceFile(name, false, s)).string(), fabric);
        ++result.images;
        if (tractLayer) {
          TractOverlayOptions o;
          o.nearMm = r.tractsNearMm;
          glm::vec3 lo, hi;
          mesh.bounds(lo, hi);
          const TractClip c =
              tractClip(pickTracts(mesh, o.nearMm), o, glm::vec3(plan.camera.forward()), 0.5f * (lo + hi));
          render::TractStyle style;
          style.widthPx = 1.5f;
          style.plane = c.plane;
          style.slabMm = c.slabMm;
          glBindFramebuffer(GL_FRAMEBUFFER, renderer.output().id());
          tractLayer->draw(renderer.frameView(), style);
          io::writePng((folder.dir() / sliceFile(name, true, s)).string(), renderer.readback());
          ++result.images;
        }
        render::checkGl("rendering " + std::string(name) + " slice " + std::to_string(s) + " of " + r.output);
        written.push_back(s);
      }
      if ((n + 1) % step == 0 || n + 1 == plan.slices.size())
        progress(std::string(name) + " " + std::to_string(n + 1) + "/" + std::to_string(plan.slices.size()));
    }
    result.slices[a] = static_cast<int>(written.size());
    const render::Camera& cam = plan.camera;
    axes.push_back({{"name", name},
                    {"voxelAxis", plan.voxelAxis},
                    {"count", plan.count},
                    {"slices", written},
                    {"width", plan.width},
                    {"height", plan.height},
                    {"centre", vec(cam.target)},
                    {"right", vec(cam.right())},
                    {"up", vec(glm::normalize(glm::cross(cam.right(), cam.forward())))},
                    {"forward", vec(cam.forward())},
                    {"mmPerPixel", 2.0 * cam.orthoHalfHeight / plan.height},
                    {"image", std::string("slices/") + name + "_"},
                    {"tractImage", tractLayer ? std::string("slices/") + name + "_tracts_" : std::string()}});
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
      {"tracts", tractLayer ? fs::path(r.tracts).filename().string() : std::string()},
      {"axes", axes}};
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
