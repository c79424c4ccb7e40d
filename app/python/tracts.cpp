// SPDX-License-Identifier: GPL-3.0-or-later
// dtfabric.select: ROI selection from Python with `dtfabric select`'s parameters and code
// (ui/session/tract_select.h), numpy in and out.
#include "app/python/arrays.h"
#include "io/formats/atomic_file.h"
#include "io/model/error.h"
#include "surfaces/selection/tract_selection.h"
#include "ui/session/region_spec.h"
#include "ui/session/tract_files.h"
#include "ui/session/tract_select.h"

#include <cmath>
#include <cstring>
#include <limits>

namespace dtf::python {

namespace {

// Streamlines given as a list of (N, 3) arrays, world RAS mm.
Polylines linesFromArrays(const py::sequence& seq) {
  Polylines p;
  p.offsets.push_back(0);
  for (const py::handle& item : seq) {
    const auto a = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(item);
    if (!a || a.ndim() != 2 || a.shape(1) != 3)
      throw InputError("streamline " + std::to_string(p.lineCount()) + ": expected an (N, 3) array of points");
    const auto* d = a.data();
    for (py::ssize_t i = 0; i < a.shape(0); ++i) {
      const glm::vec3 v(d[3 * i], d[3 * i + 1], d[3 * i + 2]);
      if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z))
        throw InputError("streamline " + std::to_string(p.lineCount()) + ": point " + std::to_string(i) +
                         " is not finite");
      p.points.push_back(v);
    }
    p.offsets.push_back(static_cast<std::uint32_t>(p.points.size()));
  }
  return p;
}

std::vector<std::string> specList(const py::object& o, const char* name) {
  std::vector<std::string> out;
  if (o.is_none()) return out;
  if (py::isinstance<py::str>(o)) return {o.cast<std::string>()};
  for (const py::handle& h : o) {
    if (!py::isinstance<py::str>(h) && !py::hasattr(h, "__fspath__"))
      throw UsageError(std::string(name) + " takes a SPEC string or a list of them");
    out.push_back(py::isinstance<py::str>(h) ? h.cast<std::string>() : pathText(h));
  }
  return out;
}

py::dict selectTracts(const py::object& tracts, const py::object& include, const py::object& exclude,
                      const py::object& includeOrdered, const py::object& roi, bool endsOnly, bool precise,
                      double minLength, const py::object& maxLength, const py::object& output,
                      const py::object& asGroup, const py::object& reference, bool force, int threads) {
  if (threads < 0) throw UsageError("threads must be >= 0");
  session::LoadedTracts in;
  std::vector<std::string> inputs;
  const bool paths = py::isinstance<py::str>(tracts) || py::isinstance<py::bytes>(tracts) ||
                     py::hasattr(tracts, "__fspath__");
  if (paths)
    inputs.push_back(pathText(tracts));
  else if (py::isinstance<py::sequence>(tracts) && py::len(tracts) > 0) {
    const py::sequence seq = tracts.cast<py::sequence>();
    const py::handle first = seq[0];
    if (py::isinstance<py::str>(first) || py::isinstance<py::bytes>(first) || py::hasattr(first, "__fspath__"))
      for (const py::handle& h : seq)
        inputs.push_back(pathText(h));
    else
      in.lines = linesFromArrays(seq);
  } else if (py::isinstance<py::sequence>(tracts)) {
    in.lines.offsets.push_back(0);
  } else {
    throw UsageError("tracts takes a tract file, a list of them, or a list of (N, 3) arrays");
  }

  surfaces::RegionSet set;
  if (!roi.is_none()) set = session::readRegionSetFile(pathText(roi));
  for (const auto& s : specList(include, "include"))
    set.regions.push_back(session::parseRegionSpec(s, surfaces::RegionKind::Include));
  for (const auto& s : specList(exclude, "exclude"))
    set.regions.push_back(session::parseRegionSpec(s, surfaces::RegionKind::Exclude));
  for (const auto& s : specList(includeOrdered, "include_ordered"))
    set.regions.push_back(session::parseRegionSpec(s, surfaces::RegionKind::IncludeOrdered));
  set.endsOnly = set.endsOnly || endsOnly;
  set.precise = set.precise || precise;
  set.minLengthMm = minLength;
  if (!maxLength.is_none()) set.maxLengthMm = maxLength.cast<double>();
  surfaces::validate(set);

  const std::string out = optionalPath(output);
  const std::string group = asGroup.is_none() ? std::string() : asGroup.cast<std::string>();
  const std::optional<std::string> ref =
      reference.is_none() ? std::nullopt : std::optional<std::string>(pathText(reference));
  if (!out.empty()) {
    session::SelectRequest check;
    check.inputs = inputs.empty() ? std::vector<std::string>{"<arrays>"} : inputs;
    check.output = out;
    check.regions = set;
    check.asGroup = group;
    check.reference = ref;
    session::checkSelectRequest(check);
    if (!roi.is_none()) io::refuseOverwritingInput(out, {pathText(roi)});
    if (!force && io::outputExists(out)) throw InputError(out + " exists (use force=True to overwrite)");
  } else if (!group.empty()) {
    throw UsageError("as_group needs an output .trx file");
  }

  std::vector<std::uint32_t> keep;
  {
    py::gil_scoped_release release;
    if (!inputs.empty()) in = session::readTractInputs(inputs, ref);
    else if (ref) in.grid = session::referenceGridOf(*ref);
    keep = session::selectIndices(in.lines, set, false, threads);
    if (!out.empty()) session::writeSelection(out, in, keep, group, inputs.empty() ? "<arrays>" : inputs.front());
  }
  py::array_t<std::uint32_t> indices(static_cast<py::ssize_t>(keep.size()));
  if (!keep.empty()) std::memcpy(indices.mutable_data(), keep.data(), keep.size() * sizeof(std::uint32_t));
  py::list lines;
  for (std::uint32_t i : keep) {
    const auto n = static_cast<py::ssize_t>(in.lines.offsets[i + 1] - in.lines.offsets[i]);
    py::array_t<float> a({n, py::ssize_t(3)});
    // Through a const view: a TRX's positions are read in place, and non-const access would copy them all.
    const Polylines& from = in.lines;
    if (n)
      std::memcpy(a.mutable_data(), &from.points[from.offsets[i]], static_cast<std::size_t>(n) * sizeof(glm::vec3));
    lines.append(std::move(a));
  }
  py::dict d;
  d["indices"] = indices;
  d["streamlines"] = lines;
  d["total"] = in.lines.lineCount();
  return d;
}

} // namespace

void bindTracts(py::module_& m) {
  m.def("select", &selectTracts, py::arg("tracts"), py::arg("include") = py::none(),
        py::arg("exclude") = py::none(), py::arg("include_ordered") = py::none(), py::arg("roi") = py::none(),
        py::arg("ends_only") = false, py::arg("precise") = false, py::arg("min_length") = 0.0,
        py::arg("max_length") = py::none(), py::arg("output") = py::none(), py::arg("as_group") = py::none(),
        py::arg("reference") = py::none(), py::arg("force") = false, py::arg("threads") = 0,
        R"(ROI selection as `dtfabric select`: the streamlines of `tracts` (a tract file, a list of files that are
concatenated, or a list of (N, 3) arrays in world RAS mm) through every `include` region and no `exclude`
region, `include_ordered` regions entered in order, as MRtrix's tckedit on the stored vertices (`precise`: also
the segments between them; `ends_only`: the two end points). A region is a SPEC string as the command takes it
(X,Y,Z,R | box:X0,Y0,Z0,X1,Y1,Z1 | IMAGE | IMAGE:L[,L...]); `roi` a region set file. With `output`, the kept
streamlines (or, with `as_group`, every streamline and the selection as a TRX group) are written as the command
writes them. Returns a dict: "indices" (uint32, ascending, into the concatenated input), "streamlines" (a list of
(N, 3) float32 arrays) and "total" (the input's streamline count).)");
}

} // namespace dtf::python
