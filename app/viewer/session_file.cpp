// SPDX-License-Identifier: GPL-3.0-or-later
#include "app/viewer/session_file.h"

#include "io/formats/atomic_file.h"
#include "io/model/error.h"
#include "render/fabric_options.h"
#include "ui/session/region_spec.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace dtf::app {

namespace fs = std::filesystem;

namespace {

std::string absolute(const std::string& path) {
  if (path.empty()) return path;
  std::error_code ec;
  const fs::path p = fs::absolute(path, ec);
  return ec ? path : p.lexically_normal().string();
}

std::string num(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

std::string triple(const glm::dvec3& v) {
  return num(v.x) + "," + num(v.y) + "," + num(v.z);
}

const char* onOff(bool on) {
  return on ? "on" : "off";
}

// A surface spec in the syntax of ui/session/surface_spec.h with its files absolute.
std::string specText(const session::SurfaceSpec& s) {
  using K = session::SurfaceSpec::Kind;
  switch (s.kind) {
  case K::Fa:
    return "fa=" + num(s.value);
  case K::Slice:
    return "slice=" + s.axis + (s.index >= 0 ? ":" + std::to_string(s.index) : "");
  case K::Mesh:
    return "mesh=" + absolute(s.file);
  case K::Iso:
    return "iso=" + absolute(s.file) + ":" + num(s.value);
  case K::Combined: {
    std::string text;
    for (const auto& part : s.parts)
      text += (text.empty() ? "" : "+") + specText(part);
    return text;
  }
  case K::Plane:
  case K::Fibre:
    return s.text; // no files
  }
  return s.text;
}

std::string cameraLine(const render::Camera& c, int pane) {
  std::string line = "camera";
  if (pane >= 0) line += " pane=" + std::to_string(pane);
  line += " eye=" + triple(c.eye) + " target=" + triple(c.target) + " up=" + triple(c.up);
  line += c.orthographic ? " ortho=" + num(c.orthoHalfHeight) : " fov=" + num(c.fovYDeg);
  line += " near=" + num(c.nearPlane) + " far=" + num(c.farPlane);
  return line;
}

} // namespace

std::string sessionScript(const ViewerScene& scene, int width, int height, std::optional<double> uiScale,
                          std::vector<std::string>* notes) {
  const session::ViewerState& s = scene.state();
  const session::ViewerSession& ses = scene.session();
  std::ostringstream out;
  auto note = [&](const std::string& text) {
    out << "# not restored: " << text << "\n";
    if (notes) notes->push_back(text);
  };
  out << "# dtfabric viewer session: `dtfabric view --script FILE` brings this view back\n";
  out << "session 1\n";
  out << "resize " << width << "x" << height << "\n";
  if (uiScale) out << "ui-scale " << num(*uiScale) << "\n";

  if (s.hasData) {
    const session::LoadFile& load = ses.loadedRequest();
    if (s.fibres.present) {
      out << "fibres layout=" << s.fibres.layout;
      if (!load.tensor.empty()) out << " tensor=" << absolute(load.tensor);
      out << " " << absolute(load.path) << "\n";
    } else {
      out << "load " << (load.layout != "auto" ? "layout=" + load.layout + " " : "") << absolute(load.path)
          << "\n";
    }
  }
  if (s.hasData || s.surface == session::SurfaceKind::Other || s.surface == session::SurfaceKind::Fibre)
    out << "surface " << specText(ses.surfaceSpec()) << "\n";

  // Every fabric option as it is (the defaults may differ from one version to the next).
  for (const auto& o : render::fabricOptions())
    out << "set " << o.name << " " << render::formatFabricValue(o, o.get(s.fabric)) << "\n";

  const session::SetBackground& bg = scene.backgroundAsked();
  if (bg.what.empty())
    out << "background default";
  else if (bg.what == "fa" || bg.what == "md" || bg.what == "none")
    out << "background " << bg.what;
  else
    out << "background " << absolute(bg.what);
  if (!bg.window.empty()) out << " " << bg.window;
  out << "\n";
  out << "furniture legend " << onOff(s.legend) << "\nfurniture scale-bar " << onOff(s.scaleBar)
      << "\nfurniture colour-bar " << onOff(s.colourBar) << "\n";

  out << "neurological " << onOff(s.neurological) << "\n";
  out << "view " << render::viewName(s.view) << "\n";
  out << "layout " << (s.ortho ? "ortho" : "single") << "\n";
  out << "split " << (s.split ? session::secondPaneName(s.secondPane) : "off") << "\n";
  out << "linked " << onOff(s.linked) << "\n";
  if (s.ortho && s.hasData)
    out << "crosshair " << num(s.crosshair.x) << " " << num(s.crosshair.y) << " " << num(s.crosshair.z)
        << "\n";

  const std::string tracts = ses.tractsFile();
  if (!tracts.empty()) {
    out << "tracts " << absolute(tracts) << "\n";
    out << "tracts-visible " << onOff(s.tractsVisible) << "\n";
    out << "tracts-near " << num(s.tractsNearMm) << "\n";
    out << "tracts-clip " << num(s.tractsClipMm) << " " << num(s.tractsClipOffsetMm) << "\n";
    out << "tract-width " << num(s.tractWidthPx) << "\n";
    const session::SetTractGroups& groups = ses.tractGroups();
    if (!groups.all) {
      std::string names;
      for (const auto& g : groups.shown)
        names += (names.empty() ? "" : ",") + g;
      out << "tracts-groups " << (names.empty() ? "none" : names) << "\n";
    }
    if (!s.tractColourBy.empty())
      out << "tracts-color " << s.tractColourBy << " " << num(s.tractColourLo) << " " << num(s.tractColourHi)
          << "\n";
  } else if (!s.tractPath.empty()) {
    note("the tracts tracked in the viewer (save them with Save in the Tracts panel, then load that file)");
  }
  // The regions of the ROI selection, in order, with the set's rules (names and visibility are not lines).
  bool renamed = false;
  for (std::size_t i = 0; i < s.roiSet.regions.size(); ++i) {
    const surfaces::Region& r = s.roiSet.regions[i];
    const std::string spec = session::regionSpecOf(r);
    out << "roi add " << surfaces::kindName(r.kind) << " " << spec << "\n";
    renamed |= r.name != spec || (i < s.roiVisible.size() && !s.roiVisible[i]);
  }
  if (s.roiSet.endsOnly) out << "roi ends-only on\n";
  if (!s.roiHideOthers) out << "roi others dim\n";
  if (renamed)
    note("the regions' names and visibility (save the region set with `roi save` to keep the names)");
  if (scene.hasUncertainty()) note("the uncertainty map (give `view --uncertainty` again)");

  // The cameras last: loading, the view and the layout above each place them anew.
  if (s.linked) {
    out << cameraLine(scene.camera(0), -1) << "\n";
  } else {
    out << cameraLine(scene.camera(0), 0) << "\n" << cameraLine(scene.camera(1), 1) << "\n";
  }
  return out.str();
}

void writeSessionFile(const std::string& path, const std::string& text) {
  if (path.empty()) throw InputError("session: no path given");
  io::AtomicOutput file(path);
  {
    std::ofstream out(file.tempPath(), std::ios::binary);
    out << text;
    out.close();
    if (!out) throw InputError(path + ": cannot write the session");
  }
  file.commit();
}

} // namespace dtf::app
