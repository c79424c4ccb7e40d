// SPDX-License-Identifier: GPL-3.0-or-later
// The viewer's keyboard conventions as a pure function from a key and the current
// state to actions: Up/Down and PgUp/PgDn step the slice, A/C/S pick the axial/coronal/sagittal slice and
// its view, R resets the view. The app maps GLFW keys and script `key NAME` lines onto Key.
#pragma once

#include "ui/session/actions.h"
#include "ui/session/viewer_state.h"

#include <optional>
#include <string>

namespace dtf::session {

enum class Key { Up, Down, PageUp, PageDown, A, C, S, R };

// Parses Up, Down, PgUp/PageUp, PgDn/PageDown, A, C, S, R (case-insensitive); nullopt otherwise.
std::optional<Key> parseKey(const std::string& name);
const char* keyName(Key key);

// Slices moved by PgUp/PgDn.
inline constexpr int kPageSlices = 10;

// Appends the actions `key` stands for in `state` (none when it does not apply, e.g. Up without a slice).
void keyActions(Key key, const ViewerState& state, ActionList& out);

} // namespace dtf::session
