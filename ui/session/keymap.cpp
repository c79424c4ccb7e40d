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
  }
  const int axis = sliceAxisOf(state.surface);
  if (axis < 0 || !state.hasData) return;
  const int count = std::max(state.sliceCount[axis], 1);
  const int next = std::clamp(state.slice[axis] + step, 0, count - 1);
  if (next != state.slice[axis]) out.push_back(SetSlice{axis, next});
}

} // namespace dtf::session
