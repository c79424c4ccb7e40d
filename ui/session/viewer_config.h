// SPDX-License-Identifier: GPL-3.0-or-later
// What the viewer remembers between runs: the window size, the panels' scale and which panels are open, the
// file dialogs' last folder and the recent files and folders, in $XDG_CONFIG_HOME/dtfabric/viewer.conf
// (default ~/.config). A small text file of "key value" lines, written atomically; an unreadable or bad file
// is ignored line by line (the viewer starts with the defaults) and never stops a run. Command-line flags
// win over it (mergeConfig); runs with --script neither read nor write it, and --no-config starts clean.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

namespace dtf::session {

struct ViewerConfig {
  std::optional<int> width, height;     // window size, pixels
  std::optional<double> uiScale;        // a scale the user set (--ui-scale, View panel); none: the monitor's
  std::string lastFolder;               // the file dialogs' last folder
  std::vector<std::string> recentFiles; // most recent first
  std::vector<std::string> recentFolders;
  std::map<std::string, bool> panelsOpen; // panel header -> open
};

// $XDG_CONFIG_HOME/dtfabric/viewer.conf, or $HOME/.config/dtfabric/viewer.conf; empty when neither is set.
std::string viewerConfigPath();
// Reads `path`; a missing file gives the defaults. Lines it does not understand are skipped and named in
// `warnings` (when given), as is a file that cannot be read.
ViewerConfig readViewerConfig(const std::string& path, std::vector<std::string>* warnings = nullptr);
// Writes `config` to `path` atomically, creating the folder. Throws InputError naming the file.
void writeViewerConfig(const std::string& path, const ViewerConfig& config);
std::string formatViewerConfig(const ViewerConfig& config);
ViewerConfig parseViewerConfig(const std::string& text, std::vector<std::string>* warnings = nullptr);

// The window's start settings from the command line and the remembered ones: a flag given wins, the
// remembered value fills what was not given.
struct StartSettings {
  int width = 1280, height = 800;
  std::optional<double> uiScale; // none: the monitor's content scale
};
StartSettings mergeConfig(const ViewerConfig& remembered, std::optional<int> width, std::optional<int> height,
                          std::optional<double> uiScale);

} // namespace dtf::session
