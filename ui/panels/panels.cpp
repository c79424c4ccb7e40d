// SPDX-License-Identifier: GPL-3.0-or-later
#include "ui/panels/panels.h"

#include "render/fabric_options.h"
#include "render/tract_renderer.h"
#include "surfaces/tracking/tracking_parameters.h"
#include "ui/session/file_kinds.h"
#include "ui/session/keymap.h"
#include "ui/session/roi_outline.h"
#include "ui/session/tract_colouring.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <imgui.h>
#include <limits>

namespace dtf::ui {

const std::array<const char*, 8> kLayoutNames = {"auto",  "fsl",          "mrtrix",     "symmatrix",
                                                 "dtitk", "mrtrix-peaks", "dipy-peaks", "bedpostx"};

namespace {

// Records the centre of the last widget for tests (PanelBuffers::itemCentres): of its frame, without the
// label that sliders and combos draw to the right of it.
void probe(PanelBuffers& b, const char* label) {
  if (!b.itemCentres) return;
  const ImVec2 lo = ImGui::GetItemRectMin(), hi = ImGui::GetItemRectMax();
  const float right = std::min(hi.x, lo.x + ImGui::CalcItemWidth());
  (*b.itemCentres)[label] = {0.5f * (lo.x + right), 0.5f * (lo.y + hi.y)};
}

bool sliderDouble(const char* label, double& v, float lo, float hi, const char* format,
                  bool logarithmic = false) {
  float f = static_cast<float>(v);
  if (!ImGui::SliderFloat(label, &f, lo, hi, format, logarithmic ? ImGuiSliderFlags_Logarithmic : 0))
    return false;
  v = f;
  return true;
}

void copyPath(std::array<char, 1024>& dst, const std::string& src) {
  std::snprintf(dst.data(), dst.size(), "%s", src.c_str());
}

// A collapsing header whose open state is kept in PanelBuffers::panelsOpen (and restored from it once).
bool header(PanelBuffers& b, const char* name, bool defaultOpen) {
  if (!b.panelsRestored) {
    if (const auto it = b.panelsOpen.find(name); it != b.panelsOpen.end()) ImGui::SetNextItemOpen(it->second);
  }
  const bool open = ImGui::CollapsingHeader(name, defaultOpen ? ImGuiTreeNodeFlags_DefaultOpen : 0);
  if (const auto it = b.panelsOpen.find(name); it != b.panelsOpen.end())
    it->second = open;
  else
    b.panelsOpen.emplace(name, open); // once per header: later frames find it
  return open;
}

// The "..." button after a path field: the file dialog for `target`.
void browseButton(PanelBuffers& b, const char* id, session::FileTarget target, session::ActionList& out) {
  ImGui::SameLine();
  ImGui::PushID(id);
  if (ImGui::Button("...")) out.push_back(session::Browse{target, {}});
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", session::fileTargetTitle(target));
  ImGui::PopID();
  probe(b, id);
}

// The Data panel's Open: the typed (or chosen) path with the panel's layout and tensor.
void openData(PanelBuffers& b, session::ActionList& out) {
  out.push_back(session::LoadFile{b.openPath.data(), kLayoutNames[b.layout], b.tensorPath.data()});
}

constexpr ImGuiWindowFlags kFixed =
    ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse;

// Colour by (DEC or a data value) with its range and colour bar, and a checkbox per group.
void tractColouringWidgets(const session::ViewerState& s, PanelBuffers& b, session::ActionList& out) {
  const char* current = s.tractColourBy.empty() ? "DEC (direction)" : s.tractColourBy.c_str();
  if (ImGui::BeginCombo("colour by", current)) {
    if (ImGui::Selectable("DEC (direction)", s.tractColourBy.empty()))
      out.push_back(session::SetTractColour{});
    for (const std::string& name : s.tractDataNames)
      if (name != session::kNodeColouring && name != session::kProfileColouring &&
          ImGui::Selectable(name.c_str(), name == s.tractColourBy))
        out.push_back(session::SetTractColour{name, {}});
    if (ImGui::Selectable("node (profile node index)", s.tractColourBy == session::kNodeColouring))
      out.push_back(session::SetTractColour{session::kNodeColouring, {}});
    if (ImGui::Selectable("profile (the profile's value at each node)",
                          s.tractColourBy == session::kProfileColouring))
      out.push_back(session::SetTractColour{session::kProfileColouring, {}});
    ImGui::EndCombo();
  }
  probe(b, "colour by");
  if (!s.tractColourBy.empty()) {
    double lo = s.tractColourLo, hi = s.tractColourHi;
    ImGui::PushItemWidth(ImGui::GetContentRegionAvail().x * 0.35f);
    const bool loEntered = ImGui::InputDouble("min", &lo, 0, 0, "%.4g", ImGuiInputTextFlags_EnterReturnsTrue);
    probe(b, "colour min");
    ImGui::SameLine();
    const bool hiEntered = ImGui::InputDouble("max", &hi, 0, 0, "%.4g", ImGuiInputTextFlags_EnterReturnsTrue);
    probe(b, "colour max");
    ImGui::PopItemWidth();
    if ((loEntered || hiEntered) && std::isfinite(lo) && std::isfinite(hi) && lo < hi)
      out.push_back(session::SetTractColour{s.tractColourBy, std::make_pair(lo, hi)});
    // The colour map, low on the left, as a strip of flat cells.
    const ImVec2 p = ImGui::GetCursorScreenPos();
    const float w = ImGui::GetContentRegionAvail().x, h = ImGui::GetFrameHeight() * 0.6f;
    constexpr int kCells = 32;
    ImDrawList* draw = ImGui::GetWindowDrawList();
    for (int i = 0; i < kCells; ++i) {
      const glm::vec3 c = render::tractValueColour((static_cast<float>(i) + 0.5f) / kCells);
      draw->AddRectFilled(ImVec2(p.x + w * static_cast<float>(i) / kCells, p.y),
                          ImVec2(p.x + w * static_cast<float>(i + 1) / kCells, p.y + h),
                          ImGui::ColorConvertFloat4ToU32(ImVec4(c.x, c.y, c.z, 1.0f)));
    }
    ImGui::Dummy(ImVec2(w, h));
    ImGui::TextDisabled("%.4g .. %.4g (viridis)", s.tractColourLo, s.tractColourHi);
  }
  if (s.tractGroupNames.empty()) return;
  ImGui::TextUnformatted("groups");
  for (std::size_t g = 0; g < s.tractGroupNames.size(); ++g) {
    bool on = g < s.tractGroupShown.size() && s.tractGroupShown[g];
    ImGui::PushID(static_cast<int>(g));
    if (ImGui::Checkbox(s.tractGroupNames[g].c_str(), &on)) {
      session::SetTractGroups groups;
      groups.all = false;
      for (std::size_t k = 0; k < s.tractGroupNames.size(); ++k)
        if (k == g ? on : (k < s.tractGroupShown.size() && s.tractGroupShown[k]))
          groups.shown.push_back(s.tractGroupNames[k]);
      groups.all = groups.shown.size() == s.tractGroupNames.size();
      if (groups.all) groups.shown.clear();
      out.push_back(std::move(groups));
    }
    probe(b, s.tractGroupNames[g].c_str());
    ImGui::PopID();
  }
}

} // namespace

float em(float pixelsAtScale1) {
  return pixelsAtScale1 * ImGui::GetFontSize() / kBaseFontPixels;
}

void probeItem(PanelBuffers& b, const char* label) {
  probe(b, label);
}

void choosePath(PanelBuffers& b, session::FileTarget target, const std::string& path,
                session::ActionList& out) {
  using T = session::FileTarget;
  switch (target) {
  case T::Data:
    copyPath(b.openPath, path);
    openData(b, out);
    break;
  case T::Tensor:
    copyPath(b.tensorPath, path);
    break;
  case T::Background:
    copyPath(b.backgroundPath, path);
    out.push_back(session::SetBackground{path, ""});
    break;
  case T::Tracts:
    copyPath(b.tractPath, path);
    out.push_back(session::LoadTracts{path});
    break;
  case T::Mesh:
    out.push_back(session::SetSurfaceSpec{"mesh=" + path});
    break;
  case T::Regions:
    copyPath(b.roiPath, path);
    out.push_back(session::LoadRegions{path});
    break;
  case T::RegionsSave:
    copyPath(b.roiPath, path);
    out.push_back(session::SaveRegions{path});
    break;
  case T::SelectedSave: {
    copyPath(b.roiSelectedPath, path);
    session::SaveTracts save{path, false, true};
    save.asGroup = b.roiGroup.data();
    out.push_back(save);
    break;
  }
  case T::Session:
    break; // not opened from the panels
  case T::Screenshot:
    copyPath(b.screenshotPath, path);
    break;
  case T::Camera:
    copyPath(b.cameraPath, path);
    break;
  case T::Movie:
    copyPath(b.moviePath, path);
    break;
  case T::TractsSave:
    copyPath(b.tractSavePath, path);
    break;
  case T::SessionSave:
    copyPath(b.sessionPath, path);
    out.push_back(session::SaveSession{path});
    break;
  }
}

void sceneRect(const PanelLayout& layout, float width, float height, float rect[4]) {
  rect[0] = std::min(layout.sideWidth, width - 1);
  rect[1] = 0;
  rect[2] = std::max(width - rect[0], 1.0f);
  rect[3] = std::max(height - layout.statusHeight, 1.0f);
}

void dataPanel(const session::ViewerState& s, PanelBuffers& b, session::ActionList& out) {
  if (!header(b, "Data", true)) return;
  ImGui::SetNextItemWidth(ImGui::GetContentRegionAvail().x - em(80));
  const bool enter =
      ImGui::InputText("##path", b.openPath.data(), b.openPath.size(), ImGuiInputTextFlags_EnterReturnsTrue);
  probe(b, "path");
  ImGui::SameLine();
  const bool open = ImGui::Button("Open");
  probe(b, "Open");
  browseButton(b, "browse data", session::FileTarget::Data, out);
  ImGui::Combo("layout", &b.layout, kLayoutNames.data(), static_cast<int>(kLayoutNames.size()));
  probe(b, "layout");
  ImGui::SetNextItemWidth(ImGui::GetContentRegionAvail().x - em(s.hasData ? 175 : 110));
  ImGui::InputText("tensor", b.tensorPath.data(), b.tensorPath.size());
  probe(b, "tensor");
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("fibre sets: a tensor volume on the same grid (FA)");
  browseButton(b, "browse tensor", session::FileTarget::Tensor, out);
  if ((enter || open) && b.openPath[0] != '\0') openData(b, out);
  if (s.hasData) {
    ImGui::SameLine();
    if (ImGui::Button("Reload"))
      out.push_back(session::LoadFile{s.data.path, kLayoutNames[b.layout], b.tensorPath.data()});
    probe(b, "Reload");
  }
  if (!s.recent.empty() && ImGui::TreeNodeEx("Recent files", ImGuiTreeNodeFlags_DefaultOpen)) {
    for (std::size_t i = 0; i < s.recent.size() && i < 8; ++i) {
      ImGui::PushID(static_cast<int>(i));
      if (ImGui::Selectable(s.recent[i].c_str(), s.hasData && s.recent[i] == s.data.path)) {
        copyPath(b.openPath, s.recent[i]);
        out.push_back(session::LoadFile{s.recent[i], kLayoutNames[b.layout], b.tensorPath.data()});
      }
      ImGui::PopID();
    }
    ImGui::TreePop();
  }
  if (!s.hasData) {
    ImGui::TextDisabled(s.busy ? "loading..." : "no data loaded");
    return;
  }
  const session::DataInfo& d = s.data;
  ImGui::TextWrapped("%s", d.path.c_str());
  ImGui::Text("%d x %d x %d voxels, %.2f x %.2f x %.2f mm", d.dims.x, d.dims.y, d.dims.z, d.spacing.x,
              d.spacing.y, d.spacing.z);
  ImGui::Text("orientation %s, %zu valid voxels", d.orientation.c_str(), d.validVoxels);
  ImGui::Text("layout %s", d.layout.c_str());
  if (!d.layoutReason.empty()) ImGui::TextWrapped("(%s)", d.layoutReason.c_str());
  for (const auto& w : d.warnings)
    ImGui::TextColored(ImVec4(1.0f, 0.8f, 0.3f, 1.0f), "warning: %s", w.c_str());
}

void surfacePanel(const session::ViewerState& s, PanelBuffers& b, session::ActionList& out) {
  if (!header(b, "Surface", true)) return;
  ImGui::BeginDisabled(!s.hasData);
  static const char* const kinds[] = {"FA isosurface",  "axial slice",   "coronal slice",
                                      "sagittal slice", "fibre surface", "other (from a spec)"};
  int kind = static_cast<int>(s.surface);
  if (ImGui::Combo("type", &kind, kinds, 6) && kind != static_cast<int>(session::SurfaceKind::Other))
    out.push_back(session::SetSurfaceKind{static_cast<session::SurfaceKind>(kind)});
  probe(b, "type");
  if (ImGui::Button("Open a mesh...")) out.push_back(session::Browse{session::FileTarget::Mesh, {}});
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", session::fileTargetTitle(session::FileTarget::Mesh));
  probe(b, "browse mesh");

  ImGui::BeginDisabled(s.surface != session::SurfaceKind::FaIsosurface);
  double fa = s.faThreshold;
  // Live sweep: every change while dragging is sent; the viewer re-extracts the latest on its worker.
  if (sliderDouble("FA threshold", fa, 0.05f, 0.9f, "%.3f")) out.push_back(session::SetFaThreshold{fa});
  probe(b, "FA threshold");
  ImGui::EndDisabled();

  // "##slice" keeps the IDs apart from the View panel's axial/coronal/sagittal buttons.
  static const char* const axes[] = {"axial##slice", "coronal##slice", "sagittal##slice"};
  static const char* const probes[] = {"axial slice", "coronal slice", "sagittal slice"};
  for (int a = 0; a < 3; ++a) {
    ImGui::BeginDisabled(session::sliceAxisOf(s.surface) != a);
    int idx = s.slice[a];
    if (ImGui::SliderInt(axes[a], &idx, 0, std::max(s.sliceCount[a] - 1, 0)))
      out.push_back(session::SetSlice{a, idx});
    probe(b, probes[a]);
    ImGui::EndDisabled();
  }

  if (b.fibreSeedSerial != s.fibreSeedSerial) { // a seed line set elsewhere (script, command line)
    b.fibreSeedSerial = s.fibreSeedSerial;
    std::copy(s.fibreSeed.begin(), s.fibreSeed.begin() + 3, b.fibreFrom.begin());
    std::copy(s.fibreSeed.begin() + 3, s.fibreSeed.end(), b.fibreTo.begin());
  }
  if (s.surface == session::SurfaceKind::Fibre) {
    ImGui::TextWrapped("Seed line (voxel indices); the stream surface of e1 grows from it.");
    ImGui::InputInt3("from", b.fibreFrom.data());
    ImGui::InputInt3("to", b.fibreTo.data());
    if (ImGui::Button("Build fibre surface")) {
      char spec[160];
      std::snprintf(spec, sizeof spec, "fibre-voxel=%d,%d,%d:%d,%d,%d", b.fibreFrom[0], b.fibreFrom[1],
                    b.fibreFrom[2], b.fibreTo[0], b.fibreTo[1], b.fibreTo[2]);
      out.push_back(session::SetSurfaceSpec{spec});
    }
    probe(b, "Build fibre surface");
  }
  ImGui::EndDisabled();
  if (!s.surfaceText.empty())
    ImGui::TextWrapped("%s, %zu triangles%s", s.surfaceText.c_str(), s.triangles,
                       s.surfacePending ? " (updating)" : "");
}

void fabricPanel(const session::ViewerState& s, PanelBuffers& b, session::ActionList& out) {
  if (!header(b, "Fabric", true)) return;
  render::FabricParams p = s.fabric;
  bool changed = false;
  // The options of render/fabric_options.h that have a control on the panel, with the table's slider ranges.
  using Kind = render::FabricOption::Kind;
  for (const auto& o : render::fabricOptions()) {
    if (!o.sliderLabel) continue;
    double v = o.get(p);
    bool c = false;
    if (o.kind == Kind::Choice) {
      int choice = static_cast<int>(v);
      // ImGui's zero-separated item list: the table's names with the spaces as separators.
      char items[128] = {};
      std::strncpy(items, o.choices ? o.choices : "", sizeof items - 2);
      for (char& ch : items)
        if (ch == ' ') ch = '\0';
      c = ImGui::Combo(o.sliderLabel, &choice, items);
      v = choice;
    } else if (o.kind == Kind::OnOff) {
      bool on = v != 0;
      c = ImGui::Checkbox(o.sliderLabel, &on);
      v = on ? 1 : 0;
    } else if (o.kind == Kind::Integer) {
      int i = static_cast<int>(v);
      c = ImGui::SliderInt(o.sliderLabel, &i, static_cast<int>(o.slider.lo), static_cast<int>(o.slider.hi));
      v = i;
    } else {
      c = sliderDouble(o.sliderLabel, v, static_cast<float>(o.slider.lo), static_cast<float>(o.slider.hi),
                       o.sliderFormat, o.sliderLogarithmic);
    }
    if (c) {
      o.set(p, v);
      changed = true;
    }
  }
  if (changed) out.push_back(session::SetFabricParams{p});
  // The fabric only near the tracts on screen (`render --fabric-along`), the anatomy elsewhere.
  bool along = s.fabricAlong;
  if (ImGui::Checkbox("along the tracts", &along)) out.push_back(session::SetFabricAlong{along, {}});
  probe(b, "along the tracts");
  if (!s.fabricAlong) return;
  double mm = s.fabricAlongMm;
  if (sliderDouble("within (mm)", mm, 0.5f, 10.0f, "%.1f", false) && mm > 0)
    out.push_back(session::SetFabricAlong{{}, mm});
  probe(b, "within (mm)");
  if (s.tractCount == 0)
    ImGui::TextDisabled("no tracts loaded: the fabric everywhere");
  else if (s.fabricAlongPending)
    ImGui::TextDisabled("finding where the tracts pass...");
}

// The Profile panel: the profile of the tracts on screen (as `dtfabric profile` computes it) with its 95 %
// confidence band; hovering a node moves the crosshair to its core position, a click pins it.
void profilePanel(const session::ViewerState& s, PanelBuffers& b, session::ActionList& out) {
  if (!header(b, "Profile", true)) return;
  const session::ViewerState::Profile& pr = s.profile;
  bool on = pr.on;
  if (ImGui::Checkbox("profile the tracts", &on)) out.push_back(session::SetProfile{on, {}});
  probe(b, "profile the tracts");
  if (!pr.on) return;
  if (!pr.scalars.empty() && ImGui::BeginCombo("scalar", pr.scalar.c_str())) {
    for (const std::string& name : pr.scalars)
      if (ImGui::Selectable(name.c_str(), name == pr.scalar)) out.push_back(session::SetProfile{{}, name});
    // The background image, when it is a file: any scalar image (NAME=IMAGE, as `dtfabric profile --scalar`).
    if (!s.background.empty() && s.background.find('=') == std::string::npos &&
        std::filesystem::is_regular_file(s.background)) {
      std::string stem = std::filesystem::path(s.background).filename().string();
      for (const char* ext : {".nii.gz", ".nii", ".mif", ".nrrd", ".mgz"})
        if (stem.size() > std::strlen(ext) && stem.ends_with(ext)) {
          stem.resize(stem.size() - std::strlen(ext));
          break;
        }
      const std::string spec = stem + "=" + s.background;
      if (ImGui::Selectable(("the background: " + stem).c_str(), spec == pr.scalar))
        out.push_back(session::SetProfile{{}, spec});
    }
    ImGui::EndCombo();
  }
  probe(b, "scalar");
  if (pr.pending) ImGui::TextDisabled("profiling...");
  if (!pr.error.empty()) {
    ImGui::TextWrapped("%s", pr.error.c_str());
    return;
  }
  const std::size_t n = pr.mean.size();
  if (n < 2 || pr.core.size() != n) return;
  ImGui::TextWrapped("%zu streamlines, %s", pr.streamlines, pr.axis.c_str());
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (std::size_t i = 0; i < n; ++i)
    for (double v : {pr.mean[i], pr.ciLow[i], pr.ciHigh[i]})
      if (std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
  if (!(lo < hi)) lo = (std::isfinite(lo) ? lo : 0.0) - 0.5, hi = lo + 1.0;
  const ImVec2 p = ImGui::GetCursorScreenPos();
  const float w = std::max(ImGui::GetContentRegionAvail().x, 16.0f), h = em(140);
  ImGui::InvisibleButton("profile plot", ImVec2(w, h));
  const bool inside = ImGui::IsItemHovered();
  probe(b, "profile plot");
  ImDrawList* draw = ImGui::GetWindowDrawList();
  draw->AddRectFilled(p, ImVec2(p.x + w, p.y + h), IM_COL32(20, 20, 24, 255));
  const auto X = [&](std::size_t i) { return p.x + w * static_cast<float>(i) / static_cast<float>(n - 1); };
  const auto Y = [&](double v) { return p.y + h * static_cast<float>(1.0 - (v - lo) / (hi - lo)); };
  for (std::size_t i = 0; i + 1 < n; ++i) {
    if (std::isfinite(pr.ciLow[i]) && std::isfinite(pr.ciHigh[i]) && std::isfinite(pr.ciLow[i + 1]) &&
        std::isfinite(pr.ciHigh[i + 1]))
      draw->AddQuadFilled(ImVec2(X(i), Y(pr.ciHigh[i])), ImVec2(X(i + 1), Y(pr.ciHigh[i + 1])),
                          ImVec2(X(i + 1), Y(pr.ciLow[i + 1])), ImVec2(X(i), Y(pr.ciLow[i])),
                          IM_COL32(80, 140, 220, 90));
    if (std::isfinite(pr.mean[i]) && std::isfinite(pr.mean[i + 1]))
      draw->AddLine(ImVec2(X(i), Y(pr.mean[i])), ImVec2(X(i + 1), Y(pr.mean[i + 1])),
                    IM_COL32(120, 180, 255, 255), 2.0f);
  }
  int node = -1; // under the mouse; else the node hovered by a script line shows
  if (inside) {
    const float t = (ImGui::GetIO().MousePos.x - p.x) / w;
    node =
        std::clamp(static_cast<int>(std::lround(t * static_cast<float>(n - 1))), 0, static_cast<int>(n) - 1);
  }
  if (pr.pinned >= 0 && pr.pinned < static_cast<int>(n))
    draw->AddLine(ImVec2(X(std::size_t(pr.pinned)), p.y), ImVec2(X(std::size_t(pr.pinned)), p.y + h),
                  IM_COL32(255, 200, 40, 255), 2.0f);
  const int shown = inside ? node : pr.hovered;
  if (shown >= 0 && shown < static_cast<int>(n)) {
    const auto k = static_cast<std::size_t>(shown);
    draw->AddLine(ImVec2(X(k), p.y), ImVec2(X(k), p.y + h), IM_COL32(255, 255, 255, 200), 1.0f);
  }
  if (node >= 0) {
    const auto k = static_cast<std::size_t>(node);
    ImGui::SetTooltip("node %d: %s %.4g (95 %% CI %.4g .. %.4g)\ncore %.1f, %.1f, %.1f mm%s", node,
                      pr.scalar.c_str(), pr.mean[k], pr.ciLow[k], pr.ciHigh[k], pr.core[k].x, pr.core[k].y,
                      pr.core[k].z, node == pr.pinned ? " (pinned: click to unpin)" : " (click to pin)");
  }
  // The mouse entering, moving over or leaving the plot sets the hover; a script's hover stays otherwise.
  if ((inside || b.profileHovering) && node != pr.hovered) out.push_back(session::HoverProfileNode{node, false});
  b.profileHovering = inside;
  if (inside && ImGui::IsItemClicked()) out.push_back(session::HoverProfileNode{node, true});
  ImGui::TextDisabled("%s %.3g .. %.3g; node 0 .. %zu", pr.scalar.c_str(), lo, hi, n - 1);
  const int at = shown >= 0 ? shown : pr.pinned;
  if (at >= 0 && at < static_cast<int>(n)) {
    const auto k = static_cast<std::size_t>(at);
    ImGui::Text("node %d%s: %s %.3g, core %.1f, %.1f, %.1f mm", at, at == pr.pinned ? " (pinned)" : "",
                pr.scalar.c_str(), pr.mean[k], pr.core[k].x, pr.core[k].y, pr.core[k].z);
  }
}

void fibresPanel(const session::ViewerState& s, PanelBuffers& b, session::ActionList& out) {
  const session::FibreInfo& f = s.fibres;
  if (!f.present || !header(b, "Fibres", true)) return;
  ImGui::TextWrapped("%s", f.path.c_str());
  ImGui::Text("layout %s, up to %d fibres per voxel", f.layout.c_str(), f.slots);
  if (!f.layoutReason.empty()) ImGui::TextWrapped("(%s)", f.layoutReason.c_str());
  if (f.faSource.empty())
    ImGui::TextWrapped(
        "no FA: pair a tensor (the Data panel's tensor field, `view --tensor`) for FA surfaces");
  else
    ImGui::TextWrapped("FA from %s", f.faSource.c_str());
  // The threshold is the option table's fibre-threshold, over the range the CLI accepts.
  if (const render::FabricOption* o = render::findFabricOption("fibre-threshold")) {
    double v = o->get(s.fabric);
    if (sliderDouble("fibre threshold", v, static_cast<float>(o->range.lo), static_cast<float>(o->range.hi),
                     "%.2f", false)) {
      render::FabricParams p = s.fabric;
      o->set(p, v);
      out.push_back(session::SetFabricParams{p});
    }
    probe(b, "fibre threshold");
  }
  ImGui::Text("voxels with fibres: %zu", f.voxels);
  ImGui::Text("populations drawn (threshold %.2f):", static_cast<double>(f.threshold));
  for (std::size_t n = 0; n < f.populations.size(); ++n)
    ImGui::BulletText("%zu %s: %zu voxels", n + 1, n ? "populations" : "population", f.populations[n]);
}

void viewPanel(const session::ViewerState& s, PanelBuffers& b, session::ActionList& out) {
  if (!header(b, "View", true)) return;
  using V = render::StandardView;
  static const V views[] = {V::Superior, V::Inferior, V::Anterior, V::Posterior, V::Left,
                            V::Right,    V::Axial,    V::Coronal,  V::Sagittal};
  for (int i = 0; i < 9; ++i) {
    if (i % 3) ImGui::SameLine();
    const char* name = render::viewName(views[i]);
    if (ImGui::Button(name, ImVec2(em(88), 0))) out.push_back(session::SetView{views[i]});
    probe(b, name);
  }
  if (ImGui::RadioButton("radiological", !s.neurological) && s.neurological)
    out.push_back(session::SetNeurological{false});
  probe(b, "radiological");
  ImGui::SameLine();
  if (ImGui::RadioButton("neurological", s.neurological) && !s.neurological)
    out.push_back(session::SetNeurological{true});
  probe(b, "neurological");
  bool split = s.split, linked = s.linked;
  if (ImGui::Checkbox("split", &split)) out.push_back(session::SetSplit{split});
  probe(b, "split");
  ImGui::SameLine();
  if (ImGui::Checkbox("linked camera", &linked)) out.push_back(session::SetLinkedCameras{linked});
  probe(b, "linked camera");
  bool ortho = s.ortho;
  if (ImGui::Checkbox("ortho layout", &ortho)) out.push_back(session::SetOrtho{ortho});
  probe(b, "ortho layout");
  if (s.ortho)
    ImGui::Text("crosshair %.1f %.1f %.1f mm (click a slice)", s.crosshair.x, s.crosshair.y, s.crosshair.z);
  int second = static_cast<int>(s.secondPane);
  static const char* const panes[] = {"other colour mode", "Phong shading", "fabric + tracts"};
  if (ImGui::Combo("right pane", &second, panes, 3))
    out.push_back(session::SetSecondPane{static_cast<session::SecondPane>(second)});
  if (ImGui::Button("Reset view (R)")) out.push_back(session::ResetView{});
  probe(b, "Reset view");

  // The grey beneath the fabric and the figure furniture over the panes (as `render` draws them).
  ImGui::SetNextItemWidth(ImGui::GetContentRegionAvail().x - em(150));
  ImGui::InputText("##background", b.backgroundPath.data(), b.backgroundPath.size());
  probe(b, "background path");
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("a scalar volume on any grid (a T1, say), fa or md");
  browseButton(b, "browse background", session::FileTarget::Background, out);
  ImGui::SameLine();
  if (ImGui::Button("Background") && b.backgroundPath[0] != '\0')
    out.push_back(session::SetBackground{b.backgroundPath.data(), ""});
  probe(b, "Background");
  ImGui::SameLine();
  if (ImGui::Button("default")) out.push_back(session::SetBackground{});
  probe(b, "default background");
  ImGui::TextDisabled("beneath: %s", s.background.empty() ? "FA within the data" : s.background.c_str());
  bool legend = s.legend, scaleBar = s.scaleBar, colourBar = s.colourBar;
  if (ImGui::Checkbox("legend", &legend)) out.push_back(session::SetFurniture{legend, {}, {}});
  probe(b, "legend");
  ImGui::SameLine();
  if (ImGui::Checkbox("scale bar", &scaleBar)) out.push_back(session::SetFurniture{{}, scaleBar, {}});
  probe(b, "scale bar");
  ImGui::SameLine();
  if (ImGui::Checkbox("colour bar", &colourBar)) out.push_back(session::SetFurniture{{}, {}, colourBar});
  probe(b, "colour bar");

  ImGui::InputText("##shot", b.screenshotPath.data(), b.screenshotPath.size());
  browseButton(b, "browse screenshot", session::FileTarget::Screenshot, out);
  if (ImGui::Button("Screenshot window")) out.push_back(session::Screenshot{b.screenshotPath.data(), false});
  probe(b, "Screenshot window");
  ImGui::SameLine();
  if (ImGui::Button("scene only")) out.push_back(session::Screenshot{b.screenshotPath.data(), true});
  ImGui::InputText("##camera", b.cameraPath.data(), b.cameraPath.size());
  browseButton(b, "browse camera", session::FileTarget::Camera, out);
  if (ImGui::Button("Save camera")) out.push_back(session::SaveCamera{b.cameraPath.data()});
  ImGui::SameLine();
  if (ImGui::Button("Load camera")) out.push_back(session::LoadCamera{b.cameraPath.data()});

  // A movie of the 3D pane as shown (surface, fabric, camera): a turntable, a slice sweep, an FA sweep.
  ImGui::InputText("##movie", b.moviePath.data(), b.moviePath.size());
  browseButton(b, "browse movie", session::FileTarget::Movie, out);
  static const char* const kinds[] = {"turntable", "axial sweep", "coronal sweep", "sagittal sweep", "FA sweep"};
  ImGui::SetNextItemWidth(em(130));
  ImGui::Combo("##moviekind", &b.movieKind, kinds, 5);
  probe(b, "movie kind");
  ImGui::SameLine();
  ImGui::SetNextItemWidth(em(90));
  ImGui::InputInt("frames", &b.movieFrames);
  b.movieFrames = std::clamp(b.movieFrames, 1, 10000);
  if (b.movieKind == 4) {
    ImGui::PushItemWidth(ImGui::GetContentRegionAvail().x * 0.3f);
    ImGui::InputDouble("FA from", &b.movieFaLo, 0, 0, "%.2f");
    ImGui::SameLine();
    ImGui::InputDouble("to", &b.movieFaHi, 0, 0, "%.2f");
    ImGui::PopItemWidth();
    b.movieFaLo = std::clamp(b.movieFaLo, 0.01, 0.99);
    b.movieFaHi = std::clamp(b.movieFaHi, 0.01, 0.99);
  }
  if (s.recording) {
    ImGui::Text("recording %d/%d", s.recordedFrames, s.recordFrames);
  } else {
    if (ImGui::Button("Record") && b.moviePath[0] != '\0') {
      session::RecordMovie m{b.moviePath.data(), b.movieFrames};
      static const char* const axes[] = {"axial", "coronal", "sagittal"};
      if (b.movieKind >= 1 && b.movieKind <= 3) {
        m.kind = session::RecordMovie::Kind::Sweep;
        m.axis = axes[b.movieKind - 1];
      } else if (b.movieKind == 4) {
        m.kind = session::RecordMovie::Kind::FaSweep;
        m.faLo = b.movieFaLo;
        m.faHi = b.movieFaHi;
      }
      out.push_back(m);
    }
    probe(b, "Record");
  }
  if (!s.recordStatus.empty() && !s.recording) ImGui::TextWrapped("%s", s.recordStatus.c_str());

  // The whole view as a view script (`view --script FILE` brings it back).
  ImGui::InputText("##session", b.sessionPath.data(), b.sessionPath.size());
  probe(b, "session path");
  browseButton(b, "browse session", session::FileTarget::SessionSave, out);
  if (ImGui::Button("Save session") && b.sessionPath[0] != '\0')
    out.push_back(session::SaveSession{b.sessionPath.data()});
  probe(b, "Save session");

  // The panels' and fonts' scale: the monitor's, or one chosen here (applied when the slider is let go).
  bool automatic = s.uiScaleAuto;
  if (ImGui::Checkbox("UI scale from the monitor", &automatic) && automatic)
    out.push_back(session::SetUiScale{0});
  probe(b, "UI scale auto");
  // The value being dragged lives in the buffers until the slider is let go.
  if (!b.uiScaleDragging) b.uiScaleEdit = static_cast<float>(s.uiScale);
  ImGui::SliderFloat("UI scale", &b.uiScaleEdit, 0.5f, 3.0f, "%.2f");
  probe(b, "UI scale");
  b.uiScaleDragging = ImGui::IsItemActive();
  if (ImGui::IsItemDeactivatedAfterEdit()) out.push_back(session::SetUiScale{b.uiScaleEdit});
  ImGui::TextDisabled("F1 or ?: mouse and keys");
}

// The regions of the ROI selection: adding at the crosshair or by a click in a slice pane, the list with
// visibility, kind, size, rename and delete, the rules for the set, saving and loading.
void regionsWidgets(const session::ViewerState& s, PanelBuffers& b, session::ActionList& out) {
  const bool open = ImGui::TreeNodeEx("Regions", ImGuiTreeNodeFlags_DefaultOpen);
  probe(b, "Regions");
  if (!open) return;
  using surfaces::RegionKind;
  static const char* const kinds[] = {"include", "exclude", "include-ordered"};
  if (s.roiActive)
    ImGui::Text("selected: %zu of %zu streamlines%s", s.roiSelected, s.tractCount,
                s.roiSelecting ? " (selecting...)" : "");
  else
    ImGui::TextDisabled("no region: every streamline is selected%s", s.roiSelecting ? " (indexing...)" : "");
  if (s.roiSelecting && !s.roiStage.empty()) ImGui::TextDisabled("%s", s.roiStage.c_str());
  ImGui::SetNextItemWidth(em(130));
  ImGui::Combo("kind##new", &b.roiKind, kinds, 3);
  probe(b, "kind##new");
  ImGui::SetNextItemWidth(em(130));
  ImGui::SliderFloat("size (mm)##new", &b.roiSizeMm, 1.0f, 40.0f, "%.1f");
  const auto kind = static_cast<RegionKind>(std::clamp(b.roiKind, 0, 2));
  auto addAt = [&](bool sphere, const glm::dvec3& at) {
    session::RoiAdd add;
    add.kind = kind;
    add.region.kind = kind;
    if (sphere) {
      add.region.shape = surfaces::RegionShape::Sphere;
      add.region.centre = at;
      add.region.radius = b.roiSizeMm;
    } else {
      add.region.shape = surfaces::RegionShape::Box;
      add.region.lo = at - glm::dvec3(b.roiSizeMm);
      add.region.hi = at + glm::dvec3(b.roiSizeMm);
    }
    out.push_back(add);
  };
  if (ImGui::Button("sphere at crosshair")) addAt(true, s.crosshair);
  probe(b, "sphere at crosshair");
  ImGui::SameLine();
  if (ImGui::Button("box at crosshair")) addAt(false, s.crosshair);
  probe(b, "box at crosshair");
  const char* placing = b.roiPlace == 1 ? "click a slice pane: sphere" : "click a slice pane: box";
  if (b.roiPlace != 0) {
    if (ImGui::Button("cancel")) b.roiPlace = 0;
    ImGui::SameLine();
    ImGui::TextDisabled("%s", placing);
  } else {
    if (ImGui::Button("place sphere")) b.roiPlace = 1;
    probe(b, "place sphere");
    ImGui::SameLine();
    if (ImGui::Button("place box")) b.roiPlace = 2;
    probe(b, "place box");
  }
  bool endsOnly = s.roiSet.endsOnly;
  if (ImGui::Checkbox("end points only", &endsOnly)) out.push_back(session::RoiEndsOnly{endsOnly});
  probe(b, "end points only");
  bool hide = s.roiHideOthers;
  if (ImGui::Checkbox("hide the others (else dimmed)", &hide)) out.push_back(session::RoiHideOthers{hide});
  probe(b, "hide the others (else dimmed)");
  ImGui::TextDisabled("include green, exclude red, ordered include blue; drag in a slice pane, wheel: size");
  for (std::size_t i = 0; i < s.roiSet.regions.size(); ++i) {
    const surfaces::Region& r = s.roiSet.regions[i];
    ImGui::PushID(static_cast<int>(i));
    bool visible = i < s.roiVisible.size() ? s.roiVisible[i] != 0 : true;
    if (ImGui::Checkbox("##visible", &visible)) out.push_back(session::RoiVisible{i, visible});
    ImGui::SameLine();
    const glm::u8vec3 c = session::regionKindColour(r.kind);
    ImGui::TextColored(ImVec4(c.x / 255.0f, c.y / 255.0f, c.z / 255.0f, 1.0f), "%zu", i + 1);
    ImGui::SameLine();
    if (b.roiRenaming == static_cast<int>(i)) {
      ImGui::SetNextItemWidth(em(120));
      if (ImGui::InputText("##name", b.roiName.data(), b.roiName.size(),
                           ImGuiInputTextFlags_EnterReturnsTrue)) {
        session::RoiSet set{i, r};
        set.region.name = b.roiName.data();
        out.push_back(set);
        b.roiRenaming = -1;
      }
    } else {
      ImGui::TextUnformatted(r.name.c_str());
      if (ImGui::IsItemClicked()) {
        b.roiRenaming = static_cast<int>(i);
        std::snprintf(b.roiName.data(), b.roiName.size(), "%s", r.name.c_str());
      }
    }
    ImGui::SameLine();
    if (ImGui::SmallButton("x")) out.push_back(session::RoiRemove{i});
    int k = static_cast<int>(r.kind);
    ImGui::SetNextItemWidth(em(110));
    if (ImGui::Combo("##kind", &k, kinds, 3)) {
      session::RoiSet set{i, r};
      set.region.kind = static_cast<RegionKind>(k);
      out.push_back(set);
    }
    if (r.shape == surfaces::RegionShape::Sphere) {
      ImGui::SameLine();
      double radius = r.radius;
      ImGui::SetNextItemWidth(em(90));
      if (sliderDouble("mm##radius", radius, 0.5f, 60.0f, "%.1f") && radius > 0) {
        session::RoiSet set{i, r};
        set.region.radius = radius;
        out.push_back(set);
      }
    } else if (r.shape == surfaces::RegionShape::Box) {
      ImGui::SameLine();
      const glm::dvec3 centre = 0.5 * (r.lo + r.hi), half = 0.5 * (r.hi - r.lo);
      double size = std::max({half.x, half.y, half.z});
      ImGui::SetNextItemWidth(em(90));
      if (sliderDouble("mm##half", size, 0.5f, 60.0f, "%.1f") && size > 0) {
        session::RoiSet set{i, r};
        const glm::dvec3 h = half * (size / std::max(std::max({half.x, half.y, half.z}), 1e-9));
        set.region.lo = centre - h;
        set.region.hi = centre + h;
        out.push_back(set);
      }
    } else {
      ImGui::SameLine();
      ImGui::TextDisabled("mask");
    }
    ImGui::PopID();
  }
  if (!s.roiSet.regions.empty() && ImGui::Button("remove every region")) out.push_back(session::RoiClear{});
  // The region set file (`select --roi`).
  ImGui::SetNextItemWidth(ImGui::GetContentRegionAvail().x - em(120));
  ImGui::InputText("##roipath", b.roiPath.data(), b.roiPath.size());
  browseButton(b, "browse regions", session::FileTarget::Regions, out);
  browseButton(b, "browse regions save", session::FileTarget::RegionsSave, out);
  if (ImGui::Button("load regions") && b.roiPath[0] != '\0')
    out.push_back(session::LoadRegions{b.roiPath.data()});
  probe(b, "load regions");
  ImGui::SameLine();
  if (ImGui::Button("save regions") && b.roiPath[0] != '\0')
    out.push_back(session::SaveRegions{b.roiPath.data()});
  probe(b, "save regions");
  // The selected streamlines, in any tract format; a .trx may hold them as a group of every streamline.
  ImGui::SetNextItemWidth(ImGui::GetContentRegionAvail().x - em(80));
  ImGui::InputText("##roisel", b.roiSelectedPath.data(), b.roiSelectedPath.size());
  browseButton(b, "browse selected save", session::FileTarget::SelectedSave, out);
  ImGui::SetNextItemWidth(em(120));
  ImGui::InputText("as group (.trx)", b.roiGroup.data(), b.roiGroup.size());
  if (ImGui::Button("save selected") && b.roiSelectedPath[0] != '\0') {
    session::SaveTracts save{b.roiSelectedPath.data(), false, true};
    save.asGroup = b.roiGroup.data();
    out.push_back(save);
  }
  probe(b, "save selected");
  if (!s.roiStatus.empty()) ImGui::TextDisabled("%s", s.roiStatus.c_str());
  ImGui::TreePop();
}

void tractsPanel(const session::ViewerState& s, PanelBuffers& b, session::ActionList& out) {
  const bool open = header(b, "Tracts", false);
  probe(b, "Tracts");
  if (!open) return;
  ImGui::SetNextItemWidth(ImGui::GetContentRegionAvail().x - em(120));
  const bool enter = ImGui::InputText("##tracts", b.tractPath.data(), b.tractPath.size(),
                                      ImGuiInputTextFlags_EnterReturnsTrue);
  ImGui::SameLine();
  const bool load = ImGui::Button("Load tracts");
  probe(b, "Load tracts");
  browseButton(b, "browse tracts", session::FileTarget::Tracts, out);
  if ((enter || load) && b.tractPath[0] != '\0') out.push_back(session::LoadTracts{b.tractPath.data()});
  if (s.tractsLoading) ImGui::TextDisabled("loading...");
  if (s.tractPath.empty()) {
    ImGui::TextDisabled(".tck, .trk or .vtk streamlines (world RAS mm), or track below");
  } else {
    ImGui::TextWrapped("%s", s.tractPath.c_str());
    ImGui::TextWrapped("%zu streamlines, %zu points, mean length %.1f mm", s.tractCount, s.tractPoints,
                       s.tractMeanLengthMm);
    bool visible = s.tractsVisible;
    if (ImGui::Checkbox("show tracts", &visible)) out.push_back(session::SetTractsVisible{visible});
    probe(b, "show tracts");
    double width = s.tractWidthPx;
    if (sliderDouble("width (px)", width, 0.5f, 8.0f, "%.1f")) out.push_back(session::SetTractWidth{width});
    probe(b, "width (px)");
    double near = s.tractsNearMm;
    if (sliderDouble("near surface (mm)", near, 0.0f, 20.0f, "%.1f"))
      out.push_back(session::SetTractsNear{near});
    probe(b, "near surface (mm)");
    // Planar surfaces: every tract within a slab around the plane, the clip's half-width when set, else the
    // near distance; curved surfaces: the tracts near them, clipped by the camera-facing slab.
    const double planarSlab = s.tractsClipMm > 0 ? s.tractsClipMm : s.tractsNearMm;
    if (s.tractsSlab && planarSlab > 0)
      ImGui::TextDisabled("planar surface: slab of +-%.1f mm", planarSlab);
    else if (s.tractsSlab || s.tractsNearMm <= 0)
      ImGui::TextDisabled("every tract is shown");
    double clip = s.tractsClipMm, clipOffset = s.tractsClipOffsetMm;
    bool clipChanged = sliderDouble("clip slab (mm)", clip, 0.0f, 50.0f, "%.1f");
    probe(b, "clip slab (mm)");
    if (clip > 0) {
      clipChanged |= sliderDouble("clip depth (mm)", clipOffset, -100.0f, 100.0f, "%.1f");
      probe(b, "clip depth (mm)");
      if (s.tractsSlab) ImGui::TextDisabled("planar surface: the slab lies around its plane");
    }
    if (clipChanged) out.push_back(session::SetTractsClip{clip, clipOffset});
    ImGui::Text("shown: %zu pieces, %zu points%s", s.tractsShownLines, s.tractsShownPoints,
                s.tractsSelecting ? " (selecting...)" : "");
    if (s.tractsLevel > 0 || s.tractsLevelFraction < 1)
      ImGui::TextDisabled("drawing level %d (every %d-th point), %.0f%% of the lines", s.tractsLevel,
                          1 << s.tractsLevel, 100.0 * s.tractsLevelFraction);
    tractColouringWidgets(s, b, out);
    ImGui::SetNextItemWidth(ImGui::GetContentRegionAvail().x - em(80));
    ImGui::InputText("##savetracts", b.tractSavePath.data(), b.tractSavePath.size());
    browseButton(b, "browse tracts save", session::FileTarget::TractsSave, out);
    ImGui::SameLine();
    if (ImGui::Button("Save") && b.tractSavePath[0] != '\0')
      out.push_back(session::SaveTracts{b.tractSavePath.data()});
    probe(b, "Save");
    if (!s.saveStatus.empty()) ImGui::TextDisabled("%s", s.saveStatus.c_str());
    regionsWidgets(s, b, out);
  }

  const bool tracking = ImGui::TreeNode("Tracking");
  probe(b, "Tracking");
  if (tracking) {
    session::TrackRequest& t = b.track;
    // The panel's seed places, in SeedKind order from Surface (a seed mask file is for `dtfabric track`).
    static const char* const seedKinds[] = {"surface on screen", "slice", "sphere (ROI)", "FA mask"};
    constexpr int kFirst = static_cast<int>(session::SeedKind::Surface);
    if (t.seeds < session::SeedKind::Surface) t.seeds = session::SeedKind::Surface;
    int seeds = static_cast<int>(t.seeds) - kFirst;
    if (ImGui::Combo("seeds", &seeds, seedKinds, 4)) t.seeds = static_cast<session::SeedKind>(seeds + kFirst);
    probe(b, "seeds");
    if (t.seeds == session::SeedKind::Slice) {
      static const char* const axes[] = {"axial", "coronal", "sagittal"};
      ImGui::Combo("slice axis", &t.sliceAxis, axes, 3);
      ImGui::InputInt("slice (-1 current)", &t.sliceIndex);
      t.sliceIndex = std::max(t.sliceIndex, -1);
    } else if (t.seeds == session::SeedKind::Sphere) {
      float c[3] = {static_cast<float>(t.centre.x), static_cast<float>(t.centre.y),
                    static_cast<float>(t.centre.z)};
      if (ImGui::InputFloat3("centre (mm)", c)) t.centre = glm::dvec3(c[0], c[1], c[2]);
      if (s.probe.onSurface && ImGui::Button("centre at the last probed point")) t.centre = s.probe.world;
      sliderDouble("radius (mm)", t.radiusMm, 1.0f, 50.0f, "%.1f");
    } else if (t.seeds == session::SeedKind::FaMask) {
      sliderDouble("mask FA >=", t.faMask, 0.05f, 0.9f, "%.2f");
    }
    static const char* const counts[] = {"streamlines", "seeds", "seeds per voxel"};
    int count = static_cast<int>(t.count);
    if (ImGui::Combo("count", &count, counts, t.seeds == session::SeedKind::FaMask ? 3 : 2))
      t.count = static_cast<session::SeedCount>(count);
    if (t.seeds != session::SeedKind::FaMask && t.count == session::SeedCount::PerVoxel)
      t.count = session::SeedCount::Select;
    ImGui::InputInt("number", &t.number);
    t.number = std::clamp(t.number, 1, 10'000'000);
    for (const auto& p : surfaces::trackingParameters()) {
      double v = p.get(t.options);
      if (sliderDouble(p.sliderLabel, v, static_cast<float>(p.slider.lo), static_cast<float>(p.slider.hi),
                       p.sliderFormat) &&
          p.range.contains(v))
        p.set(t.options, v);
    }
    ImGui::Checkbox("RK4 (off: Euler)", &t.options.rk4);
    int rngSeed = static_cast<int>(std::min<std::uint64_t>(t.rngSeed, INT_MAX));
    if (ImGui::InputInt("random seed", &rngSeed)) t.rngSeed = static_cast<std::uint64_t>(std::max(rngSeed, 0));
    if (s.tracking) {
      char overlay[64];
      std::snprintf(overlay, sizeof overlay, "%zu seeds", s.trackSeedsDone);
      ImGui::ProgressBar(static_cast<float>(s.trackProgress), ImVec2(-80, 0), overlay);
      ImGui::SameLine();
      if (ImGui::Button("Cancel")) out.push_back(session::CancelTracking{});
      probe(b, "Cancel");
    } else {
      ImGui::BeginDisabled(!s.hasData);
      if (ImGui::Button("Track")) out.push_back(session::TrackTracts{t});
      probe(b, "Track");
      ImGui::EndDisabled();
    }
    if (!s.trackStatus.empty()) ImGui::TextWrapped("%s", s.trackStatus.c_str());
    ImGui::TreePop();
  }

  const bool agreement = ImGui::TreeNode("Agreement with the fabric");
  probe(b, "Agreement with the fabric");
  if (agreement) {
    sliderDouble("within (mm)", b.agreementNearMm, 0.5f, 10.0f, "%.1f");
    ImGui::SliderInt("bins", &b.agreementBins, 3, 30);
    ImGui::BeginDisabled(s.tractPath.empty() || !s.hasData || s.agreementRunning);
    if (ImGui::Button("Compute"))
      out.push_back(session::ComputeAgreement{b.agreementNearMm, b.agreementBins});
    probe(b, "Compute");
    ImGui::EndDisabled();
    if (s.agreementRunning) {
      ImGui::SameLine();
      ImGui::TextDisabled("computing...");
    }
    if (s.hasAgreement) {
      ImGui::PlotHistogram(
          "##angles", s.agreementHistogram.data(), static_cast<int>(s.agreementHistogram.size()), 0,
          "tract-fabric angle, 0-90 deg", 0.0f, FLT_MAX,
          ImVec2(ImGui::GetContentRegionAvail().x, em(80))); // a negative width draws nothing
      probe(b, "agreement histogram");
      if (s.agreementPoints == 0)
        ImGui::TextWrapped("no tract point could be compared (%zu within %.1f mm, %zu skipped)",
                           s.agreementNearPoints, s.agreementNearMm, s.agreementSkipped);
      else
        ImGui::TextWrapped("%zu points: median %.1f, mean %.1f deg, %.1f%% below 15 deg (%zu within %.1f mm, "
                           "%zu skipped)",
                           s.agreementPoints, s.agreementMedianDeg, s.agreementMeanDeg,
                           100.0 * s.agreementFracBelow15, s.agreementNearPoints, s.agreementNearMm,
                           s.agreementSkipped);
      ImGui::TextDisabled("on the %s", s.agreementSurface.c_str());
    }
    ImGui::TreePop();
  }
}

void statusBar(const session::ViewerState& s, const PanelLayout& layout) {
  const ImGuiIO& io = ImGui::GetIO();
  ImGui::SetNextWindowPos(ImVec2(0, io.DisplaySize.y - layout.statusHeight));
  ImGui::SetNextWindowSize(ImVec2(io.DisplaySize.x, layout.statusHeight));
  ImGui::Begin("##status", nullptr, kFixed | ImGuiWindowFlags_NoTitleBar | ImGuiWindowFlags_NoScrollbar);
  if (s.busy) {
    // Indeterminate progress: the loader reports stages, not fractions.
    const float phase = static_cast<float>(std::fmod(s.busySeconds, 1.5) / 1.5);
    ImGui::ProgressBar(phase, ImVec2(em(120), 0), "");
    ImGui::SameLine();
    ImGui::Text("%s (%.0f s)", s.busyStage.c_str(), s.busySeconds);
    ImGui::SameLine();
  }
  if (s.tracking) { // long work on the tract worker: progress with its own bar
    ImGui::ProgressBar(static_cast<float>(s.trackProgress), ImVec2(em(120), 0), "");
    ImGui::SameLine();
    ImGui::Text("tracking: %zu seeds", s.trackSeedsDone);
    ImGui::SameLine();
  } else if (s.tractsSelecting || s.agreementRunning) {
    ImGui::TextDisabled(s.agreementRunning ? "agreement..." : "selecting tracts...");
    ImGui::SameLine();
  }
  const session::ProbeInfo& p = s.probe;
  if (p.onSurface) {
    ImGui::Text("(%.1f, %.1f, %.1f) mm", p.world.x, p.world.y, p.world.z);
    if (p.inData) {
      ImGui::SameLine();
      // Tensor and fibres of the voxel (ui/session/viewer_session.h), clipped before the frame time.
      const ImVec2 at = ImGui::GetCursorScreenPos();
      ImGui::PushClipRect(at, ImVec2(std::max(at.x, io.DisplaySize.x - em(210)), at.y + layout.statusHeight),
                          true);
      ImGui::TextUnformatted(p.text.c_str());
      ImGui::PopClipRect();
    }
  } else {
    ImGui::TextDisabled("cursor not on the surface");
  }
  ImGui::SameLine(std::max(ImGui::GetWindowWidth() - em(200), ImGui::GetCursorPosX() + em(10)));
  ImGui::Text("%5.1f ms %s", s.frameMs, s.converged ? "still" : "refining");
  ImGui::End();
}

void errorModal(const session::ViewerState& s, PanelBuffers& b, session::ActionList& out) {
  if (s.errorChain.empty()) return;
  if (!ImGui::IsPopupOpen("Error")) ImGui::OpenPopup("Error");
  const ImGuiIO& io = ImGui::GetIO();
  ImGui::SetNextWindowPos(ImVec2(io.DisplaySize.x * 0.5f, io.DisplaySize.y * 0.5f), ImGuiCond_Always,
                          ImVec2(0.5f, 0.5f));
  ImGui::SetNextWindowSizeConstraints(ImVec2(em(300), 0),
                                      ImVec2(std::max(io.DisplaySize.x * 0.9f, em(300)), FLT_MAX));
  if (ImGui::BeginPopupModal("Error", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
    for (std::size_t i = 0; i < s.errorChain.size(); ++i) {
      if (i) ImGui::Indent(em(12));
      ImGui::TextWrapped("%s", s.errorChain[i].c_str());
    }
    if (s.errorChain.size() > 1) ImGui::Unindent(em(12) * static_cast<float>(s.errorChain.size() - 1));
    if (ImGui::Button("OK", ImVec2(em(120), 0))) {
      out.push_back(session::DismissError{});
      ImGui::CloseCurrentPopup();
    }
    probe(b, "OK");
    ImGui::EndPopup();
  }
}

void overwriteModal(const session::ViewerState& s, PanelBuffers& b, session::ActionList& out) {
  // The error modal goes first: ImGui stacks popups, and an error hides the question until dismissed.
  if (s.overwritePath.empty() || !s.errorChain.empty()) return;
  if (!ImGui::IsPopupOpen("Overwrite?")) ImGui::OpenPopup("Overwrite?");
  const ImGuiIO& io = ImGui::GetIO();
  ImGui::SetNextWindowPos(ImVec2(io.DisplaySize.x * 0.5f, io.DisplaySize.y * 0.5f), ImGuiCond_Always,
                          ImVec2(0.5f, 0.5f));
  if (ImGui::BeginPopupModal("Overwrite?", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
    ImGui::TextWrapped("%s exists. Replace it?", s.overwritePath.c_str());
    if (ImGui::Button("Overwrite", ImVec2(em(120), 0))) {
      out.push_back(session::ConfirmOverwrite{true});
      ImGui::CloseCurrentPopup();
    }
    probe(b, "Overwrite");
    ImGui::SameLine();
    if (ImGui::Button("Cancel", ImVec2(em(120), 0))) {
      out.push_back(session::ConfirmOverwrite{false});
      ImGui::CloseCurrentPopup();
    }
    probe(b, "Cancel");
    ImGui::EndPopup();
  }
}

void drawPanels(const session::ViewerState& s, PanelBuffers& b, const PanelLayout& layout,
                session::ActionList& out) {
  const ImGuiIO& io = ImGui::GetIO();
  ImGui::SetNextWindowPos(ImVec2(0, 0));
  ImGui::SetNextWindowSize(ImVec2(layout.sideWidth, std::max(io.DisplaySize.y - layout.statusHeight, 1.0f)));
  ImGui::Begin("dtfabric", nullptr, kFixed);
  ImGui::PushItemWidth(-em(120));
  dataPanel(s, b, out);
  surfacePanel(s, b, out);
  fabricPanel(s, b, out);
  fibresPanel(s, b, out);
  viewPanel(s, b, out);
  tractsPanel(s, b, out);
  profilePanel(s, b, out);
  ImGui::PopItemWidth();
  ImGui::End();
  statusBar(s, layout);
  b.panelsRestored = true;
  helpOverlay(s, layout, out);
  fileBrowserPanel(s, b, out);
  errorModal(s, b, out);
  overwriteModal(s, b, out);
}

void helpOverlay(const session::ViewerState& s, const PanelLayout& layout, session::ActionList& out) {
  if (!s.helpShown) return;
  const ImGuiIO& io = ImGui::GetIO();
  // Centred over the scene, not the side bar.
  const float sceneX = std::min(layout.sideWidth, io.DisplaySize.x - 1);
  ImGui::SetNextWindowPos(
      ImVec2(sceneX + 0.5f * (io.DisplaySize.x - sceneX), 0.5f * (io.DisplaySize.y - layout.statusHeight)),
      ImGuiCond_Always, ImVec2(0.5f, 0.5f));
  // As wide as the scene allows (its text wraps), as tall as its rows.
  ImGui::SetNextWindowSize(
      ImVec2(std::min(em(620), std::max(io.DisplaySize.x - sceneX - em(20), em(200))), 0), ImGuiCond_Always);
  ImGui::SetNextWindowBgAlpha(0.85f);
  bool open = true;
  if (ImGui::Begin("Mouse and keys (F1 or ? to close)", &open,
                   ImGuiWindowFlags_NoCollapse | ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize |
                       ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoFocusOnAppearing)) {
    if (ImGui::BeginTable("##bindings", 2, ImGuiTableFlags_RowBg | ImGuiTableFlags_SizingStretchProp)) {
      ImGui::TableSetupColumn("input", ImGuiTableColumnFlags_WidthStretch, 1.0f);
      ImGui::TableSetupColumn("does", ImGuiTableColumnFlags_WidthStretch, 1.2f);
      for (const session::Binding& binding : session::bindings()) {
        ImGui::TableNextRow();
        ImGui::TableNextColumn();
        ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1.0f, 0.9f, 0.35f, 1.0f));
        ImGui::TextWrapped("%s", binding.input);
        ImGui::PopStyleColor();
        ImGui::TableNextColumn();
        ImGui::TextWrapped("%s", binding.does);
      }
      ImGui::EndTable();
    }
  }
  ImGui::End();
  if (!open) out.push_back(session::ShowHelp{false});
}

} // namespace dtf::ui
