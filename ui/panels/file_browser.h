// SPDX-License-Identifier: GPL-3.0-or-later
// The in-window file browser, the fallback of the desktop's own dialog (where no XDG desktop portal runs, as
// under Xvfb): a modal with the folder's path, its parent, the recent folders and files, the subfolders and
// the files the target reads (ui/session/file_kinds.h), and for an output a name field. Like ui/panels.h it
// changes no viewer state: a chosen file goes to choosePath (ui/panels/panels.h), the panels' own open path,
// which appends what the panel's button would. Listing a folder reads the disk once, when the folder is
// entered, never per frame.
#pragma once

#include "ui/session/actions.h"
#include "ui/session/file_kinds.h"

#include <array>
#include <string>
#include <vector>

namespace dtf::ui {

struct FileBrowserState {
  bool open = false;
  session::FileTarget target = session::FileTarget::Data;
  session::FolderListing listing;         // the folder shown
  std::array<char, 1024> folderText{};    // its path, editable
  std::array<char, 256> name{};           // outputs: the file name typed
  std::string lastFolder;                 // the folder the last file was chosen in
  std::vector<std::string> recentFolders; // most recent first
  std::string pickError;                  // why the last pick failed (a missing entry), shown in the browser
  // Made when a folder is entered, so drawing allocates nothing: each entry's label ("name/" for a folder)
  // and size text, and the target's patterns.
  std::vector<std::string> labels, sizes;
  std::string patterns;
};

// Opens the browser for `target` in `folder` (empty: the last folder, else the working folder).
void openFileBrowser(FileBrowserState& b, session::FileTarget target, const std::string& folder);
// Lists `folder` in the open browser.
void enterFolder(FileBrowserState& b, const std::string& folder);
// Records the folder of a chosen path as the last and most recent folder.
void rememberFolder(FileBrowserState& b, const std::string& chosenPath);

} // namespace dtf::ui
