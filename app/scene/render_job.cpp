// The render session behind `dtfabric render` and dtfabric.render (Python): load, build the surfaces, render
// the panes and overlay the tracts.
#include "app/scene/render_job.h"

#include "app/scene/fibre_input.h"
#include "app/scene/tract_files.h"
#include "app/scene/tract_overlay.h"
#include "io/model/error.h"
#include "io/model/log.h"
#include "render/gl_context.h"
#include "render/tract_renderer.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <optional>
#include <vector>

namespace dtf::app {

namespace {

struct Background {
  ScalarVolume volume; // empty: none
  float lo = 0, hi = 1;
};

// --background fa|md|FILE with an optional LO,HI window (FILE default: its 1st..99th percentile).
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
    std::vector<float> v;
    for (std::size_t i = 0; i < b.volume.grid.voxelCount(); ++i) {
      const float x = b.volume.data[i * static_cast<std::size_t>(b.volume.components)];
      if (std::isfinite(x) && x != 0) v.push_back(x);
    }
    if (v.empty()) throw InputError(what + ": the background volume holds no non-zero values");
    std::sort(v.begin(), v.end());
    b.lo = v[v.size() / 100];
    b.hi = v[v.size() - 1 - v.size() / 100];
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

} // namespace

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

RenderResult runRender(const RenderRequest& r) {
  // The command checks these as it parses its flags; other callers get the same limits here.
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
  // The request under the names the command used for its flags.
  const std::string& input = r.input;
  const std::string& layoutText = r.layout;
  const std::string& tensorPath = r.tensor;
  const SurfaceSpec& spec = r.surface;
  const TensorInputOptions& in = r.tensorOptions;
  const std::string& backgroundArg = r.background;
  const std::string& backgroundWindow = r.backgroundWindow;
  const std::string& tractsPath = r.tracts;
  const TractColouring& colouring = r.colouring;
  const SplitMode& split = r.split;
  const int width = r.width, height = r.height;
  const render::StandardView view = r.view ? *r.view : defaultView(spec);
  const bool neurological = r.neurological, perspective = r.perspective;
  const double tractsNear = r.tractsNear, tractsSlab = r.tractsSlab, tractsSlabDepth = r.tractsSlabDepth;
  const double tractWidth = r.tractWidth;
  render::FabricParams p = r.params;

  // A fibre set (the carrier field gives surfaces their grid and data mask), or tensors.
  std::optional<FibreInput> fibreIn;
  io::LoadedTensors loaded;
  if (!r.field && isFibreInput(input, layoutText)) {
    fibreIn = loadFibreInput(input, layoutText, tensorPath);
    checkFibreSurface(spec, *fibreIn);
    if (!r.colourGiven) p.colour = render::ColourMode::Fibres;
    if (p.colour != render::ColourMode::Fibres)
      throw UsageError("--color " + r.colourName +
                       " colours a tensor's eigenvectors; a fibre set is shown with --color fibres");
    if ((!fibreIn->tensor && backgroundArg == "md") || (fibreIn->fa.data.empty() && backgroundArg == "fa"))
      throw UsageError("--background " + backgroundArg + " needs a tensor: pair one with --tensor FILE");
  } else {
    if (!tensorPath.empty())
      throw UsageError("--tensor pairs a tensor with a fibre-set INPUT; " + input + " is not one");
    if (!r.field) loaded = loadTensorInput(input, in);
  }
  const TensorField& field = fibreIn ? fibreIn->carrier : r.field ? *r.field : loaded.field;
  ScalarVolume fa = !fibreIn                   ? computeFaMap(field)
                    : fibreIn->fa.data.empty() ? ScalarVolume(field.grid, 1)
                                               : fibreIn->fa;
  SurfaceBuildOptions buildOptions;
  buildOptions.clipToData = backgroundArg.empty();
  Background background = loadBackground(backgroundArg, backgroundWindow, field, fa);
  Mesh mesh;
  try {
    mesh = buildSurface(spec, field, fa, buildOptions);
  } catch (...) {
    rethrowWithContext("while building the surface " + describeSurface(spec));
  }
  if (mesh.empty()) throw InputError("the surface " + describeSurface(spec) + " is empty");
  Polylines tracts = tractsPath.empty() ? Polylines{} : readTracts(tractsPath);
  const TractColouringApplied coloured = applyTractColouring(tracts, colouring, tractsPath);
  if (coloured.coloured) logInfo(coloured.summary);

  // The second pane's data: another surface of the same field, or the same surface of another input.
  io::LoadedTensors loaded2;
  std::optional<FibreInput> fibreIn2;
  Mesh mesh2;
  if (split.kind == SplitMode::Kind::Surface || split.kind == SplitMode::Kind::Input) {
    const TensorField* field2 = &field;
    const ScalarVolume* fa2 = &fa;
    ScalarVolume faOther;
    SurfaceSpec spec2 = spec;
    if (split.kind == SplitMode::Kind::Input && isFibreInput(split.value, "auto")) {
      // DTI beside a fibre set: both panes in the fibre colours, the tensor as its principal direction.
      fibreIn2 = loadFibreInput(split.value, "auto", "");
      if (!r.colourGiven) p.colour = render::ColourMode::Fibres;
      if (p.colour != render::ColourMode::Fibres)
        throw UsageError("--split input=" + split.value + " is a fibre set: it is shown with --color fibres");
      field2 = &fibreIn2->carrier;
      faOther = ScalarVolume(field2->grid, 1);
      fa2 = &faOther;
    } else if (split.kind == SplitMode::Kind::Input) {
      if (fibreIn) throw UsageError("--split input=FILE beside a fibre-set INPUT must be a fibre set too");
      loaded2 = loadTensorInput(split.value, in);
      faOther = computeFaMap(loaded2.field);
      field2 = &loaded2.field;
      fa2 = &faOther;
    } else {
      spec2 = parseSurfaceSpec(split.value);
    }
    try {
      mesh2 = buildSurface(spec2, *field2, *fa2, buildOptions);
    } catch (...) {
      rethrowWithContext("while building the second pane's surface " + describeSurface(spec2));
    }
    if (mesh2.empty()) throw InputError("the second pane's surface " + describeSurface(spec2) + " is empty");
  }

  render::GlContext::headless();
  render::FabricRenderer renderer;
  renderer.resize(width, height);
  if (!background.volume.data.empty())
    renderer.setBackground(&background.volume, background.lo, background.hi);
  glm::vec3 lo, hi;
  mesh.bounds(lo, hi);
  // Both panes share this camera (linked views).
  render::Camera camera = render::Camera::standard(view, glm::dvec3(lo), glm::dvec3(hi),
                                                   double(width) / height, neurological, !perspective);
  std::optional<render::TractRenderer> tractRenderer;
  if (!tractsPath.empty()) tractRenderer.emplace();
  // The tracts shown on `m` and their clip slab (app/scene/tract_overlay.h).
  TractOverlayOptions overlayOptions;
  overlayOptions.nearMm = tractsNear;
  overlayOptions.clipMm = tractsSlab;
  overlayOptions.clipDepthMm = tractsSlabDepth;
  auto overlay = [&](const Mesh& m, const Image& fabric) {
    render::TractStyle style;
    style.widthPx = static_cast<float>(tractWidth);
    const TractSelection selection = selectTracts(tracts, m, tractsNear);
    const TractClip clip =
        tractClip(selection.pick, overlayOptions, glm::vec3(camera.forward()), 0.5f * (lo + hi));
    style.plane = clip.plane;
    style.slabMm = clip.slabMm;
    tractRenderer->upload(tractOverlayDisplay(selection.all ? tracts : selection.near));
    if (tractRenderer->lineCount() == 0) {
      logWarning("no tract of " + tractsPath + " lies near the surface");
      return fabric;
    }
    glBindFramebuffer(GL_FRAMEBUFFER, renderer.output().id());
    tractRenderer->draw(renderer.frameView(), style);
    Image out = renderer.readback();
    if (coloured.coloured) render::drawTractColourBar(out.rgba.data(), out.width, out.height);
    return out;
  };
  // Fibre colours: the fibre set of the pane (a tensor's principal directions when it has none).
  std::optional<FibreSet> principal;
  auto fibresOf = [&](const TensorField& f) -> std::pair<const FibreSet*, const ScalarVolume*> {
    if (fibreIn && &f == &fibreIn->carrier)
      return {&fibreIn->fibres.set, fibreIn->fa.data.empty() ? nullptr : &fa};
    if (fibreIn2 && &f == &fibreIn2->carrier) return {&fibreIn2->fibres.set, nullptr};
    principal = principalFibres(f);
    return {&*principal, &f == &field ? &fa : nullptr};
  };
  auto pane = [&](const Mesh& m, const TensorField& f, const render::FabricParams& params, bool withTracts) {
    renderer.setMesh(m);
    renderer.setField(f);
    if (params.colour == render::ColourMode::Fibres) {
      auto [set, setFa] = fibresOf(f);
      renderer.setFibres(*set, setFa);
    }
    Image img = renderer.renderStill(camera, params);
    return withTracts && tractRenderer ? overlay(m, img) : img;
  };
  Image image;
  if (split.kind == SplitMode::Kind::Tracts) {
    Image plain = pane(mesh, field, p, false);
    image = sideBySide(plain, overlay(mesh, plain));
  } else if (split.kind == SplitMode::Kind::Colour) {
    if (fibreIn) throw UsageError("--split colour compares the tensor colour modes; a fibre set has one");
    render::FabricParams p2 = p;
    p.colour = render::ColourMode::Medical;
    p2.colour = render::ColourMode::Engineering;
    Image left = pane(mesh, field, p, true);
    image = sideBySide(left, pane(mesh, field, p2, true));
  } else if (split.kind == SplitMode::Kind::Surface || split.kind == SplitMode::Kind::Input) {
    Image left = pane(mesh, field, p, true);
    const TensorField& field2 = split.kind != SplitMode::Kind::Input ? field
                                : fibreIn2                           ? fibreIn2->carrier
                                                                     : loaded2.field;
    image = sideBySide(left, pane(mesh2, field2, p, true));
  } else {
    image = pane(mesh, field, p, true);
  }
  render::checkGl("rendering " + r.output);
  RenderResult result;
  result.image = std::move(image);
  result.surface = describeSurface(spec);
  result.triangles = mesh.triangleCount();
  result.view = view;
  result.iterations = renderer.lastIterations();
  return result;
}

} // namespace dtf::app
