// SPDX-License-Identifier: GPL-3.0-or-later
// What the viewer's file dialogs and dropped files are for, without a window: the targets the panels take a
// path for (data, tensor, background, tracts, mesh, regions, the outputs), which file names each target
// reads, a folder listed for the in-window browser (ui/panels/file_browser.h), and a dropped file's kind
// (a volume opens as data, a tractogram as tracts, a mesh as the surface, a region set as regions). The
// window's dialogs (the desktop portal, the in-window browser) and a drop all end in the actions here or in
// the panels' own open path, so a chosen, dropped or typed path is opened the same way.
#pragma once

#include "ui/session/actions.h"

#include <cstdint>
#include <string>
#include <vector>

namespace dtf::session {

// "data", "tensor", "background", "tracts", "mesh", "regions", "session" (inputs); "screenshot", "camera",
// "movie", "tracts-save", "session-save" (outputs).
const char* fileTargetName(FileTarget target);
// Parses the names above; nullopt otherwise.
std::optional<FileTarget> parseFileTarget(const std::string& name);
// An output: the dialog asks where to save, the browser takes a typed name.
bool isSaveTarget(FileTarget target);
// The dialog's title, e.g. "Open a tensor volume, DWI or fibre set".
const char* fileTargetTitle(FileTarget target);
// The name patterns `target` reads or writes, e.g. {"*.nii", "*.nii.gz", ...} (the portal's filter).
const std::vector<std::string>& fileTargetPatterns(FileTarget target);
// Whether the file name `name` (no folder) matches one of the target's patterns (case-insensitive).
bool fileTargetAccepts(FileTarget target, const std::string& name);

struct FolderEntry {
  std::string name;
  bool folder = false;
  std::uintmax_t bytes = 0; // files
};

// A folder as the in-window browser shows it: its subfolders, then the files the target reads, each sorted
// by name (case-insensitive); hidden entries (a leading dot) left out. `error` says why it could not be
// listed (then `entries` is empty).
struct FolderListing {
  std::string folder; // absolute, normalised
  std::vector<FolderEntry> entries;
  std::string error;
};
FolderListing listFolder(const std::string& folder, FileTarget target);

// What a dropped file opens as.
enum class DropKind { Data, Tracts, Mesh, Regions };
const char* dropKindName(DropKind kind); // "data", "tracts", "surface mesh", "regions"

// Decides a dropped file's kind: meshes by name (.ply, .obj; a .vtk or .vtp holding
// polygons rather than lines), a .json region set, tract files by name, else what io/input.h makes of it (a
// tensor volume, DWI or fibre set opens as data; a folder too, as a bedpostx folder). Throws InputError
// naming the file when it does not exist, cannot be read, or is none of these.
DropKind classifyDrop(const std::string& path);

// The actions a drop of `paths` (several at once) stands for: each file checked first, and on any failure
// nothing at all (InputError naming the file and why). A region set (ui/session/region_spec.h) is read and
// checked, then loaded as the ROI selection's regions (LoadRegions).
// The mesh comes before the data so the data's first surface is the mesh; tracts after the data. Two volumes
// or two tractograms in one drop are refused (which one to show is not for the viewer to guess). `layout`
// and `tensor` are the Data panel's choice for the volume, as its Open button takes them.
ActionList dropActions(const std::vector<std::string>& paths, const std::string& layout = "auto",
                       const std::string& tensor = {});

} // namespace dtf::session
