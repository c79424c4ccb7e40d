// SPDX-License-Identifier: GPL-3.0-or-later
// The viewer's keyboard conventions as a pure function from a key and the current
// state to actions: Up/Down and PgUp/PgDn step the slice, A/C/S pick the axial/coronal/sagittal slice and
// its view, R resets the view, F1 (or ?) shows the bindings over the scene. The app maps GLFW keys and script
// `key NAME` lines onto Key; bindings() lists the keys with the mouse for the help overlay.
#pragma once

#include "ui/session/actions.h"
#include "ui/session/viewer_state.h"

#include <optional>
#include <string>
#include <vector>

namespace dtf::session {

enum class Key { Up, Down, PageUp, PageDown, A, C, S, R, Help };

// Parses Up, Down, PgUp/PageUp, PgDn/PageDown, A, C, S, R, F1 (or ?) (case-insensitive); nullopt otherwise.
std::optional<Key> parseKey(const std::string& name);
const char* keyName(Key key);

// Slices moved by PgUp/PgDn.
inline constexpr int kPageSlices = 10;

// Appends the actions `key` stands for in `state` (none when it does not apply, e.g. Up without a slice).
void keyActions(Key key, const ViewerState& state, ActionList& out);

// One line of the help overlay: the mouse gesture or key, and what it does.
struct Binding {
  const char* input;
  const char* does;
};
// The mouse and keyboard bindings of the viewer, mouse first.
const std::vector<Binding>& bindings();

} // namespace dtf::session
