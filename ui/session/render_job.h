// SPDX-License-Identifier: GPL-3.0-or-later
// One headless render of the fabric, as `dtfabric render` and the Python module's dtfabric.render run it: a
// request (input file or an in-memory tensor field, surface, view, size, fabric parameters, background,
// tracts, split panes) in, an RGBA image out. The caller has validated the flag values it parsed; the job
// loads the data, builds the surfaces, renders with the headless GL context current on the calling thread
// (render::GlContext::headless(): every job of a process must run on the thread that created it) and
// returns the pixels. Equal requests give equal pixels.
#pragma once

#include "io/model/image.h"
#include "io/model/tensor_field.h"
#include "render/camera.h"
#include "render/fabric_renderer.h"
#include "render/figure_furniture.h"
#include "ui/session/surface_spec.h"
#include "ui/session/tensor_input.h"
#include "ui/session/tract_colouring.h"

#include <memory>
#include <optional>
#include <string>

namespace dtf::session {

// The second pane of a split render: tracts | colour | surface=SPEC | input=FILE.
struct SplitMode {
  enum class Kind { None, Tracts, Colour, Surface, Input } kind = Kind::None;
  std::string value; // the SPEC or FILE
};

// Parses tracts | colour | color | surface=SPEC | input=FILE. Throws UsageError for anything else.
SplitMode parseSplitMode(const std::string& text);

// --fabric-along TRACTS[:MM]: the fabric drawn only within MM of the streamlines of a tract file, the
// background (the anatomy) elsewhere.
struct FabricAlong {
  std::string path; // empty: the fabric everywhere
  double mm = 2.0;
};

// Parses TRACTS[:MM]: a text after the last ':' that is not part of an existing file's name is MM, which must
// be a number in (0, 1000]. Throws InputError naming the text (an empty path, a bad MM).
FabricAlong parseFabricAlong(const std::string& text);

// The proximity weight of `along`'s streamlines (surfaces/analyses/tract_proximity.h), read from its file.
// Throws InputError naming the file (unreadable, or without a streamline point).
ScalarVolume loadFabricAlong(const FabricAlong& along);

struct RenderRequest {
  std::string input;                  // INPUT: a tensor file, a DWI or a fibre set
  const TensorField* field = nullptr; // when set: these tensors instead of loading `input` (which then only
                                      // names them in messages)
  TensorInputOptions tensorOptions;   // tensor layout, bval/bvec, DWI fit mask
  std::string layout = "auto";        // the layout as given: a tensor or a fibre layout name, or auto
  std::string tensor;                 // fibre sets: a paired tensor file (FA)
  SurfaceSpec surface;
  std::optional<render::StandardView> view; // default: the slice's own view, else superior
  bool neurological = false, perspective = false;
  int width = 768, height = 768; // above 768 the fabric keeps the threads of a 768 px image (noise cell and
                                 // advection step scale), so a larger image is sharper, not finer
  render::FabricParams params;
  bool colourGiven = false;     // params.colour was chosen (a fibre set defaults to fibres)
  std::string colourName;       // as given, for messages
  std::string background;       // fa | md | FILE, or empty
  std::string backgroundWindow; // LO,HI or empty
  std::string uncertainty;      // a cone map (degrees, any grid) or a bedpostx folder: the threads fray
                                // (params.fray) and a legend is drawn; empty: none
  std::string tracts;           // tract file or empty
  FabricAlong fabricAlong;      // the fabric only near these streamlines (empty path: everywhere)
  TractColouring colouring;
  double tractsNear = 3.0, tractsSlab = 0.0, tractsSlabDepth = 0.0, tractWidth = 2.0;
  SplitMode split;
  int supersample = 1;               // render at N x the size and box-filter down (1..4); the noise cell,
                                     // advection step, silhouette and tract widths scale with N, so the
                                     // fabric is the same one, anti-aliased
  render::FigureFurniture furniture; // orientation letters, legend, scale bar (per pane)
  std::optional<render::Camera> camera; // when set: this camera instead of the view's framing of the surface
                                        // (the web page's slices share one camera per axis)
  std::string output = "the image";  // what GL errors name
};

struct RenderResult {
  Image image;
  std::string surface;       // describeSurface of the request's surface
  std::size_t triangles = 0; // of the (first pane's) surface
  render::StandardView view = render::StandardView::Superior;
  int iterations = 0; // advection iterations of the last pane
};

// A grey background volume shown where the fabric is absent.
struct Background {
  ScalarVolume volume; // empty: none
  float lo = 0, hi = 1;
};

// Windows `b` to its volume's non-zero values' 1st..99th percentile; false when it has none.
bool windowByPercentiles(Background& b);

// --background fa|md|FILE with an optional LO,HI window (FILE default: its 1st..99th percentile); empty
// `what`: none. `fa` is the field's FA map. Throws UsageError (bad window), InputError (unreadable FILE).
Background loadBackground(const std::string& what, const std::string& window, const TensorField& field,
                          const ScalarVolume& fa);

// The fabric parameters on `spec`: an FA isosurface lies at one FA, its threshold, everywhere, where the
// anatomy look's FA ramp would give one partial opacity over the grey beneath (0.35 at the default 0.25: a
// dark surface). On an FA isosurface the anatomy look's fabric is opaque; elsewhere `p` is unchanged.
render::FabricParams paramsOnSurface(render::FabricParams p, bool faIsosurface);
render::FabricParams paramsOnSurface(const render::FabricParams& p, const SurfaceSpec& spec);

// The view a surface is shown from by default: a slice's own view, else superior.
render::StandardView defaultView(const SurfaceSpec& spec);

// Loads, builds and renders. Throws InputError (data, files: named), UsageError (combinations the data
// refuses, e.g. --color medical on a fibre set), GlError (no context, GL failure).
RenderResult runRender(const RenderRequest& request);

// Many frames of one request (movies): the data, FA, background and the request's surface loaded once, then
// frames of any surface of the same data from any camera, the advection state carried from frame to frame
// (render::FabricRenderer::renderMovieFrame). Tensor, DWI and fibre-set inputs; no split panes; the request's
// tracts are drawn only over stills that ask for them.
// The headless context is made current on the calling thread, as for runRender.
class FrameSession {
public:
  // Loads and builds; throws as runRender.
  explicit FrameSession(const RenderRequest& request);
  ~FrameSession();
  FrameSession(const FrameSession&) = delete;
  FrameSession& operator=(const FrameSession&) = delete;

  const TensorField& field() const;
  const ScalarVolume& fa() const;
  const Mesh& surface() const; // the request's surface
  // Another surface of the same data with the request's build options (InputError when empty).
  Mesh build(const SurfaceSpec& spec) const;
  // The fabric parameters of the next frames (a change restarts the advection from the noise).
  render::FabricParams& params();
  // The mesh of the next frames (uploaded now; initially the request's surface). Cheap to call per frame.
  void setMesh(const Mesh& mesh);
  // One frame seen by `camera`: `first` starts from the noise and converges, the others continue the
  // previous frame's state, reprojected into this view and onto the current mesh.
  Image frame(const render::Camera& camera, bool first);
  // A still of `mesh` (the surface `spec` built by build()) as runRender renders it: seen by `camera` at
  // width x height, from the noise, with `furniture`. Equal to runRender's image of a request with the same
  // surface, camera, size and furniture. `withTracts`, when given and the request has tracts: the same with
  // the tracts near the surface over it (the still itself when none is near).
  Image still(const Mesh& mesh, const SurfaceSpec& spec, const render::Camera& camera, int width, int height,
              const render::FigureFurniture& furniture, Image* withTracts = nullptr);
  // Whether the request's tracts hold a streamline.
  bool hasTracts() const;
  // Whether a grey background shows beneath (the surfaces are then built over the whole grid).
  bool hasBackground() const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

} // namespace dtf::session
