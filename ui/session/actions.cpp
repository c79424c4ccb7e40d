// SPDX-License-Identifier: GPL-3.0-or-later
#include "ui/session/actions.h"

#include <cstdio>
#include <type_traits>

namespace dtf::session {

const char* surfaceKindName(SurfaceKind kind) {
  switch (kind) {
  case SurfaceKind::FaIsosurface:
    return "FA isosurface";
  case SurfaceKind::Axial:
    return "axial slice";
  case SurfaceKind::Coronal:
    return "coronal slice";
  case SurfaceKind::Sagittal:
    return "sagittal slice";
  case SurfaceKind::Fibre:
    return "fibre surface";
  case SurfaceKind::Other:
    return "other surface";
  }
  return "?";
}

const char* secondPaneName(SecondPane mode) {
  switch (mode) {
  case SecondPane::OtherColourMode:
    return "colour";
  case SecondPane::Phong:
    return "phong";
  case SecondPane::Tracts:
    return "tracts";
  }
  return "?";
}

int sliceAxisOf(SurfaceKind kind) {
  switch (kind) {
  case SurfaceKind::Axial:
    return 0;
  case SurfaceKind::Coronal:
    return 1;
  case SurfaceKind::Sagittal:
    return 2;
  default:
    return -1;
  }
}

std::string describe(const Action& action) {
  char buf[160];
  return std::visit(
      [&](const auto& a) -> std::string {
        using T = std::decay_t<decltype(a)>;
        if constexpr (std::is_same_v<T, LoadFile>)
          return "LoadFile " + a.path + " layout=" + a.layout +
                 (a.tensor.empty() ? "" : " tensor=" + a.tensor);
        else if constexpr (std::is_same_v<T, SetSurfaceKind>)
          return std::string("SetSurfaceKind ") + surfaceKindName(a.kind);
        else if constexpr (std::is_same_v<T, SetSurfaceSpec>)
          return "SetSurfaceSpec " + a.text;
        else if constexpr (std::is_same_v<T, SetFaThreshold>) {
          std::snprintf(buf, sizeof buf, "SetFaThreshold %g", a.value);
          return buf;
        } else if constexpr (std::is_same_v<T, SetSlice>) {
          std::snprintf(buf, sizeof buf, "SetSlice %d %d", a.axis, a.index);
          return buf;
        } else if constexpr (std::is_same_v<T, SetFabricParams>) {
          std::snprintf(buf, sizeof buf, "SetFabricParams k=%g iterations=%d r=%g", a.params.k,
                        a.params.iterations, a.params.r);
          return buf;
        } else if constexpr (std::is_same_v<T, SetView>)
          return std::string("SetView ") + render::viewName(a.view);
        else if constexpr (std::is_same_v<T, SetNeurological>)
          return a.on ? "SetNeurological on" : "SetNeurological off";
        else if constexpr (std::is_same_v<T, SetSplit>)
          return std::string(a.on ? "SetSplit on" : "SetSplit off") +
                 (a.mode ? std::string(" ") + secondPaneName(*a.mode) : std::string());
        else if constexpr (std::is_same_v<T, SetLinkedCameras>)
          return a.on ? "SetLinkedCameras on" : "SetLinkedCameras off";
        else if constexpr (std::is_same_v<T, SetSecondPane>)
          return std::string("SetSecondPane ") + secondPaneName(a.mode);
        else if constexpr (std::is_same_v<T, SetOrtho>)
          return a.on ? "SetOrtho on" : "SetOrtho off";
        else if constexpr (std::is_same_v<T, SetCrosshair>) {
          std::snprintf(buf, sizeof buf, "SetCrosshair %g %g %g", a.world.x, a.world.y, a.world.z);
          return buf;
        } else if constexpr (std::is_same_v<T, RecordMovie>) {
          if (a.kind == RecordMovie::Kind::Sweep)
            std::snprintf(buf, sizeof buf, "RecordMovie sweep %s %d frames at %g fps ", a.axis.c_str(), a.frames,
                          a.fps);
          else if (a.kind == RecordMovie::Kind::FaSweep)
            std::snprintf(buf, sizeof buf, "RecordMovie fa-sweep %g:%g %d frames at %g fps ", a.faLo, a.faHi,
                          a.frames, a.fps);
          else
            std::snprintf(buf, sizeof buf, "RecordMovie turntable %d frames at %g fps ", a.frames, a.fps);
          return buf + std::string(a.force ? "--force " : "") + a.path;
        } else if constexpr (std::is_same_v<T, SetBackground>) {
          return "SetBackground " + (a.what.empty() ? std::string("default") : a.what) +
                 (a.window.empty() ? std::string() : " " + a.window);
        } else if constexpr (std::is_same_v<T, SetFabricAlong>) {
          std::snprintf(buf, sizeof buf, " %g mm", a.mm ? *a.mm : 0.0);
          return std::string("SetFabricAlong") + (a.on ? (*a.on ? " on" : " off") : "") + (a.mm ? buf : "");
        } else if constexpr (std::is_same_v<T, SetProfile>) {
          return std::string("SetProfile") + (a.on ? (*a.on ? " on" : " off") : "") +
                 (a.scalar ? " " + *a.scalar : "");
        } else if constexpr (std::is_same_v<T, HoverProfileNode>) {
          return "HoverProfileNode " + std::to_string(a.node) + (a.pin ? " pin" : "");
        } else if constexpr (std::is_same_v<T, SetFurniture>) {
          auto piece = [](const char* name, const std::optional<bool>& on) {
            return on ? std::string(" ") + name + (*on ? " on" : " off") : std::string();
          };
          return "SetFurniture" + piece("legend", a.legend) + piece("scale-bar", a.scaleBar) +
                 piece("colour-bar", a.colourBar);
        } else if constexpr (std::is_same_v<T, ResetView>)
          return "ResetView";
        else if constexpr (std::is_same_v<T, Rotate>) {
          std::snprintf(buf, sizeof buf, "Rotate %g %g", a.dx, a.dy);
          return buf;
        } else if constexpr (std::is_same_v<T, Pan>) {
          std::snprintf(buf, sizeof buf, "Pan %g %g", a.dx, a.dy);
          return buf;
        } else if constexpr (std::is_same_v<T, Zoom>) {
          std::snprintf(buf, sizeof buf, "Zoom %g", a.factor);
          return buf;
        } else if constexpr (std::is_same_v<T, Screenshot>)
          return std::string(a.sceneOnly ? "Screenshot scene " : "Screenshot ") +
                 (a.force ? "--force " : "") + a.path;
        else if constexpr (std::is_same_v<T, SaveCamera>)
          return "SaveCamera " + std::string(a.force ? "--force " : "") + a.path;
        else if constexpr (std::is_same_v<T, LoadCamera>)
          return "LoadCamera " + a.path;
        else if constexpr (std::is_same_v<T, LoadTracts>)
          return "LoadTracts " + a.path;
        else if constexpr (std::is_same_v<T, SetTractsVisible>)
          return a.on ? "SetTractsVisible on" : "SetTractsVisible off";
        else if constexpr (std::is_same_v<T, SetTractsNear>) {
          std::snprintf(buf, sizeof buf, "SetTractsNear %g", a.mm);
          return buf;
        } else if constexpr (std::is_same_v<T, SetTractWidth>) {
          std::snprintf(buf, sizeof buf, "SetTractWidth %g", a.px);
          return buf;
        } else if constexpr (std::is_same_v<T, SetTractsClip>) {
          std::snprintf(buf, sizeof buf, "SetTractsClip %g %g", a.mm, a.offsetMm);
          return buf;
        } else if constexpr (std::is_same_v<T, SetTractColour>) {
          if (a.value.empty()) return "SetTractColour dec";
          if (!a.range) return "SetTractColour " + a.value;
          std::snprintf(buf, sizeof buf, " %g %g", a.range->first, a.range->second);
          return "SetTractColour " + a.value + buf;
        } else if constexpr (std::is_same_v<T, SetTractGroups>) {
          if (a.all) return "SetTractGroups all";
          std::string s = "SetTractGroups";
          for (const auto& g : a.shown)
            s += " " + g;
          return a.shown.empty() ? s + " none" : s;
        } else if constexpr (std::is_same_v<T, TrackTracts>) {
          static const char* const seeds[] = {"data", "mask", "surface", "slice", "sphere", "fa-mask"};
          static const char* const counts[] = {"select", "seeds", "per-voxel"};
          const TrackRequest& r = a.request;
          std::snprintf(buf, sizeof buf,
                        "TrackTracts seeds=%s %s=%d fa-stop=%g angle=%g step=%g length=%g..%g",
                        seeds[static_cast<int>(r.seeds)], counts[static_cast<int>(r.count)], r.number,
                        r.options.faStop, r.options.maxAngleDeg, r.options.stepMm, r.options.minLengthMm,
                        r.options.maxLengthMm);
          return buf;
        } else if constexpr (std::is_same_v<T, CancelTracking>)
          return "CancelTracking";
        else if constexpr (std::is_same_v<T, SaveTracts>)
          return "SaveTracts " + a.path + (a.selected ? " selected" : "") +
                 (a.asGroup.empty() ? "" : " as-group " + a.asGroup) + (a.force ? " (force)" : "");
        else if constexpr (std::is_same_v<T, RoiAdd>)
          return std::string("RoiAdd ") + surfaces::kindName(a.kind) + " " +
                 (a.spec.empty() ? std::string(surfaces::shapeName(a.region.shape)) : a.spec);
        else if constexpr (std::is_same_v<T, RoiSet>)
          return "RoiSet " + std::to_string(a.index) + " " + surfaces::kindName(a.region.kind) + " " +
                 surfaces::shapeName(a.region.shape);
        else if constexpr (std::is_same_v<T, RoiVisible>)
          return "RoiVisible " + std::to_string(a.index) + (a.on ? " on" : " off");
        else if constexpr (std::is_same_v<T, RoiRemove>)
          return "RoiRemove " + std::to_string(a.index);
        else if constexpr (std::is_same_v<T, RoiClear>)
          return "RoiClear";
        else if constexpr (std::is_same_v<T, RoiEndsOnly>)
          return std::string("RoiEndsOnly ") + (a.on ? "on" : "off");
        else if constexpr (std::is_same_v<T, RoiHideOthers>)
          return std::string("RoiHideOthers ") + (a.on ? "on" : "off");
        else if constexpr (std::is_same_v<T, SaveRegions>)
          return "SaveRegions " + a.path + (a.force ? " (force)" : "");
        else if constexpr (std::is_same_v<T, LoadRegions>)
          return "LoadRegions " + a.path;
        else if constexpr (std::is_same_v<T, ComputeAgreement>) {
          std::snprintf(buf, sizeof buf, "ComputeAgreement near=%g bins=%d", a.nearMm, a.bins);
          return buf;
        } else if constexpr (std::is_same_v<T, Browse>)
          return std::string("Browse ") + std::to_string(static_cast<int>(a.target)) +
                 (a.folder.empty() ? "" : " " + a.folder);
        else if constexpr (std::is_same_v<T, SetCamera>) {
          std::snprintf(buf, sizeof buf, "SetCamera eye %g %g %g target %g %g %g pane %d", a.camera.eye.x,
                        a.camera.eye.y, a.camera.eye.z, a.camera.target.x, a.camera.target.y,
                        a.camera.target.z, a.pane);
          return buf;
        } else if constexpr (std::is_same_v<T, SaveSession>)
          return "SaveSession " + a.path + (a.force ? " (force)" : "");
        else if constexpr (std::is_same_v<T, ShowHelp>)
          return std::string("ShowHelp ") + (a.on ? (*a.on ? "on" : "off") : "toggle");
        else if constexpr (std::is_same_v<T, SetUiScale>) {
          std::snprintf(buf, sizeof buf, "SetUiScale %g", a.scale);
          return buf;
        } else if constexpr (std::is_same_v<T, DismissError>)
          return "DismissError";
        else if constexpr (std::is_same_v<T, ConfirmOverwrite>)
          return a.overwrite ? "ConfirmOverwrite yes" : "ConfirmOverwrite no";
        else
          return "Quit";
      },
      action);
}

std::vector<std::string> splitErrorChain(const std::string& message) {
  // Contexts are added as "while ...: " prefixes (dtf::rethrowWithContext); the rest is the cause.
  std::vector<std::string> links;
  std::size_t start = 0;
  while (message.compare(start, 6, "while ") == 0) {
    const std::size_t colon = message.find(": ", start);
    if (colon == std::string::npos) break;
    links.push_back(message.substr(start, colon - start));
    start = colon + 2;
  }
  if (start < message.size() || links.empty()) links.push_back(message.substr(start));
  return links;
}

} // namespace dtf::session
