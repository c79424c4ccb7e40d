// SPDX-License-Identifier: GPL-3.0-or-later
#include "ui/session/keymap.h"

#include <algorithm>
#include <cctype>

namespace dtf::session {

std::optional<Key> parseKey(const std::string& name) {
  std::string n(name);
  std::transform(n.begin(), n.end(), n.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (n == "up") return Key::Up;
  if (n == "down") return Key::Down;
  if (n == "pgup" || n == "pageup") return Key::PageUp;
  if (n == "pgdn" || n == "pagedown") return Key::PageDown;
  if (n == "a") return Key::A;
  if (n == "c") return Key::C;
  if (n == "s") return Key::S;
  if (n == "r") return Key::R;
  if (n == "f1" || n == "?" || n == "help") return Key::Help;
  return std::nullopt;
}

const char* keyName(Key key) {
  switch (key) {
  case Key::Up:
    return "Up";
  case Key::Down:
    return "Down";
  case Key::PageUp:
    return "PgUp";
  case Key::PageDown:
    return "PgDn";
  case Key::A:
    return "A";
  case Key::C:
    return "C";
  case Key::S:
    return "S";
  case Key::R:
    return "R";
  case Key::Help:
    return "F1";
  }
  return "?";
}

void keyActions(Key key, const ViewerState& state, ActionList& out) {
  auto pick = [&](SurfaceKind kind, render::StandardView view) {
    out.push_back(SetSurfaceKind{kind});
    out.push_back(SetView{view});
  };
  int step = 0;
  switch (key) {
  case Key::Up:
    step = 1;
    break;
  case Key::Down:
    step = -1;
    break;
  case Key::PageUp:
    step = kPageSlices;
    break;
  case Key::PageDown:
    step = -kPageSlices;
    break;
  case Key::A:
    pick(SurfaceKind::Axial, render::StandardView::Axial);
    return;
  case Key::C:
    pick(SurfaceKind::Coronal, render::StandardView::Coronal);
    return;
  case Key::S:
    pick(SurfaceKind::Sagittal, render::StandardView::Sagittal);
    return;
  case Key::R:
    out.push_back(ResetView{});
    return;
  case Key::Help:
    out.push_back(ShowHelp{});
    return;
  }
  const int axis = sliceAxisOf(state.surface);
  if (axis < 0 || !state.hasData) return;
  const int count = std::max(state.sliceCount[axis], 1);
  const int next = std::clamp(state.slice[axis] + step, 0, count - 1);
  if (next != state.slice[axis]) out.push_back(SetSlice{axis, next});
}

const std::vector<Binding>& bindings() {
  static const std::vector<Binding> b = {
      {"left drag", "rotate (trackball)"},
      {"middle drag, shift + left drag", "pan"},
      {"wheel", "zoom"},
      {"left click (ortho slice pane)", "move the crosshair"},
      {"files dropped on the window", "open by kind: data, tracts, surface mesh"},
      {"Up / Down", "next / previous slice"},
      {"PgUp / PgDn", "10 slices on / back"},
      {"A, C, S", "axial, coronal, sagittal slice and view"},
      {"R", "reset the view"},
      {"Esc", "close the error message"},
      {"F1 or ?", "show or hide this help"},
  };
  return b;
}

} // namespace dtf::session
