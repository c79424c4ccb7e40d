// SPDX-License-Identifier: GPL-3.0-or-later
// The render session behind `dtfabric render` and dtfabric.render (Python): load, build the surfaces, render
// the panes and overlay the tracts.
#include "ui/session/render_job.h"

#include "io/diffusion/uncertainty.h"
#include "io/model/error.h"
#include "io/model/log.h"
#include "io/model/range.h"
#include "render/figure_furniture.h"
#include "render/fray.h"
#include "render/gl_context.h"
#include "render/tract_renderer.h"
#include "surfaces/analyses/tract_proximity.h"
#include "ui/session/fibre_input.h"
#include "ui/session/tract_files.h"
#include "ui/session/tract_overlay.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <optional>
#include <vector>

namespace dtf::session {

bool windowByPercentiles(Background& b) {
  std::vector<float> v;
  for (std::size_t i = 0; i < b.volume.grid.voxelCount(); ++i) {
    const float x = b.volume.data[i * static_cast<std::size_t>(b.volume.components)];
    if (std::isfinite(x) && x != 0) v.push_back(x);
  }
  if (v.empty()) return false;
  std::sort(v.begin(), v.end());
  b.lo = v[v.size() / 100];
  b.hi = v[v.size() - 1 - v.size() / 100];
  return true;
}

FabricAlong parseFabricAlong(const std::string& text) {
  FabricAlong a;
  a.path = text;
  const auto colon = text.rfind(':');
  std::error_code ec;
  if (colon != std::string::npos && text.find('/', colon) == std::string::npos &&
      !std::filesystem::exists(text, ec)) {
    a.path = text.substr(0, colon);
    const std::string mm = text.substr(colon + 1);
    char* end = nullptr;
    a.mm = std::strtod(mm.c_str(), &end);
    if (mm.empty() || end != mm.c_str() + mm.size() || !std::isfinite(a.mm) || a.mm <= 0.0 || a.mm > 1000.0)
      throw InputError("--fabric-along " + text + ": the distance '" + mm +
                       "' must be a number of mm in (0, 1000]");
  }
  if (a.path.empty()) throw InputError("--fabric-along " + text + ": no tract file named");
  return a;
}

ScalarVolume loadFabricAlong(const FabricAlong& along) {
  Polylines lines;
  try {
    lines = readTracts(along.path);
  } catch (...) {
    rethrowWithContext("while reading the --fabric-along tracts " + along.path);
  }
  surfaces::TractProximityOptions options;
  options.mm = along.mm;
  surfaces::TractProximity near = surfaces::tractProximity(lines, options);
  if (near.points == 0) throw InputError(along.path + ": no streamline point to draw the fabric along");
  logInfo("the fabric along " + std::to_string(lines.lineCount()) + " streamlines of " + along.path +
          " (within " + shortestNumber(along.mm) + " mm, a " + shortestNumber(near.voxelMm) + " mm grid)");
  return std::move(near.weight);
}

Background loadBackground(const std::string& what, const std::string& window, const TensorField& field,
                          const ScalarVolume& fa) {
  Background b;
  if (what.empty()) {
    if (!window.empty()) throw UsageError("--background-window needs --background");
    return b;
  }
  if (what == "fa") {
    b.volume = fa;
  } else if (what == "md") {
    b.volume = computeMetricMaps(field, false, false).md;
    b.hi = 0.003f;
  } else {
    b.volume = io::readScalarVolume(what);
    if (!windowByPercentiles(b)) throw InputError(what + ": the background volume holds no non-zero values");
  }
  if (!window.empty()) {
    const auto comma = window.find(',');
    char* end = nullptr;
    const std::string a = window.substr(0, comma),
                      c = comma == std::string::npos ? "" : window.substr(comma + 1);
    b.lo = std::strtof(a.c_str(), &end);
    const bool okA = !a.empty() && *end == '\0';
    b.hi = std::strtof(c.c_str(), &end);
    if (!okA || c.empty() || *end != '\0' || !(b.hi > b.lo))
      throw UsageError("--background-window must be LO,HI with LO < HI, got '" + window + "'");
  }
  return b;
}

SplitMode parseSplitMode(const std::string& text) {
  SplitMode m;
  if (text == "tracts")
    m.kind = SplitMode::Kind::Tracts;
  else if (text == "colour" || text == "color")
    m.kind = SplitMode::Kind::Colour;
  else if (text.rfind("surface=", 0) == 0 && text.size() > 8)
    m = {SplitMode::Kind::Surface, text.substr(8)};
  else if (text.rfind("input=", 0) == 0 && text.size() > 6)
    m = {SplitMode::Kind::Input, text.substr(6)};
  else
    throw UsageError("--split must be tracts, colour, surface=SPEC or input=FILE, not '" + text + "'");
  return m;
}

render::StandardView defaultView(const SurfaceSpec& spec) {
  if (spec.kind == SurfaceSpec::Kind::Slice) return render::parseView(spec.axis);
  return render::StandardView::Superior;
}

namespace {

// The command checks these as it parses its flags; other callers get the same limits here.
void validate(const RenderRequest& r) {
  if (r.width < 16 || r.height < 16 || r.width > 8192 || r.height > 8192)
    throw UsageError("the size must be between 16x16 and 8192x8192");
  if ((!r.colouring.value.empty() || r.colouring.range || !r.colouring.groups.empty()) && r.tracts.empty())
    throw UsageError("--tracts-color, --tracts-range and --tracts-group need --tracts FILE");
  if (!(r.tractsNear >= 0 && r.tractsNear <= 1000)) throw UsageError("--tracts-near must be in [0, 1000] mm");
  if (!(r.tractsSlab >= 0 && r.tractsSlab <= 1000)) throw UsageError("--tracts-slab must be in [0, 1000] mm");
  if (!(std::abs(r.tractsSlabDepth) <= 1000))
    throw UsageError("--tracts-slab-depth must be in [-1000, 1000] mm");
  if (!(r.tractWidth > 0 && r.tractWidth <= 32)) throw UsageError("--tract-width must be in (0, 32] pixels");
  if (r.split.kind == SplitMode::Kind::Tracts && r.tracts.empty())
    throw UsageError("--split tracts needs --tracts FILE");
  if (r.supersample < 1 || r.supersample > 4) throw UsageError("--supersample must be 1, 2, 3 or 4");
  if (r.width * r.supersample > 16384 || r.height * r.supersample > 16384)
    throw UsageError("--supersample: the size times N must stay within 16384x16384");
}

// The uncertainty legend's font scale for the request's image.
int frayLegendScale(const RenderRequest& r) {
  return std::max(1, r.height / 384);
}

// The image size up to which the fabric's threads are those of the pixel-based defaults (FabricParams'
// stepPixels, autoLodPixels); larger images scale them (the same fabric, sharper).
constexpr double kFabricReferencePx = 768;

// The N x N box filter of a supersampled image (RGBA8; sizes are multiples of n).
Image downsample(const Image& big, int n) {
  if (n == 1) return big;
  Image out(big.width / n, big.height / n);
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x)
      for (int c = 0; c < 4; ++c) {
        int sum = 0;
        for (int dy = 0; dy < n; ++dy)
          for (int dx = 0; dx < n; ++dx)
            sum += big.pixel(x * n + dx, y * n + dy)[c];
        out.pixel(x, y)[c] = static_cast<std::uint8_t>((sum + n * n / 2) / (n * n));
      }
  return out;
}

Mesh buildNamedSurface(const SurfaceSpec& spec, const TensorField& field, const ScalarVolume& fa,
                       const SurfaceBuildOptions& options, const std::string& what) {
  Mesh mesh;
  try {
    mesh = buildSurface(spec, field, fa, options);
  } catch (...) {
    rethrowWithContext("while building " + what + " " + describeSurface(spec));
  }
  if (mesh.empty()) throw InputError(what + " " + describeSurface(spec) + " is empty");
  return mesh;
}

// The first pane's data: a fibre set (its carrier field gives surfaces their grid and data mask) or tensors,
// FA, the background, the surface and the tracts. Built in place: `field` points into it.
struct Scene {
  std::optional<FibreInput> fibreIn;
  io::LoadedTensors loaded;
  const TensorField* field = nullptr;
  ScalarVolume fa;
  Background background;
  ScalarVolume cone; // degrees; empty without --uncertainty
  ScalarVolume along; // --fabric-along's proximity weight; empty without it
  SurfaceBuildOptions buildOptions;
  Mesh mesh;
  Polylines tracts;
  TractColouringApplied coloured;
};

// Loads the first pane's data; a fibre set switches `p` to the fibre colours unless a colour was chosen.
void loadScene(const RenderRequest& r, render::FabricParams& p, Scene& s) {
  const io::OpenedInput in =
      r.field ? io::OpenedInput{} : io::openInput(inputRequest(r.input, r.layout, r.tensorOptions, true));
  if (!r.field && in.kind == io::InputKind::Fibres) {
    if (r.layout == "auto") logInfo(r.input + ": read as a fibre set (" + in.reason + ")");
    s.fibreIn = loadFibreInput(in, r.tensor);
    checkFibreSurface(r.surface, *s.fibreIn);
    if (!r.colourGiven) p.colour = render::ColourMode::Fibres;
    if (p.colour != render::ColourMode::Fibres)
      throw UsageError("--color " + r.colourName +
                       " colours a tensor's eigenvectors; a fibre set is shown with --color fibres");
    if ((!s.fibreIn->tensor && r.background == "md") || (s.fibreIn->fa.data.empty() && r.background == "fa"))
      throw UsageError("--background " + r.background + " needs a tensor: pair one with --tensor FILE");
  } else {
    if (!r.tensor.empty())
      throw UsageError("--tensor pairs a tensor with a fibre-set INPUT; " + r.input + " is not one");
    if (!r.field) s.loaded = loadTensors(in, r.tensorOptions);
  }
  s.field = s.fibreIn ? &s.fibreIn->carrier : r.field ? r.field : &s.loaded.field;
  s.fa = !s.fibreIn                   ? computeFaMap(*s.field)
         : s.fibreIn->fa.data.empty() ? ScalarVolume(s.field->grid, 1)
                                      : s.fibreIn->fa;
  s.background = loadBackground(r.background, r.backgroundWindow, *s.field, s.fa);
  // The anatomy look over a DWI: its mean b=0 image beneath, unless a background was given. (Over a tensor
  // file the composite shows FA beneath, within the data's edge.)
  if (r.background.empty() && p.look == render::Look::Anatomy && !s.loaded.meanB0.data.empty()) {
    s.background.volume = std::move(s.loaded.meanB0);
    if (!windowByPercentiles(s.background)) s.background.volume = ScalarVolume{};
  }
  if (!r.fabricAlong.path.empty()) {
    s.along = loadFabricAlong(r.fabricAlong);
    // Away from the streamlines the anatomy shows: the background volume, FA when none was given.
    if (s.background.volume.data.empty()) {
      s.background = loadBackground("fa", r.backgroundWindow, *s.field, s.fa);
      logInfo("--fabric-along: FA beneath, where the fabric is not drawn (--background B for another)");
    }
  }
  s.buildOptions.clipToData = s.background.volume.data.empty();
  s.buildOptions.dataEdgeCells = true;
  if (!r.uncertainty.empty()) {
    try {
      s.cone = conesFor(readUncertainty(r.uncertainty), s.fibreIn ? &s.fibreIn->fibres.set : nullptr);
    } catch (...) {
      rethrowWithContext("while reading the uncertainty map " + r.uncertainty);
    }
  }
  s.mesh = buildNamedSurface(r.surface, *s.field, s.fa, s.buildOptions, "the surface");
  if (!r.tracts.empty()) s.tracts = readTracts(r.tracts);
  s.coloured = applyTractColouring(s.tracts, r.colouring, r.tracts);
  if (s.coloured.coloured) logInfo(s.coloured.summary);
}

// The second pane's data (split surface= or input=): another surface of the same field, or the same surface
// of another input. Built in place: `field` points into it or into the scene.
struct SecondPane {
  io::LoadedTensors loaded;
  std::optional<FibreInput> fibreIn;
  const TensorField* field = nullptr;
  const ScalarVolume* fibreFa = nullptr; // a fibre set pane's FA: its own, else the first pane's on its grid
  SurfaceSpec spec;                      // the pane's surface
  Mesh mesh;
};

void loadSecondPane(const RenderRequest& r, const Scene& s, render::FabricParams& p, SecondPane& out) {
  const SplitMode& split = r.split;
  if (split.kind != SplitMode::Kind::Surface && split.kind != SplitMode::Kind::Input) return;
  out.field = s.field;
  const ScalarVolume* fa2 = &s.fa;
  ScalarVolume faOther;
  SurfaceSpec spec2 = r.surface;
  const io::OpenedInput in = split.kind == SplitMode::Kind::Input
                                 ? io::openInput(inputRequest(split.value, "auto", r.tensorOptions, true))
                                 : io::OpenedInput{};
  if (split.kind == SplitMode::Kind::Input && in.kind == io::InputKind::Fibres) {
    // DTI beside a fibre set: both panes in the fibre colours, the tensor as its principal direction.
    logInfo(split.value + ": read as a fibre set (" + in.reason + ")");
    out.fibreIn = loadFibreInput(in, "");
    if (!r.colourGiven) p.colour = render::ColourMode::Fibres;
    if (p.colour != render::ColourMode::Fibres)
      throw UsageError("--split input=" + split.value + " is a fibre set: it is shown with --color fibres");
    out.field = &out.fibreIn->carrier;
    // A fibre set without FA of its own (MRtrix peaks) takes the first pane's FA on the same grid: the
    // anatomy look and FA surfaces then read the same tissue in both panes.
    const Grid& g = out.field->grid;
    if (!out.fibreIn->fa.data.empty()) {
      out.fibreFa = &out.fibreIn->fa;
    } else if (g.sameAs(s.field->grid)) {
      out.fibreFa = &s.fa;
      logInfo(split.value + ": FA from " + r.input + " (the first pane's, on the same grid)");
    } else {
      logWarning(split.value + ": no FA (its grid differs from " + r.input + "'s): shown as FA 0");
    }
    faOther = ScalarVolume(g, 1);
    fa2 = out.fibreFa ? out.fibreFa : &faOther;
  } else if (split.kind == SplitMode::Kind::Input) {
    if (s.fibreIn) throw UsageError("--split input=FILE beside a fibre-set INPUT must be a fibre set too");
    out.loaded = loadTensors(in, r.tensorOptions);
    faOther = computeFaMap(out.loaded.field);
    out.field = &out.loaded.field;
    fa2 = &faOther;
  } else {
    spec2 = parseSurfaceSpec(split.value);
  }
  out.spec = spec2;
  out.mesh = buildNamedSurface(spec2, *out.field, *fa2, s.buildOptions, "the second pane's surface");
}

// Slices and oblique planes only (alone or joined): the surfaces built over the whole grid when a background
// shows beneath them.
bool planesOnly(const SurfaceSpec& spec) {
  if (spec.kind == SurfaceSpec::Kind::Combined)
    return std::all_of(spec.parts.begin(), spec.parts.end(),
                       [](const SurfaceSpec& p) { return planesOnly(p); });
  return spec.kind == SurfaceSpec::Kind::Slice || spec.kind == SurfaceSpec::Kind::Plane;
}

// The bounds a slice's camera frames: of its vertices in voxels with data, so a slice over the whole grid (a
// background beneath) and one clipped to the data are framed alike; the whole mesh's when none is in the
// data.
void dataBounds(const Mesh& mesh, const TensorField& field, glm::vec3& lo, glm::vec3& hi) {
  mesh.bounds(lo, hi);
  glm::vec3 dlo(std::numeric_limits<float>::max()), dhi(-std::numeric_limits<float>::max());
  bool any = false;
  for (const glm::vec3& p : mesh.positions) {
    const glm::ivec3 v = glm::ivec3(glm::round(field.grid.toVoxel(glm::dvec3(p))));
    if (!field.grid.contains(v.x, v.y, v.z) || !field.valid[field.grid.index(v.x, v.y, v.z)]) continue;
    dlo = glm::min(dlo, p);
    dhi = glm::max(dhi, p);
    any = true;
  }
  if (any) {
    lo = dlo;
    hi = dhi;
  }
}

// The GL part: one renderer and camera for every pane (linked views), the tract overlay.
class PaneRenderer {
public:
  PaneRenderer(const RenderRequest& r, const Scene& s, const SecondPane& second, render::StandardView view)
      : r_(r), s_(s), second_(second), n_(r.supersample), width_(r.width), height_(r.height),
        furniture_(r.furniture) {
    renderer_.resize(r.width * n_, r.height * n_);
    if (!s.background.volume.data.empty())
      renderer_.setBackground(&s.background.volume, s.background.lo, s.background.hi);
    if (!s.cone.data.empty()) renderer_.setUncertainty(&s.cone);
    if (!s.along.data.empty()) renderer_.setAlong(&s.along);
    if (planesOnly(r.surface))
      dataBounds(s.mesh, *s.field, lo_, hi_);
    else
      s.mesh.bounds(lo_, hi_);
    camera_ = render::Camera::standard(view, glm::dvec3(lo_), glm::dvec3(hi_), double(r.width) / r.height,
                                       r.neurological, !r.perspective);
    if (r.camera) {
      camera_ = *r.camera;
    } else if (r.furniture.letters) {
      // The orientation letters sit in a band at each edge: the data is framed inside it.
      const double half = 0.5 * std::min(r.width, r.height);
      const double band = render::letterBand(r.width, r.height);
      if (half > 2 * band)
        camera_.fit(glm::dvec3(lo_), glm::dvec3(hi_), double(r.width) / r.height,
                    std::max(1.05, half / (half - band)));
    }
    if (!r.tracts.empty()) tracts_.emplace();
  }

  // One pane: `m` woven from `f`, with the tracts over it when asked and given; filtered down to the
  // requested size and furnished.
  Image pane(const Mesh& m, const TensorField& f, const render::FabricParams& params, bool withTracts) {
    renderer_.setMesh(m);
    renderer_.setField(f);
    if (params.colour == render::ColourMode::Fibres) {
      auto [set, setFa] = fibresOf(f);
      renderer_.setFibres(*set, setFa);
    }
    Image img = renderer_.renderStill(camera_, scaled(params));
    if (withTracts && tracts_)
      if (auto over = tractsOver(m)) return finish(*over);
    return finish(img);
  }

  // A still of `m` woven from the scene's field as pane() renders it, seen by `camera` at width x height with
  // `furniture` (the request's size, camera and furniture are restored after).
  Image still(const Mesh& m, const render::FabricParams& params, const render::Camera& camera, int width,
              int height, const render::FigureFurniture& furniture, Image* withTracts) {
    const render::Camera keepCamera = camera_;
    const render::FigureFurniture keepFurniture = furniture_;
    const int keepW = width_, keepH = height_;
    camera_ = camera;
    furniture_ = furniture;
    width_ = width;
    height_ = height;
    renderer_.resize(width * n_, height * n_);
    movieField_ = false;
    Image img = pane(m, *s_.field, params, false);
    if (withTracts) {
      std::optional<Image> over = tracts_ ? tractsOver(m, false) : std::nullopt;
      *withTracts = over ? finish(*over) : img;
    }
    camera_ = keepCamera;
    furniture_ = keepFurniture;
    width_ = keepW;
    height_ = keepH;
    renderer_.resize(keepW * n_, keepH * n_);
    return img;
  }

  // The tracts shown on `m` (the one overlay rule, ui/session/tract_overlay.h) over the last pane rendered
  // (`fabric`, returned when there are none).
  Image overlay(const Mesh& m, const Image& fabric) {
    if (!tracts_) return fabric;
    auto over = tractsOver(m);
    return over ? finish(*over) : fabric;
  }

  int lastIterations() const { return renderer_.lastIterations(); }

  void setMovieMesh(const Mesh& m) { renderer_.setMesh(m); }
  // A movie frame (FabricRenderer::renderMovieFrame) of the mesh set last.
  Image movieFrame(const render::Camera& camera, const render::FabricParams& params, bool first) {
    if (!movieField_) {
      renderer_.setField(*s_.field);
      if (params.colour == render::ColourMode::Fibres) {
        auto [set, setFa] = fibresOf(*s_.field);
        renderer_.setFibres(*set, setFa);
      }
    }
    movieField_ = true;
    renderer_.renderMovieFrame(camera, params, first);
    render::checkGl("rendering " + r_.output);
    // The figure's furniture for this frame's camera (a turntable's letters follow its rotation).
    Image img = renderer_.readback();
    render::FigureFurniture furniture = furniture_;
    furniture.scaleBar = furniture.scaleBar && camera.orthographic;
    render::drawFurniture(img, camera, renderer_.frameView().pixelMm, furniture);
    return img;
  }

private:
  // The tracts drawn over the renderer's output (at the supersampled size), read back; none when no tract
  // lies near the surface.
  std::optional<Image> tractsOver(const Mesh& m, bool warnWhenNone = true) {
    TractOverlayOptions options;
    options.nearMm = r_.tractsNear;
    options.clipMm = r_.tractsSlab;
    options.clipDepthMm = r_.tractsSlabDepth;
    const TractSelection selection = selectTracts(s_.tracts, m, r_.tractsNear);
    const TractClip clip =
        tractClip(selection.pick, options, glm::vec3(camera_.forward()), 0.5f * (lo_ + hi_));
    render::TractStyle style;
    style.widthPx = static_cast<float>(r_.tractWidth * n_);
    style.plane = clip.plane;
    style.slabMm = clip.slabMm;
    tracts_->upload(tractOverlayDisplay(selection.all ? s_.tracts : selection.near));
    if (tracts_->lineCount() == 0) {
      if (warnWhenNone) logWarning("no tract of " + r_.tracts + " lies near the surface");
      return std::nullopt;
    }
    glBindFramebuffer(GL_FRAMEBUFFER, renderer_.output().id());
    tracts_->draw(renderer_.frameView(), style);
    colourBarDue_ = s_.coloured.coloured; // drawn by finish() at the final size
    return renderer_.readback();
  }

  // Supersampling: the same fabric at n times the pixels (noise cell, step and silhouette in pixels x n).
  // Above kFabricReferencePx the fabric keeps the threads of an image that size (the noise cell and the
  // advection step scale with the image), so a larger image shows the same fabric sharper, not a finer one.
  render::FabricParams scaled(render::FabricParams p) const {
    const double size = std::max(width_, height_);
    const double k = n_ * std::max(1.0, size / kFabricReferencePx);
    p.stepPixels *= k;
    p.autoLodPixels *= k;
    p.silhouettePixels *= n_;
    p.guard = static_cast<int>(std::ceil(p.guard * k));
    return p;
  }

  // Filtered down to the requested size, then the figure's furniture at that size.
  Image finish(const Image& full) const {
    Image img = downsample(full, n_);
    render::FigureFurniture furniture = furniture_;
    furniture.scaleBar = furniture.scaleBar && !r_.perspective; // one pixel size only without perspective
    if (!s_.cone.data.empty()) furniture.bottomLeftReserved = render::frayLegendHeight(frayLegendScale(r_));
    render::drawFurniture(img, camera_, renderer_.frameView().pixelMm * n_, furniture);
    if (colourBarDue_ && furniture.colourBar)
      render::drawColourBar(img, {r_.colouring.value, s_.coloured.lo, s_.coloured.hi});
    colourBarDue_ = false;
    return img;
  }

  // Fibre colours: the fibre set of the pane (a tensor's principal directions when it has none).
  std::pair<const FibreSet*, const ScalarVolume*> fibresOf(const TensorField& f) {
    if (s_.fibreIn && &f == &s_.fibreIn->carrier)
      return {&s_.fibreIn->fibres.set, s_.fibreIn->fa.data.empty() ? nullptr : &s_.fa};
    if (second_.fibreIn && &f == &second_.fibreIn->carrier)
      return {&second_.fibreIn->fibres.set, second_.fibreFa};
    principal_ = principalFibres(f);
    return {&*principal_, &f == s_.field ? &s_.fa : nullptr};
  }

  const RenderRequest& r_;
  const Scene& s_;
  const SecondPane& second_;
  int n_; // supersampling factor
  int width_, height_;                  // the image's size (the request's, or a still's)
  render::FigureFurniture furniture_;   // the request's, or a still's
  // Makes the process's headless context current before the renderer compiles its programs.
  struct CurrentContext {
    CurrentContext() { render::GlContext::headless(); }
  } context_;
  render::FabricRenderer renderer_;
  render::Camera camera_;
  glm::vec3 lo_{0.0f}, hi_{0.0f};
  std::optional<render::TractRenderer> tracts_;
  std::optional<FibreSet> principal_;
  bool movieField_ = false;
  mutable bool colourBarDue_ = false; // the last tract overlay was coloured by a value
};

// The image: one pane, or two side by side as the split asks.
Image renderPanes(const RenderRequest& r, const Scene& s, const SecondPane& second, PaneRenderer& panes,
                  const render::FabricParams& params) {
  render::FabricParams p = paramsOnSurface(params, r.surface); // the first pane's
  switch (r.split.kind) {
  case SplitMode::Kind::Tracts: {
    Image plain = panes.pane(s.mesh, *s.field, p, false);
    return sideBySide(plain, panes.overlay(s.mesh, plain));
  }
  case SplitMode::Kind::Colour: {
    if (s.fibreIn) throw UsageError("--split colour compares the tensor colour modes; a fibre set has one");
    render::FabricParams p2 = p;
    p.colour = render::ColourMode::Medical;
    p2.colour = render::ColourMode::Engineering;
    Image left = panes.pane(s.mesh, *s.field, p, true);
    return sideBySide(left, panes.pane(s.mesh, *s.field, p2, true));
  }
  case SplitMode::Kind::Surface:
  case SplitMode::Kind::Input: {
    Image left = panes.pane(s.mesh, *s.field, p, true);
    return sideBySide(left,
                      panes.pane(second.mesh, *second.field, paramsOnSurface(params, second.spec), true));
  }
  case SplitMode::Kind::None:
    break;
  }
  return panes.pane(s.mesh, *s.field, p, true);
}

} // namespace

render::FabricParams paramsOnSurface(render::FabricParams p, bool faIsosurface) {
  if (p.look == render::Look::Anatomy && faIsosurface) {
    p.opacityFaLow = 0; // opaque wherever FA > 0 (the shader's ramp is smoothstep(0, 1e-3, FA))
    p.opacityFaHigh = 0;
  }
  return p;
}

render::FabricParams paramsOnSurface(const render::FabricParams& p, const SurfaceSpec& spec) {
  return paramsOnSurface(p, spec.kind == SurfaceSpec::Kind::Fa);
}

RenderResult runRender(const RenderRequest& r) {
  validate(r);
  render::FabricParams p = r.params;
  Scene scene;
  loadScene(r, p, scene);
  SecondPane second;
  loadSecondPane(r, scene, p, second);
  const render::StandardView view = r.view ? *r.view : defaultView(r.surface);
  PaneRenderer panes(r, scene, second, view);
  Image image = renderPanes(r, scene, second, panes, p);
  if (r.split.kind != SplitMode::Kind::None) render::drawPaneDivider(image, image.width / 2);
  if (!scene.cone.data.empty()) render::drawFrayLegend(image, static_cast<float>(p.fray), frayLegendScale(r));
  render::checkGl("rendering " + r.output);
  RenderResult result;
  result.image = std::move(image);
  result.surface = describeSurface(r.surface);
  result.triangles = scene.mesh.triangleCount();
  result.view = view;
  result.iterations = panes.lastIterations();
  return result;
}

struct FrameSession::Impl {
  RenderRequest request;
  render::FabricParams params;
  Scene scene;
  SecondPane none;
  std::optional<PaneRenderer> panes;
};

FrameSession::FrameSession(const RenderRequest& request) : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.request = request;
  m.request.split = {};
  validate(m.request);
  m.params = m.request.params;
  loadScene(m.request, m.params, m.scene);
  m.params = paramsOnSurface(m.params, m.request.surface);
  m.panes.emplace(m.request, m.scene, m.none,
                  m.request.view ? *m.request.view : defaultView(m.request.surface));
  m.panes->setMovieMesh(m.scene.mesh);
}

FrameSession::~FrameSession() = default;

const TensorField& FrameSession::field() const {
  return *impl_->scene.field;
}

const ScalarVolume& FrameSession::fa() const {
  return impl_->scene.fa;
}

const Mesh& FrameSession::surface() const {
  return impl_->scene.mesh;
}

Mesh FrameSession::build(const SurfaceSpec& spec) const {
  const Scene& s = impl_->scene;
  return buildNamedSurface(spec, *s.field, s.fa, s.buildOptions, "the surface");
}

render::FabricParams& FrameSession::params() {
  return impl_->params;
}

void FrameSession::setMesh(const Mesh& mesh) {
  impl_->panes->setMovieMesh(mesh);
}

Image FrameSession::frame(const render::Camera& camera, bool first) {
  return impl_->panes->movieFrame(camera, impl_->params, first);
}

Image FrameSession::still(const Mesh& mesh, const SurfaceSpec& spec, const render::Camera& camera, int width,
                          int height, const render::FigureFurniture& furniture, Image* withTracts) {
  render::FabricParams p = impl_->request.params;
  if (impl_->scene.fibreIn && !impl_->request.colourGiven) p.colour = render::ColourMode::Fibres;
  return impl_->panes->still(mesh, paramsOnSurface(p, spec), camera, width, height, furniture,
                             withTracts && impl_->scene.tracts.lineCount() > 0 ? withTracts : nullptr);
}

bool FrameSession::hasTracts() const {
  return impl_->scene.tracts.lineCount() > 0;
}

bool FrameSession::hasBackground() const {
  return !impl_->scene.background.volume.data.empty();
}

} // namespace dtf::session
