// SPDX-License-Identifier: GPL-3.0-or-later
// dtfabric._core: the Python bindings over the session library (app/scene). Loading, surfaces, tracking,
// the orientation check and the render job are the ones the command-line tool runs; this file only turns
// Python arguments into their requests and results into numpy arrays. Long work runs without the GIL; GL
// work runs on the module's GL thread (app/python/gl_thread.h). dtf::Error types become the exception
// classes of dtfabric/_errors.py.
#include "app/python/arrays.h"
#include "app/python/gl_thread.h"
#include "io/diffusion/dwi.h"
#include "io/diffusion/uncertainty.h"
#include "io/formats/fibre_io.h"
#include "io/formats/formats.h"
#include "io/formats/movie_writer.h"
#include "io/formats/png_io.h"
#include "io/formats/tensor_io.h"
#include "io/input.h"
#include "io/model/error.h"
#include "io/model/log.h"
#include "render/fabric_options.h"
#include "surfaces/slices.h"
#include "surfaces/tracking/tracking_parameters.h"
#include "ui/session/check_run.h"
#include "ui/session/fibre_input.h"
#include "ui/session/movie_job.h"
#include "ui/session/render_job.h"
#include "ui/session/surface_spec.h"
#include "ui/session/tensor_input.h"
#include "ui/session/track_job.h"
#include "ui/session/tract_profiles.h"
#include "io/formats/atomic_file.h"
#include "render/profile_plot.h"
#include "ui/session/web_page.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <optional>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <string>

namespace py = pybind11;

namespace dtf::python {

namespace {

bool isPathLike(const py::handle& o) {
  return py::isinstance<py::str>(o) || py::isinstance<py::bytes>(o) || py::hasattr(o, "__fspath__");
}

// --- fields

struct PyTensorField {
  std::shared_ptr<const io::LoadedTensors> data;
  std::string source; // the file, or a description of the array
  std::string layout; // the layout name as the user knows it (dipy, world included)
  py::object tensorCache, validCache;
};

struct PyFibreSet {
  std::shared_ptr<const session::FibreInput> data;
  std::string source, layoutGiven, tensorPath;
  py::object directionsCache, amplitudesCache;
};

struct PySurface {
  py::object vertices, faces, normals;
  std::string description;
};

py::object readOnly(py::array a) {
  a.attr("setflags")(py::arg("write") = false);
  return a;
}

PyTensorField wrapTensors(io::LoadedTensors&& t, const std::string& source, const std::string& layout) {
  PyTensorField f;
  // Readers always name a layout; a DWI fitted here has none ("fitted", its reason says from what).
  f.layout = !layout.empty()                      ? layout
             : t.layout == io::TensorLayout::Auto ? "fitted"
                                                  : io::layoutName(t.layout);
  f.data = std::make_shared<const io::LoadedTensors>(std::move(t));
  f.source = source;
  return f;
}

// A field from an array-like or a nibabel image (duck-typed: .dataobj or .get_fdata(), and .affine).
PyTensorField fieldFromPython(const py::object& array, const py::object& affineArg,
                              const std::string& layout) {
  py::module_ np = py::module_::import("numpy");
  py::object values = array, affine = affineArg;
  std::string name = "numpy array";
  const bool image =
      py::hasattr(array, "affine") && (py::hasattr(array, "dataobj") || py::hasattr(array, "get_fdata"));
  if (image) {
    if (affine.is_none()) affine = array.attr("affine");
    values = py::hasattr(array, "dataobj") ? np.attr("asanyarray")(array.attr("dataobj"))
                                           : array.attr("get_fdata")();
    name = "image";
    if (py::hasattr(array, "get_filename")) {
      py::object file = array.attr("get_filename")();
      if (!file.is_none()) name = py::str(file);
    }
  }
  py::array_t<float, py::array::c_style | py::array::forcecast> a;
  try {
    a = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(values);
  } catch (const py::error_already_set&) {
    a = {};
  }
  if (!a) throw InputError(name + ": not an array of numbers");
  std::string shape = "(";
  for (py::ssize_t d = 0; d < a.ndim(); ++d)
    shape += (d ? ", " : "") + std::to_string(a.shape(d));
  shape += a.ndim() == 1 ? ",)" : ")";
  if (!image) name += " " + shape;
  const bool fourD = a.ndim() == 4 && a.shape(3) == 6;
  const bool fiveD = a.ndim() == 5 && a.shape(3) == 1 && a.shape(4) == 6;
  if (!fourD && !fiveD)
    throw InputError(name + ": is not a tensor array: shape " + shape +
                     " (expected (X, Y, Z, 6), or (X, Y, Z, 1, 6) for symmatrix/dtitk/dipy)");
  for (int d = 0; d < 3; ++d)
    if (a.shape(d) > 100000 || a.shape(d) < 1) throw InputError(name + ": absurd shape " + shape);
  if (affine.is_none())
    throw InputError(name + ": an affine (4x4 voxel -> world RAS mm) is needed with a plain array");
  const glm::dmat4 m = affineFromPython(affine, name);
  const glm::ivec3 dims(static_cast<int>(a.shape(0)), static_cast<int>(a.shape(1)),
                        static_cast<int>(a.shape(2)));
  io::LoadedTensors t;
  {
    py::gil_scoped_release release;
    t = tensorsFromArray(a.data(), dims, fiveD, m, layout, name);
  }
  return wrapTensors(std::move(t), name, layout == "auto" ? "" : layout);
}

session::TensorInputOptions tensorOptions(const std::string& layout, const py::object& bval,
                                          const py::object& bvec, const py::object& mask) {
  session::TensorInputOptions in;
  if (!io::isFibreLayoutName(layout)) in.layout = io::parseLayout(layout);
  in.bval = optionalPath(bval);
  in.bvec = optionalPath(bvec);
  in.mask = optionalPath(mask);
  in.quiet = true;
  return in;
}

py::object load(const py::object& path, const std::string& layout, const py::object& bval,
                const py::object& bvec, const py::object& mask, const py::object& tensor) {
  const std::string p = pathText(path);
  const std::string tensorPath = optionalPath(tensor);
  const session::TensorInputOptions in = tensorOptions(layout, bval, bvec, mask);
  std::optional<session::FibreInput> fibres;
  io::LoadedTensors tensors;
  {
    py::gil_scoped_release release;
    const io::OpenedInput opened = io::openInput(session::inputRequest(p, layout, in, in.bval.empty() && in.bvec.empty()));
    if (opened.kind == io::InputKind::Fibres) {
      fibres = session::loadFibreInput(opened, tensorPath, true);
    } else {
      if (!tensorPath.empty())
        throw UsageError("tensor= pairs a tensor with a fibre set; " + p + " is not one");
      tensors = session::loadTensors(opened, in);
    }
  }
  if (fibres) {
    PyFibreSet f;
    f.data = std::make_shared<const session::FibreInput>(std::move(*fibres));
    f.source = p;
    f.layoutGiven = layout;
    f.tensorPath = tensorPath;
    return py::cast(std::move(f));
  }
  return py::cast(wrapTensors(std::move(tensors), p, ""));
}

// The tensors of a field argument: a TensorField, a path (loaded), or an array/image (converted).
std::shared_ptr<const io::LoadedTensors> tensorsOf(const py::object& input, const std::string& layout,
                                                   const py::object& bval, const py::object& bvec,
                                                   const py::object& mask, std::string& source) {
  if (py::isinstance<PyTensorField>(input)) {
    const auto& f = input.cast<const PyTensorField&>();
    source = f.source;
    return f.data;
  }
  if (py::isinstance<PyFibreSet>(input)) {
    const auto& f = input.cast<const PyFibreSet&>();
    if (!f.data->tensor)
      throw UsageError(f.source +
                       " is a fibre set without a paired tensor: load it with tensor=FILE, or pass "
                       "a tensor field");
    source = f.data->tensor->header.path;
    return std::make_shared<const io::LoadedTensors>(*f.data->tensor);
  }
  if (isPathLike(input)) {
    source = pathText(input);
    const session::TensorInputOptions in = tensorOptions(layout, bval, bvec, mask);
    io::LoadedTensors t;
    {
      py::gil_scoped_release release;
      t = session::loadTensorInput(source, in);
    }
    return std::make_shared<const io::LoadedTensors>(std::move(t));
  }
  PyTensorField f = fieldFromPython(input, py::none(), layout);
  source = f.source;
  return f.data;
}

// --- render

// A Python value as the text the option table parses: True/False -> on/off, numbers as Python prints them.
std::string optionText(const py::handle& v) {
  if (py::isinstance<py::bool_>(v)) return v.cast<bool>() ? "on" : "off";
  if (py::isinstance<py::int_>(v) || py::isinstance<py::float_>(v)) return py::str(py::repr(v));
  if (py::isinstance<py::str>(v)) return v.cast<std::string>();
  py::object np = py::module_::import("numpy");
  if (py::isinstance(v, np.attr("number"))) return py::str(py::repr(np.attr("float64")(v)));
  throw py::type_error("fabric options take numbers, booleans or strings, not " +
                       std::string(py::str(py::type::of(v).attr("__name__"))));
}

void setFabricOption(render::FabricParams& p, const std::string& key, const py::handle& value) {
  std::string name = key;
  for (char& c : name)
    if (c == '_') c = '-';
  const render::FabricOption* o = render::findFabricOption(name);
  if (!o) {
    std::string names;
    for (const auto& opt : render::fabricOptions()) {
      std::string n = opt.name;
      for (char& c : n)
        if (c == '-') c = '_';
      names += (names.empty() ? "" : ", ") + n;
    }
    throw py::type_error("render() got an unexpected keyword argument '" + key +
                         "' (fabric options: " + names + ")");
  }
  o->set(p, o->parse(optionText(value)));
}

// A Python value as T, or UsageError "what" when it is not one.
template <typename T> T castOr(const py::handle& v, const char* what) {
  try {
    return v.cast<T>();
  } catch (const py::cast_error&) {
    throw UsageError(std::string(what) + ", got " + std::string(py::str(py::repr(v))));
  }
}

std::pair<int, int> sizeOf(const py::object& size) {
  if (py::isinstance<py::int_>(size)) {
    const int s = size.cast<int>();
    return {s, s};
  }
  return castOr<std::pair<int, int>>(size, "size must be (width, height) in pixels");
}

py::array_t<std::uint8_t> renderImage(const py::object& input, const std::string& surface,
                                      const py::object& view, const py::object& size,
                                      const py::object& colour, bool neurological, bool perspective,
                                      const py::object& background, const py::object& backgroundWindow,
                                      const py::object& tracts, const py::object& tractsColor,
                                      const py::object& tractsRange, const py::object& tractsGroup,
                                      double tractsNear, double tractsSlab, double tractsSlabDepth,
                                      double tractWidth, const py::object& split, const std::string& layout,
                                      const py::object& bval, const py::object& bvec, const py::object& mask,
                                      const py::object& tensor, const py::object& uncertainty,
                                      const py::kwargs& params) {
  session::RenderRequest r;
  std::shared_ptr<const io::LoadedTensors> held;
  r.layout = layout;
  r.tensor = optionalPath(tensor);
  if (py::isinstance<PyFibreSet>(input)) {
    const auto& f = input.cast<const PyFibreSet&>();
    r.input = f.source;
    r.layout = f.layoutGiven;
    if (r.tensor.empty()) r.tensor = f.tensorPath;
  } else if (isPathLike(input)) {
    r.input = pathText(input);
    r.tensorOptions = tensorOptions(layout, bval, bvec, mask);
  } else {
    held = tensorsOf(input, layout, bval, bvec, mask, r.input);
    r.field = &held->field;
  }
  r.surface = session::parseSurfaceSpec(surface);
  if (!view.is_none())
    r.view = render::parseView(castOr<std::string>(view, "view must be a view name or 'azimuth,elevation'"));
  std::tie(r.width, r.height) = sizeOf(size);
  r.neurological = neurological;
  r.perspective = perspective;
  if (!colour.is_none()) {
    r.colourName = optionText(colour);
    setFabricOption(r.params, "color", colour);
    r.colourGiven = true;
  }
  for (const auto& [key, value] : params) {
    const std::string k = py::str(key);
    // The figure's options (the render command's --supersample, --no-letters, --no-legend, --no-scale-bar,
    // --no-colour-bar).
    if (k == "supersample") {
      r.supersample = castOr<int>(value, "supersample must be an integer 1..4");
      continue;
    }
    if (k == "letters" || k == "legend" || k == "scale_bar" || k == "colour_bar") {
      const bool on = castOr<bool>(value, (k + " must be True or False").c_str());
      (k == "letters"      ? r.furniture.letters
       : k == "legend"     ? r.furniture.legend
       : k == "scale_bar"  ? r.furniture.scaleBar
                           : r.furniture.colourBar) = on;
      continue;
    }
    if (k == "color") {
      r.colourName = optionText(value);
      r.colourGiven = true;
    }
    setFabricOption(r.params, k, value);
  }
  r.background = background.is_none() ? "" : optionText(background);
  if (!backgroundWindow.is_none()) {
    auto w = castOr<std::pair<double, double>>(backgroundWindow, "background_window must be (lo, hi)");
    r.backgroundWindow = py::str(py::repr(py::float_(w.first))).cast<std::string>() + "," +
                         py::str(py::repr(py::float_(w.second))).cast<std::string>();
  }
  r.uncertainty = optionalPath(uncertainty);
  r.tracts = optionalPath(tracts);
  if (!tractsColor.is_none())
    r.colouring.value = castOr<std::string>(tractsColor, "tracts_color must be a colouring name");
  if (!tractsRange.is_none()) {
    r.colouring.range = castOr<std::pair<double, double>>(tractsRange, "tracts_range must be (lo, hi)");
    const auto [lo, hi] = *r.colouring.range;
    if (!std::isfinite(lo) || !std::isfinite(hi) || !(lo < hi))
      throw UsageError("tracts_range must be (lo, hi) with lo < hi, got " +
                       std::string(py::str(py::repr(tractsRange))));
  }
  if (!tractsGroup.is_none()) {
    if (py::isinstance<py::str>(tractsGroup))
      r.colouring.groups = {tractsGroup.cast<std::string>()};
    else
      r.colouring.groups = castOr<std::vector<std::string>>(
          tractsGroup, "tracts_group must be a group name or a list of them");
  }
  r.tractsNear = tractsNear;
  r.tractsSlab = tractsSlab;
  r.tractsSlabDepth = tractsSlabDepth;
  r.tractWidth = tractWidth;
  if (!split.is_none())
    r.split = session::parseSplitMode(castOr<std::string>(split, "split must be a split mode name"));
  r.output = "the image of " + r.input;

  session::RenderResult result;
  {
    py::gil_scoped_release release;
    runOnGlThread([&] { result = session::runRender(r); });
  }
  return imageArray(result.image);
}

// --- movie

py::object makeMovie(const py::object& input, const py::object& output, bool turntable, const py::object& sweep,
                     const py::object& faSweep, const std::string& surface, int frames, double fps,
                     const py::object& size, const py::object& view, double elevation, bool neurological,
                     bool perspective, const py::object& background, bool force, const std::string& layout,
                     const py::object& bval, const py::object& bvec, const py::object& mask,
                     const py::kwargs& params) {
  session::MovieRequest m;
  session::RenderRequest& r = m.render;
  std::shared_ptr<const io::LoadedTensors> held;
  if (isPathLike(input)) {
    r.input = pathText(input);
    r.tensorOptions = tensorOptions(layout, bval, bvec, mask);
    r.layout = layout;
  } else {
    held = tensorsOf(input, layout, bval, bvec, mask, r.input);
    r.field = &held->field;
  }
  const int motions = int(turntable) + int(!sweep.is_none()) + int(!faSweep.is_none());
  if (motions != 1) throw UsageError("give exactly one of turntable=True, sweep=AXIS and fa_sweep=(LO, HI)");
  if (turntable) m.kind = session::MovieRequest::Kind::Turntable;
  if (!sweep.is_none()) {
    m.kind = session::MovieRequest::Kind::Sweep;
    m.axis = castOr<std::string>(sweep, "sweep must be axial, coronal or sagittal");
  }
  if (!faSweep.is_none()) {
    m.kind = session::MovieRequest::Kind::FaSweep;
    std::tie(m.faLo, m.faHi) = castOr<std::pair<double, double>>(faSweep, "fa_sweep must be (lo, hi)");
  }
  r.surface = session::parseSurfaceSpec(surface);
  m.frames = frames;
  m.elevationDeg = elevation;
  std::tie(r.width, r.height) = sizeOf(size);
  if (!view.is_none())
    r.view = render::parseView(castOr<std::string>(view, "view must be a view name or 'azimuth,elevation'"));
  r.neurological = neurological;
  r.perspective = perspective;
  r.background = background.is_none() ? "" : optionText(background);
  for (const auto& [key, value] : params) setFabricOption(r.params, py::str(key), value);
  if (r.width < 16 || r.height < 16 || r.width > 8192 || r.height > 8192)
    throw UsageError("size must lie between 16x16 and 8192x8192");

  std::optional<io::MovieWriter> writer;
  std::string out;
  if (!output.is_none()) {
    out = pathText(output);
    r.output = out;
    io::refuseMovieOverInputs(out, {r.input, r.tensorOptions.bval, r.tensorOptions.bvec, r.tensorOptions.mask,
                                    r.surface.file, r.background});
    writer.emplace(out, r.width, r.height, fps, force);
  } else {
    r.output = "the movie of " + r.input;
  }
  std::vector<Image> kept;
  {
    py::gil_scoped_release release;
    runOnGlThread([&] {
      session::runMovie(m, [&](int, const Image& img) {
        if (writer)
          writer->add(img);
        else
          kept.push_back(img);
      });
    });
    if (writer) writer->finish();
  }
  if (writer) return py::str(out);
  py::array_t<std::uint8_t> all({py::ssize_t(kept.size()), py::ssize_t(r.height), py::ssize_t(r.width), py::ssize_t(4)});
  auto* dst = all.mutable_data();
  for (const auto& img : kept) dst = std::copy(img.rgba.begin(), img.rgba.end(), dst);
  return all;
}

// --- web

py::dict makeWeb(const py::object& input, const py::object& output, int size, const std::string& surface,
                 bool slicesOnly, int azimuths, int faSteps, const py::object& background, const py::object& tracts,
                 const py::object& title, bool force, const std::string& layout, const py::object& bval,
                 const py::object& bvec, const py::object& mask) {
  session::WebPageRequest w;
  std::shared_ptr<const io::LoadedTensors> held;
  if (isPathLike(input)) {
    w.input = pathText(input);
    w.tensorOptions = tensorOptions(layout, bval, bvec, mask);
  } else {
    held = tensorsOf(input, layout, bval, bvec, mask, w.input);
    w.field = &held->field;
  }
  w.output = pathText(output);
  w.size = size;
  w.surface = surface;
  w.slicesOnly = slicesOnly;
  w.azimuths = azimuths;
  w.faSteps = faSteps;
  w.background = background.is_none() ? "" : optionText(background);
  w.tracts = tracts.is_none() ? "" : pathText(tracts);
  w.title = title.is_none() ? "" : py::str(title).cast<std::string>();
  w.force = force;
  session::WebPageResult res;
  {
    py::gil_scoped_release release;
    runOnGlThread([&] { res = session::writeWebPage(w); });
  }
  py::dict d;
  d["path"] = w.output;
  d["slices"] = py::make_tuple(res.slices[0], res.slices[1], res.slices[2]);
  d["frames_3d"] = res.frames3d;
  d["fa_frames"] = res.faFrames;
  d["images"] = res.images;
  d["bytes"] = res.bytes;
  d["seconds"] = res.seconds;
  return d;
}

// --- surface, track

PySurface makeSurface(const py::object& input, const std::string& spec, double smooth, double minComponent,
                      double step, double length, double faStop, double seedSpacing, bool clipToData,
                      const std::string& layout, const py::object& bval, const py::object& bvec) {
  std::string source;
  auto tensors = tensorsOf(input, layout, bval, bvec, py::none(), source);
  const session::SurfaceSpec s = session::parseSurfaceSpec(spec);
  session::SurfaceBuildOptions bo;
  bo.smoothSigmaVoxels = smooth;
  bo.minComponentFraction = minComponent;
  bo.fibreStepMm = step;
  bo.fibreLengthMm = length;
  bo.fibreFaStop = faStop;
  bo.fibreSeedSpacingMm = seedSpacing;
  bo.clipToData = clipToData;
  Mesh mesh;
  {
    py::gil_scoped_release release;
    try {
      mesh = session::buildSurface(s, tensors->field, computeFaMap(tensors->field), bo);
    } catch (const Error&) {
      rethrowWithContext("while building the " + session::describeSurface(s) + " of " + source);
    }
    if (mesh.normals.size() != mesh.positions.size()) mesh.computeNormals();
  }
  PySurface out;
  out.description = session::describeSurface(s);
  const auto n = static_cast<py::ssize_t>(mesh.positions.size());
  py::array_t<float> v({n, py::ssize_t(3)}), nr({n, py::ssize_t(3)});
  std::memcpy(v.mutable_data(), mesh.positions.data(), mesh.positions.size() * sizeof(glm::vec3));
  std::memcpy(nr.mutable_data(), mesh.normals.data(), mesh.normals.size() * sizeof(glm::vec3));
  py::array_t<std::int64_t> f({static_cast<py::ssize_t>(mesh.triangleCount()), py::ssize_t(3)});
  std::copy(mesh.indices.begin(), mesh.indices.end(), f.mutable_data());
  out.vertices = readOnly(v);
  out.normals = readOnly(nr);
  out.faces = readOnly(f);
  return out;
}

py::list track(const py::object& input, const py::object& seedsMask, const py::object& seedSphere,
               const py::object& seedSurface, const py::object& seedSlice, const py::object& select,
               const py::object& seeds, int seedsPerVoxel, double step, double faStop, double angle,
               double minLength, double maxLength, bool rk4, const py::object& mask, long long seed,
               int threads, const std::string& layout, const py::object& bval, const py::object& bvec) {
  session::TrackRequest r;
  std::string source;
  auto tensors = tensorsOf(input, layout, bval, bvec, py::none(), source);
  r.input = source;
  r.field = &tensors->field;
  r.seedsMask = optionalPath(seedsMask);
  using K = session::SeedKind;
  if (!r.seedsMask.empty()) r.seeds = K::Mask;
  const int places = !r.seedsMask.empty() + !seedSphere.is_none() + !seedSurface.is_none() + !seedSlice.is_none();
  if (places > 1) throw UsageError("give at most one of seeds_mask, seed_sphere, seed_surface, seed_slice");
  if (!seedSphere.is_none()) {
    auto v = castOr<std::vector<double>>(seedSphere, "seed_sphere must be (x, y, z, radius) in world mm");
    if (v.size() != 4) throw UsageError("seed_sphere must be (x, y, z, radius) in world mm");
    r.seeds = K::Sphere;
    r.centre = glm::dvec3(v[0], v[1], v[2]);
    r.radiusMm = v[3];
  }
  if (!seedSurface.is_none()) {
    r.seeds = K::Surface;
    r.seedSurface =
        session::parseSurfaceSpec(castOr<std::string>(seedSurface, "seed_surface must be a surface spec"));
  }
  if (!seedSlice.is_none()) {
    std::pair<std::string, int> s;
    if (py::isinstance<py::str>(seedSlice)) {
      const std::string t = seedSlice.cast<std::string>();
      const auto colon = t.find(':');
      if (colon == std::string::npos) throw UsageError("seed_slice must be 'AXIS:INDEX', e.g. 'axial:20'");
      try {
        std::size_t used = 0;
        s = {t.substr(0, colon), std::stoi(t.substr(colon + 1), &used)};
        if (used != t.size() - colon - 1) throw std::invalid_argument("");
      } catch (const std::exception&) {
        throw UsageError("seed_slice index '" + t.substr(colon + 1) + "' is not an integer");
      }
    } else {
      s = castOr<std::pair<std::string, int>>(seedSlice, "seed_slice must be 'AXIS:INDEX' or (AXIS, INDEX)");
    }
    r.seeds = K::Slice;
    r.sliceAxis = static_cast<int>(surfaces::parseSliceAxis(s.first));
    r.sliceIndex = s.second;
  }
  if (!select.is_none() && !seeds.is_none()) throw UsageError("give either select or seeds, not both");
  if (!select.is_none()) r.number = castOr<int>(select, "select must be an integer");
  if (!seeds.is_none()) {
    r.count = session::SeedCount::Seeds;
    r.number = castOr<int>(seeds, "seeds must be an integer");
    if (r.number <= 0) throw UsageError("seeds must be positive");
  }
  if (seedsPerVoxel < 0 || (seedsPerVoxel > 0 && r.seedsMask.empty()))
    throw UsageError("seeds_per_voxel K needs seeds_mask and K >= 0");
  if (seedsPerVoxel > 0) {
    r.count = session::SeedCount::PerVoxel;
    r.number = seedsPerVoxel;
  }
  if (seed < 0) throw UsageError("seed must be >= 0");
  r.rngSeed = static_cast<std::uint64_t>(seed);
  r.stopMask = optionalPath(mask);
  r.options.stepMm = step;
  r.options.faStop = faStop;
  r.options.maxAngleDeg = angle;
  r.options.minLengthMm = minLength;
  r.options.maxLengthMm = maxLength;
  r.options.rk4 = rk4;
  if (threads < 0) throw UsageError("threads must be >= 0");
  r.options.threads = threads;
  session::TrackRun run;
  {
    py::gil_scoped_release release;
    run = session::runTrack(r);
  }
  const Polylines& l = run.result.lines;
  py::list out;
  for (std::size_t i = 0; i < l.lineCount(); ++i) {
    const auto n = static_cast<py::ssize_t>(l.offsets[i + 1] - l.offsets[i]);
    py::array_t<float> a({n, py::ssize_t(3)});
    std::memcpy(a.mutable_data(), &l.points[l.offsets[i]], static_cast<std::size_t>(n) * sizeof(glm::vec3));
    out.append(std::move(a));
  }
  return out;
}

// --- profile: the rows of `dtfabric profile`'s table as numpy columns

// One path or several (str, bytes, os.PathLike, or a sequence of them).
std::vector<std::string> pathList(const py::object& o, const char* what) {
  if (isPathLike(o)) return {pathText(o)};
  std::vector<std::string> out;
  if (!py::isinstance<py::sequence>(o)) throw UsageError(std::string(what) + " must be a path or a list of paths");
  for (const auto& item : o) out.push_back(pathText(item));
  return out;
}

// scalars as `--scalar` takes them: "fa", ["fa", "md"], ["fa", "t1=T1.nii.gz"] or {"t1": "T1.nii.gz"}.
std::vector<std::string> scalarTexts(const py::object& o) {
  std::vector<std::string> out;
  if (py::isinstance<py::str>(o)) return {o.cast<std::string>()};
  if (py::isinstance<py::dict>(o)) {
    for (const auto& [k, v] : o.cast<py::dict>())
      out.push_back(castOr<std::string>(k, "scalars' names must be strings") + "=" + pathText(v));
    return out;
  }
  if (!py::isinstance<py::sequence>(o))
    throw UsageError("scalars must be a name, a list of names and NAME=IMAGE texts, or a dict {NAME: IMAGE}");
  for (const auto& item : o) out.push_back(castOr<std::string>(item, "scalars must be strings"));
  return out;
}

py::dict profile(const py::object& tracts, const py::object& scalars, const py::object& tensor,
                 const py::object& groups, int nodes, const std::string& weights, const py::object& start,
                 int bootstrap, long long seed, const py::object& plot, const std::string& layout,
                 const py::object& bval, const py::object& bvec, const py::object& mask) {
  session::ProfileRequest r;
  r.tracts = pathList(tracts, "tracts");
  r.scalars = scalarTexts(scalars);
  r.tensor = optionalPath(tensor);
  if (!groups.is_none()) {
    if (py::isinstance<py::str>(groups)) {
      r.groups = groups.cast<std::string>();
    } else {
      for (const auto& g : groups) r.groups += (r.groups.empty() ? "" : ",") + castOr<std::string>(g, "groups must be strings");
    }
    if (r.groups.empty()) throw UsageError("groups must be 'all' or name at least one group");
  }
  if (nodes < 2) throw UsageError("nodes must be at least 2");
  r.options.nodes = nodes;
  if (weights == "gauss") r.options.weights = surfaces::ProfileWeights::Gauss;
  else if (weights == "mean") r.options.weights = surfaces::ProfileWeights::Mean;
  else if (weights == "median") r.options.weights = surfaces::ProfileWeights::Median;
  else throw UsageError("weights must be 'gauss', 'mean' or 'median', not '" + weights + "'");
  if (!start.is_none()) {
    if (py::isinstance<py::str>(start)) {
      r.start = start.cast<std::string>();
    } else {
      const auto p = castOr<std::vector<double>>(start, "start must be a region spec or (x, y, z)");
      if (p.size() != 3) throw UsageError("start must be a region spec or (x, y, z)");
      char buf[96];
      std::snprintf(buf, sizeof buf, "%.17g,%.17g,%.17g", p[0], p[1], p[2]);
      r.start = buf;
    }
  }
  if (bootstrap < 0) throw UsageError("bootstrap must be >= 0");
  if (seed < 0) throw UsageError("seed must be >= 0");
  r.options.bootstrap = bootstrap;
  r.options.seed = static_cast<std::uint64_t>(seed);
  r.layout = layout;
  r.tensorOptions = tensorOptions("auto", bval, bvec, mask);
  const std::string plotPath = optionalPath(plot);
  render::PlotFormat format = render::PlotFormat::Png;
  if (!plotPath.empty()) {
    if (!render::plotFormatOf(plotPath, format)) throw UsageError("plot must name a .png or .svg file");
    io::refuseOverwritingInput(plotPath, session::profileInputs(r));
  }
  session::ProfileResult result;
  {
    py::gil_scoped_release release;
    result = session::runProfile(r);
    if (!plotPath.empty()) {
      io::AtomicOutput out(plotPath);
      render::writeProfilePlot(session::profileFigure(result), out.tempPath(), format, plotPath);
      out.commit();
    }
  }
  std::size_t rows = 0;
  for (const auto& b : result.bundles) rows += b.profile.scalars.size() * b.profile.core.size();
  const auto n = static_cast<py::ssize_t>(rows);
  py::list bundle, scalar;
  py::array_t<std::int64_t> node(n), count(n);
  py::array_t<double> x(n), y(n), z(n), mean(n), sd(n), lo(n), hi(n);
  std::size_t i = 0;
  for (const auto& b : result.bundles)
    for (const auto& s : b.profile.scalars)
      for (std::size_t k = 0; k < b.profile.core.size(); ++k, ++i) {
        bundle.append(b.name);
        scalar.append(s.name);
        node.mutable_data()[i] = static_cast<std::int64_t>(k);
        x.mutable_data()[i] = b.profile.core[k].x;
        y.mutable_data()[i] = b.profile.core[k].y;
        z.mutable_data()[i] = b.profile.core[k].z;
        mean.mutable_data()[i] = s.mean[k];
        sd.mutable_data()[i] = s.sd[k];
        lo.mutable_data()[i] = s.ciLow[k];
        hi.mutable_data()[i] = s.ciHigh[k];
        count.mutable_data()[i] = static_cast<std::int64_t>(s.streamlines[k]);
      }
  const py::object array = py::module_::import("numpy").attr("array");
  py::dict d;
  d["bundle"] = array(bundle, "str");
  d["scalar"] = array(scalar, "str");
  d["node"] = node;
  d["x"] = x;
  d["y"] = y;
  d["z"] = z;
  d["mean"] = mean;
  d["sd"] = sd;
  d["ci_low"] = lo;
  d["ci_high"] = hi;
  d["streamlines"] = count;
  return d;
}

// --- check: the keys of `dtfabric check --json`

py::list matrixList(const surfaces::AxisTransform& t) {
  py::list rows;
  for (int row = 0; row < 3; ++row) {
    py::list r;
    for (int col = 0; col < 3; ++col)
      r.append(t.m[static_cast<std::size_t>(row * 3 + col)]);
    rows.append(r);
  }
  return rows;
}

py::dict check(const py::object& input, const py::object& bval, const py::object& bvec,
               const py::object& mask, const std::string& layout, const py::object& tensor, double minMargin,
               int minWhiteMatter) {
  session::CheckRequest req;
  req.input = pathText(input);
  req.bval = optionalPath(bval);
  req.bvec = optionalPath(bvec);
  req.mask = optionalPath(mask);
  req.tensor = optionalPath(tensor);
  if (!(minMargin >= 0 && minMargin <= 10)) throw UsageError("min_margin must be in [0, 10]");
  if (minWhiteMatter < 1) throw UsageError("min_white_matter must be at least 1");
  req.options.minMargin = minMargin;
  req.options.minWhiteMatter = static_cast<std::size_t>(minWhiteMatter);
  session::CheckRun run;
  {
    py::gil_scoped_release release;
    req.fibres = req.bval.empty() && req.bvec.empty() && session::isFibreSet(req.input, layout);
    if (req.fibres)
      req.fibreLayout = layout;
    else
      req.layout = io::parseLayout(layout);
    run = session::runCheck(req);
  }
  const surfaces::OrientationReport& r = run.report;
  py::dict d;
  d["input"] = req.input;
  d["kind"] = run.dwi ? "dwi" : run.fibres ? "fibres" : "tensor";
  d["frame"] = run.frameName;
  d["verdict"] = surfaces::verdictName(r.verdict);
  d["reason"] = r.reason;
  if (!run.dwi) d["layout"] = run.layoutNote;
  d["correction"] = matrixList(r.correction);
  d["correction_name"] = r.correction.name();
  d["score_given"] = r.scoreGiven;
  d["score_best"] = r.scoreBest;
  d["margin"] = r.margin;
  d["best"] = r.candidates[r.best].transform.name();
  d["runner_up"] = r.candidates[r.runnerUp].transform.name();
  d["mask_voxels"] = r.maskVoxels;
  d["white_matter_voxels"] = r.whiteMatterVoxels;
  d["white_matter_rule"] = r.whiteMatterRule;
  py::dict thresholds;
  thresholds["fa"] = r.options.faThreshold;
  thresholds["cos"] = r.options.cosThreshold;
  thresholds["min_white_matter"] = r.options.minWhiteMatter;
  thresholds["min_margin"] = r.options.minMargin;
  d["thresholds"] = thresholds;
  py::dict seconds;
  seconds["load"] = run.loadSeconds;
  seconds["fit"] = run.fitSeconds;
  seconds["check"] = run.checkSeconds;
  d["seconds"] = seconds;
  py::list candidates;
  for (const auto& c : r.candidates) {
    py::dict e;
    e["name"] = c.transform.name();
    e["matrix"] = matrixList(c.transform);
    e["score"] = c.score;
    e["pairs"] = c.pairs;
    candidates.append(e);
  }
  d["candidates"] = candidates;
  return d;
}

// --- exceptions

bool isFileProblem(const std::string& m) {
  for (const char* p : {": file does not exist", ": is a directory", "cannot open", "cannot write",
                        "No such file", "Permission denied"})
    if (m.find(p) != std::string::npos) return true;
  return false;
}

void raise(const char* cls, const std::string& message) {
  py::object type = py::module_::import("dtfabric._errors").attr(cls);
  PyErr_SetObject(type.ptr(), py::str(message).ptr());
}

// A tracking parameter's keyword (its table name with '_' for '-') with TrackingParams' default.
py::arg_v trackArg(const char* pythonName) {
  std::string name = pythonName;
  std::replace(name.begin(), name.end(), '_', '-');
  const surfaces::TrackingParameter* p = surfaces::findTrackingParameter(name);
  if (!p) throw std::logic_error(std::string("no tracking parameter ") + name);
  return py::arg(pythonName) = p->get(surfaces::TrackingParams{});
}

} // namespace

} // namespace dtf::python

using namespace dtf;
using namespace dtf::python;

namespace {

// The library's errors as the package's exception classes (dtfabric/_errors.py defines them).
void registerErrors() {
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const UsageError& e) {
      raise("UsageError", e.what());
    } catch (const InputError& e) {
      raise(isFileProblem(e.what()) ? "FileError" : "FormatError", e.what());
    } catch (const GlError& e) {
      raise("GlError", e.what());
    } catch (const Error& e) {
      raise("Error", e.what());
    } catch (const std::exception& e) {
      // A file system call's failure (a loop of links, a folder without access) is a file problem; anything
      // else is left to pybind11's own translation.
      const std::string fs = filesystemErrorMessage(e);
      if (fs.empty()) throw;
      raise("FileError", fs);
    }
  });
}

// dtfabric.TensorField: tensors from files or arrays.
void bindTensorField(py::module_& m) {
  py::class_<PyTensorField>(m, "TensorField", R"(A tensor volume in dtfabric's canonical form.

TensorField(array, affine=None, layout="auto")
  array   (X, Y, Z, 6) or (X, Y, Z, 1, 6) numbers in `layout`, or a nibabel image (its data and affine)
  affine  4x4 voxel -> world RAS mm (required with a plain array)
  layout  auto | fsl | mrtrix | symmatrix | dtitk | dipy | world
          dipy: TensorFit.lower_triangular() (xx xy yy xz yz zz in the gradient table's frame: voxel axes,
          x negated when det(affine) > 0, as FSL); world: the order and frame of .tensor)")
      .def(py::init([](const py::object& array, const py::object& affine, const std::string& layout) {
             return fieldFromPython(array, affine, layout);
           }),
           py::arg("array"), py::arg("affine") = py::none(), py::arg("layout") = "auto")
      .def_property_readonly(
          "tensor",
          [](PyTensorField& f) {
            if (!f.tensorCache) f.tensorCache = readOnly(tensorArray(f.data->field));
            return f.tensorCache;
          },
          "(X, Y, Z, 6) float32, world RAS, xx xy xz yy yz zz, mm^2/s, NaN where invalid (read-only)")
      .def_property_readonly(
          "valid",
          [](PyTensorField& f) {
            if (!f.validCache) {
              const Grid& g = f.data->field.grid;
              py::array_t<bool> a({g.dims.x, g.dims.y, g.dims.z});
              bool* out = a.mutable_data();
              for (int i = 0; i < g.dims.x; ++i)
                for (int j = 0; j < g.dims.y; ++j)
                  for (int k = 0; k < g.dims.z; ++k)
                    *out++ = f.data->field.valid[g.index(i, j, k)] != 0;
              f.validCache = readOnly(a);
            }
            return f.validCache;
          },
          "(X, Y, Z) bool: where the field holds a finite, non-zero tensor")
      .def_property_readonly(
          "affine", [](const PyTensorField& f) { return affineArray(f.data->field.grid); },
          "4x4 float64, voxel (i, j, k) -> world RAS mm")
      .def_property_readonly("shape",
                             [](const PyTensorField& f) {
                               const auto& d = f.data->field.grid.dims;
                               return py::make_tuple(d.x, d.y, d.z);
                             })
      .def_property_readonly("layout", [](const PyTensorField& f) { return f.layout; })
      .def_property_readonly("layout_reason", [](const PyTensorField& f) { return f.data->layoutReason; })
      .def_property_readonly("warnings", [](const PyTensorField& f) { return f.data->warnings; })
      .def_property_readonly("source", [](const PyTensorField& f) { return f.source; })
      .def_property_readonly("nan_voxels", [](const PyTensorField& f) { return f.data->nanVoxels; })
      .def(
          "fa",
          [](const PyTensorField& f) {
            ScalarVolume fa;
            {
              py::gil_scoped_release release;
              fa = computeFaMap(f.data->field);
            }
            return scalarArray(fa);
          },
          "(X, Y, Z) float32 fractional anisotropy (0 where invalid)")
      .def("__repr__", [](const PyTensorField& f) {
        const auto& d = f.data->field.grid.dims;
        return "<dtfabric.TensorField " + std::to_string(d.x) + "x" + std::to_string(d.y) + "x" +
               std::to_string(d.z) + " layout=" + f.layout + " from " + f.source + ">";
      });
}

// dtfabric.FibreSet: fibre populations from files.
void bindFibreSet(py::module_& m) {
  py::class_<PyFibreSet>(m, "FibreSet",
                         "Crossing fibres per voxel (unit world-RAS directions, strongest first).")
      .def_property_readonly(
          "directions",
          [](PyFibreSet& f) {
            if (!f.directionsCache) f.directionsCache = readOnly(fibreDirections(f.data->fibres.set));
            return f.directionsCache;
          },
          "(X, Y, Z, K, 3) float32 unit directions, world RAS, strongest first, NaN where absent")
      .def_property_readonly(
          "amplitudes",
          [](PyFibreSet& f) {
            if (!f.amplitudesCache) f.amplitudesCache = readOnly(fibreAmplitudes(f.data->fibres.set));
            return f.amplitudesCache;
          },
          "(X, Y, Z, K) float32 amplitudes or fractions, 0 where absent")
      .def_property_readonly("affine",
                             [](const PyFibreSet& f) { return affineArray(f.data->fibres.set.grid); })
      .def_property_readonly("shape",
                             [](const PyFibreSet& f) {
                               const auto& d = f.data->fibres.set.grid.dims;
                               return py::make_tuple(d.x, d.y, d.z);
                             })
      .def_property_readonly(
          "layout",
          [](const PyFibreSet& f) { return std::string(io::fibreLayoutName(f.data->fibres.layout)); })
      .def_property_readonly("layout_reason", [](const PyFibreSet& f) { return f.data->fibres.layoutReason; })
      .def_property_readonly("warnings", [](const PyFibreSet& f) { return f.data->fibres.warnings; })
      .def_property_readonly("files", [](const PyFibreSet& f) { return f.data->fibres.files; })
      .def_property_readonly("source", [](const PyFibreSet& f) { return f.source; })
      .def_property_readonly(
          "fa",
          [](const PyFibreSet& f) -> py::object {
            if (f.data->fa.data.empty()) return py::none();
            return scalarArray(f.data->fa);
          },
          "(X, Y, Z) FA of the paired tensor or the file's own, or None")
      .def_property_readonly(
          "tensor",
          [](const PyFibreSet& f) -> py::object {
            if (!f.data->tensor) return py::none();
            return py::cast(wrapTensors(io::LoadedTensors(*f.data->tensor), f.tensorPath, ""));
          },
          "the paired TensorField (load(..., tensor=FILE)), or None")
      .def("__repr__", [](const PyFibreSet& f) {
        const auto& s = f.data->fibres.set;
        return "<dtfabric.FibreSet " + std::to_string(s.grid.dims.x) + "x" + std::to_string(s.grid.dims.y) +
               "x" + std::to_string(s.grid.dims.z) + " K=" + std::to_string(s.maxFibres) +
               " layout=" + io::fibreLayoutName(f.data->fibres.layout) + " from " + f.source + ">";
      });
}

// load, render, surface, track, check and the helpers.
void bindSessions(py::module_& m) {
  py::class_<PySurface>(m, "Surface", "A triangle mesh in world RAS mm.")
      .def_readonly("vertices", &PySurface::vertices, "(N, 3) float32 positions, world RAS mm")
      .def_readonly("faces", &PySurface::faces, "(M, 3) int64 vertex indices, counter-clockwise from outside")
      .def_readonly("normals", &PySurface::normals, "(N, 3) float32 unit vertex normals")
      .def_readonly("description", &PySurface::description)
      .def("__repr__", [](const PySurface& s) {
        return "<dtfabric.Surface " + s.description + ", " + std::to_string(py::len(s.vertices)) +
               " vertices, " + std::to_string(py::len(s.faces)) + " triangles>";
      });

  m.def("load", &load, py::arg("path"), py::arg("layout") = "auto", py::arg("bval") = py::none(),
        py::arg("bvec") = py::none(), py::arg("mask") = py::none(), py::arg("tensor") = py::none(),
        R"(Loads a tensor volume, a DWI (fitted: WLS) or a fibre set, as `dtfabric render` reads INPUT.

layout: auto, a tensor layout (fsl, mrtrix, symmatrix, dtitk) or a fibre layout (mrtrix-peaks, dipy-peaks,
bedpostx). bval/bvec: treat path as a DWI. mask: the DWI fit mask. tensor: a tensor file paired with a fibre
set. Returns a TensorField or a FibreSet.)");

  m.def("render", &renderImage, py::arg("input"), py::arg("surface") = "slice=axial",
        py::arg("view") = py::none(), py::arg("size") = std::make_pair(768, 768),
        py::arg("colour") = py::none(), py::arg("neurological") = false, py::arg("perspective") = false,
        py::arg("background") = py::none(), py::arg("background_window") = py::none(),
        py::arg("tracts") = py::none(), py::arg("tracts_color") = py::none(),
        py::arg("tracts_range") = py::none(), py::arg("tracts_group") = py::none(),
        py::arg("tracts_near") = 3.0, py::arg("tracts_slab") = 0.0, py::arg("tracts_slab_depth") = 0.0,
        py::arg("tract_width") = 2.0, py::arg("split") = py::none(), py::arg("layout") = "auto",
        py::arg("bval") = py::none(), py::arg("bvec") = py::none(), py::arg("mask") = py::none(),
        py::arg("tensor") = py::none(), py::arg("uncertainty") = py::none(),
        R"(Renders the fabric headless: the pixels `dtfabric render` writes for the same arguments.

input: a TensorField, a FibreSet from load(), a path, or an array/nibabel image (layout= names its layout).
surface: a surface spec (fa=T, slice=AXIS[:I], plane=..., fibre=..., mesh=FILE; '+' joins).
view, size=(W, H), colour, neurological, perspective, background, background_window=(lo, hi), tracts,
tracts_color, tracts_range=(lo, hi), tracts_group, tracts_near, tracts_slab, tracts_slab_depth, tract_width,
split, uncertainty (a cone map or bedpostx folder: the threads fray): as the command's flags. supersample=N
(1..4) and letters=, legend=, scale_bar=, colour_bar= (True/False) as its Figure flags. Further keyword arguments are the
fabric options of `dtfabric render --help` with '-' written '_' (blend_k=0.1, lighting=False, look='plain',
...). Returns (H, W, 4) uint8 RGBA, row 0 at the top.)");

  m.def("movie", &makeMovie, py::arg("input"), py::arg("output") = py::none(), py::arg("turntable") = false,
        py::arg("sweep") = py::none(), py::arg("fa_sweep") = py::none(), py::arg("surface") = "fa=0.25",
        py::arg("frames") = 36, py::arg("fps") = 12.0, py::arg("size") = std::make_pair(512, 512),
        py::arg("view") = py::none(), py::arg("elevation") = 20.0, py::arg("neurological") = false,
        py::arg("perspective") = false, py::arg("background") = py::none(), py::arg("force") = false,
        py::arg("layout") = "auto", py::arg("bval") = py::none(), py::arg("bvec") = py::none(),
        py::arg("mask") = py::none(),
        R"(A movie of the fabric, as `dtfabric movie` makes it: exactly one of turntable=True, sweep="axial"
(coronal, sagittal) or fa_sweep=(lo, hi). The advection state is carried from frame to frame (no re-seeded
flicker). output: OUT.mp4 or OUT.gif (through the ffmpeg program on PATH) or "DIR/" (numbered PNG frames),
written atomically, an existing output replaced only with force=True; returns its path. output=None returns
the frames as an (N, H, W, 4) uint8 array. surface (the turntable's), frames, fps, size=(W, H), view,
elevation, neurological, perspective, background, layout, bval, bvec, mask: as the command's flags; further
keyword arguments are the fabric options (frame_iterations=3, blend_k=0.1, ...).)");

  m.def("web", &makeWeb, py::arg("input"), py::arg("output"), py::arg("size") = session::WebPageRequest{}.size,
        py::arg("surface") = "fa=0.25", py::arg("slices_only") = false,
        py::arg("azimuths") = session::WebPageRequest{}.azimuths, py::arg("fa_steps") = session::WebPageRequest{}.faSteps,
        py::arg("background") = py::none(), py::arg("tracts") = py::none(), py::arg("title") = py::none(),
        py::arg("force") = false, py::arg("layout") = "auto", py::arg("bval") = py::none(),
        py::arg("bvec") = py::none(), py::arg("mask") = py::none(),
        R"(Writes the folder of `dtfabric web` (index.html, the slices, the 3D view and the FA sweep) and returns
a dict: path, slices (axial, coronal, sagittal), frames_3d, fa_frames, images, bytes, seconds. dtfabric.web()
wraps it in a WebPage that shows the page inline in Jupyter.)");

  m.def("surface", &makeSurface, py::arg("field"), py::arg("spec"), py::arg("smooth") = 0.6,
        py::arg("min_component") = 0.02, py::arg("step") = 0.5, py::arg("length") = 40.0,
        py::arg("fa_stop") = 0.15, py::arg("seed_spacing") = 0.75, py::arg("clip_to_data") = true,
        py::arg("layout") = "auto", py::arg("bval") = py::none(), py::arg("bvec") = py::none(),
        "Builds a surface of a tensor field (a TensorField, path or array) as `dtfabric surface` does.");

  m.def(
      "track", &track, py::arg("field"), py::arg("seeds_mask") = py::none(),
      py::arg("seed_sphere") = py::none(), py::arg("seed_surface") = py::none(),
      py::arg("seed_slice") = py::none(), py::arg("select") = py::none(), py::arg("seeds") = py::none(),
      py::arg("seeds_per_voxel") = 0, trackArg("step"), trackArg("fa_stop"), trackArg("angle"),
      trackArg("min_length"), trackArg("max_length"), py::arg("rk4") = surfaces::TrackingParams{}.rk4, py::arg("mask") = py::none(), py::arg("seed") = 1, py::arg("threads") = 0,
      py::arg("layout") = "auto", py::arg("bval") = py::none(), py::arg("bvec") = py::none(),
      R"(Deterministic tensor tractography as `dtfabric track`: a list of (N, 3) float32 streamlines, world RAS mm.
Default: select=1000 streamlines seeded where the field holds a tensor.)");

  m.def("profile", &profile, py::arg("tracts"), py::arg("scalars"), py::arg("tensor") = py::none(),
        py::arg("groups") = py::none(), py::arg("nodes") = surfaces::ProfileOptions{}.nodes,
        py::arg("weights") = "gauss", py::arg("start") = py::none(),
        py::arg("bootstrap") = surfaces::ProfileOptions{}.bootstrap,
        py::arg("seed") = static_cast<long long>(surfaces::ProfileOptions{}.seed), py::arg("plot") = py::none(),
        py::arg("layout") = "auto", py::arg("bval") = py::none(), py::arg("bvec") = py::none(),
        py::arg("mask") = py::none(),
        R"(Tract profiles as `dtfabric profile`: each tract file (or each group, with groups='all' or a list of
names) a bundle; scalars "fa", "md", "ad", "rd" (of `tensor`, a tensor file or a DWI) or "NAME=IMAGE" texts
(or a dict {NAME: IMAGE}); weights 'gauss' (DIPY gaussian_weights), 'mean' or 'median'; start a region spec
or an (x, y, z) point the streamlines start near. Returns the table's columns as a dict of numpy arrays
(bundle, scalar, node, x, y, z, mean, sd, ci_low, ci_high, streamlines), one entry per bundle, scalar and node:
pandas.DataFrame(result) is the table. plot: also write the figure (.png or .svg).)");

  m.def("check", &check, py::arg("input"), py::arg("bval") = py::none(), py::arg("bvec") = py::none(),
        py::arg("mask") = py::none(), py::arg("layout") = "auto", py::arg("tensor") = py::none(),
        py::arg("min_margin") = 0.07, py::arg("min_white_matter") = 3000,
        "The orientation check of a DWI with its table, a tensor file or a fibre set: the dict of "
        "`dtfabric check --json`.");

  m.def(
      "uncertainty",
      [](const py::object& path) {
        const std::string p = pathText(path);
        std::vector<ScalarVolume> cones;
        {
          py::gil_scoped_release release;
          if (io::isBedpostxSamplesPath(p))
            cones = io::readBedpostxSamples(p).cone;
          else
            cones.push_back(io::readConeMap(p));
        }
        if (cones.size() == 1) return py::make_tuple(scalarArray(cones[0]), affineArray(cones[0].grid));
        ScalarVolume all(cones[0].grid, static_cast<int>(cones.size()));
        for (std::size_t v = 0; v < all.grid.voxelCount(); ++v)
          for (std::size_t c = 0; c < cones.size(); ++c)
            all.data[v * cones.size() + c] = cones[c].data[v];
        return py::make_tuple(scalarArray(all), affineArray(all.grid));
      },
      py::arg("path"),
      R"(Reads a cone-of-uncertainty map (degrees, NaN outside the mask) as `render --uncertainty` does: a NIfTI
from `dtfabric fit --bootstrap N --cone FILE`, or a bedpostx folder with merged_thN/phN/fNsamples (one cone per
population). Returns (cone, affine): float32 (X, Y, Z), or (X, Y, Z, K) for K populations, and the 4x4
voxel -> world RAS affine.)");

  m.def(
      "bootstrap",
      [](const py::object& dwiPath, const py::object& bval, const py::object& bvec, const py::object& mask,
         int resamples, int threads) {
        const std::string p = pathText(dwiPath);
        session::TensorInputOptions in = tensorOptions("auto", bval, bvec, mask);
        io::UncertaintyMaps maps;
        io::LoadedTensors t;
        {
          py::gil_scoped_release release;
          // As `dtfabric fit`: the DWI's own table (MRtrix, DSI Studio) or sibling .bval/.bvec by default.
          if (in.bval.empty() && in.bvec.empty() && !io::hasEmbeddedGradients(p)) {
            in.bval = io::gradientSibling(p, ".bval");
            in.bvec = io::gradientSibling(p, ".bvec");
          }
          io::Dwi dwi = io::readDwi(p, in.bval, in.bvec);
          MaskVolume m;
          if (!in.mask.empty()) {
            ScalarVolume v = io::readScalarVolume(in.mask);
            m = MaskVolume(v.grid, 1, 0);
            for (std::size_t i = 0; i < m.data.size(); ++i)
              m.data[i] = v.data[i * static_cast<std::size_t>(v.components)] != 0 ? 1 : 0;
          }
          io::FitOptions o;
          o.threads = threads;
          io::BootstrapOptions b;
          b.resamples = resamples;
          t.field = io::bootstrapTensors(dwi, in.mask.empty() ? nullptr : &m, o, b, maps);
        }
        py::dict d;
        d["cone"] = scalarArray(maps.cone);
        d["fa_sd"] = scalarArray(maps.faSd);
        d["affine"] = affineArray(maps.cone.grid);
        d["tensors"] = py::cast(wrapTensors(std::move(t), p, ""));
        return d;
      },
      py::arg("dwi"), py::arg("bval") = py::none(), py::arg("bvec") = py::none(), py::arg("mask") = py::none(),
      py::arg("resamples") = 200, py::arg("threads") = 0,
      R"(Wild bootstrap of the WLS tensor fit as `dtfabric fit --bootstrap N`: a dict with "cone" (float32
(X, Y, Z), the 95 % cone of uncertainty of the principal direction in degrees, NaN outside the mask), "fa_sd"
(FA's bootstrap standard deviation), "affine" and "tensors" (the fit, a TensorField).)");

  m.def(
      "read_png",
      [](const py::object& path) {
        const std::string p = pathText(path);
        Image img;
        {
          py::gil_scoped_release release;
          img = io::readPng(p);
        }
        return imageArray(img);
      },
      py::arg("path"), "Reads a PNG as (H, W, 4) uint8 RGBA.");

  m.def(
      "fabric_options",
      [] {
        py::dict d;
        for (const auto& o : render::fabricOptions()) {
          std::string n = o.name;
          for (char& c : n)
            if (c == '-') c = '_';
          d[py::str(n)] = o.help;
        }
        return d;
      },
      "The fabric options render() takes as keyword arguments, with their help.");
}
} // namespace

PYBIND11_MODULE(_core, m) {
  m.doc() = "dtfabric's C++ core (use the package dtfabric)";
  m.attr("__version__") = DTF_VERSION; // project(dtfabric VERSION ...) in CMakeLists.txt
  // Warnings and errors of the libraries go to stderr, as the command-line tool prints them; notes are
  // dropped (the fields carry their layout reasons and warnings).
  setLogSink([](LogLevel level, const std::string& message) {
    if (level == LogLevel::Warning || level == LogLevel::Error)
      std::fprintf(stderr, "dtfabric: %s: %s\n", level == LogLevel::Warning ? "warning" : "error",
                   message.c_str());
  });

  registerErrors();
  bindTensorField(m);
  bindFibreSet(m);
  bindSessions(m);
  bindTracts(m);
}
