// SPDX-License-Identifier: GPL-3.0-or-later
#include "ui/session/file_kinds.h"

#include "io/input.h"
#include "io/model/error.h"
#include "ui/session/region_spec.h"
#include "ui/session/tract_files.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <system_error>

namespace dtf::session {

namespace fs = std::filesystem;

namespace {

struct TargetInfo {
  FileTarget target;
  const char* name;
  const char* title;
  std::vector<std::string> patterns;
};

const std::vector<std::string> kVolumes = {"*.nii",  "*.nii.gz", "*.mif",    "*.mif.gz", "*.mih",
                                           "*.nrrd", "*.nhdr",   "*.src.gz", "*.src"};
const std::vector<std::string> kTracts = {"*.tck", "*.trk", "*.trk.gz", "*.trx", "*.vtk", "*.vtp"};
const std::vector<std::string> kMeshes = {"*.ply", "*.obj", "*.vtk", "*.vtp"};

const std::array<TargetInfo, 14>& targets() {
  static const std::array<TargetInfo, 14> t = {{
      {FileTarget::Data, "data", "Open a tensor volume, DWI or fibre set", kVolumes},
      {FileTarget::Tensor, "tensor", "Pair a tensor volume with the fibre set", kVolumes},
      {FileTarget::Background, "background", "Open a scalar volume for the background", kVolumes},
      {FileTarget::Tracts, "tracts", "Open streamlines", kTracts},
      {FileTarget::Mesh, "mesh", "Open a surface mesh", kMeshes},
      {FileTarget::Regions, "regions", "Open a region set", {"*.json"}},
      {FileTarget::Session, "session", "Open a viewer session", {"*.dtfview"}},
      {FileTarget::Screenshot, "screenshot", "Save a screenshot as", {"*.png"}},
      {FileTarget::Camera, "camera", "Save the camera as", {"*.camera"}},
      {FileTarget::Movie, "movie", "Record the movie to", {"*.mp4", "*.gif"}},
      {FileTarget::TractsSave, "tracts-save", "Save the tracts as", {"*.tck", "*.trk", "*.vtk"}},
      {FileTarget::SessionSave, "session-save", "Save the session as", {"*.dtfview"}},
      {FileTarget::RegionsSave, "regions-save", "Save the region set as", {"*.json"}},
      {FileTarget::SelectedSave, "selected-save", "Save the selected streamlines as",
       {"*.tck", "*.trk", "*.trx", "*.vtk"}},
  }};
  return t;
}

const TargetInfo& info(FileTarget target) {
  for (const auto& t : targets())
    if (t.target == target) return t;
  return targets()[0];
}

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

bool endsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// A legacy VTK or VTK XML file holding polygons (a mesh) rather than lines (streamlines): the first of the
// keywords found in its first 4 MiB, which hold the header and, for ASCII files, usually the cell lists.
// nullopt when neither is found.
std::optional<bool> vtkHoldsPolygons(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string head(4u << 20, '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(in.gcount()));
  const auto first = [&](std::initializer_list<const char*> words) {
    std::size_t at = std::string::npos;
    for (const char* w : words)
      at = std::min(at, head.find(w));
    return at;
  };
  const std::size_t polygons = first({"\nPOLYGONS ", "\nTRIANGLE_STRIPS ", "<Polys", "<Strips"});
  const std::size_t lines = first({"\nLINES ", "<Lines"});
  if (polygons == std::string::npos && lines == std::string::npos) return std::nullopt;
  return polygons < lines;
}

} // namespace

const char* fileTargetName(FileTarget target) {
  return info(target).name;
}

std::optional<FileTarget> parseFileTarget(const std::string& name) {
  for (const auto& t : targets())
    if (name == t.name) return t.target;
  return std::nullopt;
}

bool isSaveTarget(FileTarget target) {
  switch (target) {
  case FileTarget::Screenshot:
  case FileTarget::Camera:
  case FileTarget::Movie:
  case FileTarget::TractsSave:
  case FileTarget::SessionSave:
  case FileTarget::RegionsSave:
  case FileTarget::SelectedSave:
    return true;
  default:
    return false;
  }
}

const char* fileTargetTitle(FileTarget target) {
  return info(target).title;
}

const std::vector<std::string>& fileTargetPatterns(FileTarget target) {
  return info(target).patterns;
}

bool fileTargetAccepts(FileTarget target, const std::string& name) {
  const std::string n = lower(name);
  for (const std::string& p : info(target).patterns)
    if (endsWith(n, p.substr(1))) return true;
  return false;
}

FolderListing listFolder(const std::string& folder, FileTarget target) {
  FolderListing out;
  std::error_code ec;
  fs::path dir = fs::absolute(folder.empty() ? fs::path(".") : fs::path(folder), ec);
  if (!ec) dir = dir.lexically_normal();
  if (dir.has_filename() == false && dir != dir.root_path()) dir = dir.parent_path();
  out.folder = dir.string();
  fs::directory_iterator it(dir, fs::directory_options::skip_permission_denied, ec);
  if (ec) {
    out.error = out.folder + ": " + ec.message();
    return out;
  }
  for (; it != fs::directory_iterator(); it.increment(ec)) {
    if (ec) break;
    const std::string name = it->path().filename().string();
    if (name.empty() || name[0] == '.') continue;
    std::error_code e2;
    const bool folderEntry = it->is_directory(e2);
    // A TRX folder is a tract file; it is listed as a folder (it can be entered) and as a file.
    if (!folderEntry && !fileTargetAccepts(target, name)) continue;
    FolderEntry entry;
    entry.name = name;
    entry.folder = folderEntry;
    if (!folderEntry) entry.bytes = it->file_size(e2);
    out.entries.push_back(std::move(entry));
  }
  if (ec) {
    out.entries.clear();
    out.error = out.folder + ": " + ec.message();
    return out;
  }
  std::sort(out.entries.begin(), out.entries.end(), [](const FolderEntry& a, const FolderEntry& b) {
    if (a.folder != b.folder) return a.folder;
    const std::string la = lower(a.name), lb = lower(b.name);
    return la != lb ? la < lb : a.name < b.name;
  });
  return out;
}

const char* dropKindName(DropKind kind) {
  switch (kind) {
  case DropKind::Data:
    return "data";
  case DropKind::Tracts:
    return "tracts";
  case DropKind::Mesh:
    return "surface mesh";
  case DropKind::Regions:
    return "regions";
  }
  return "?";
}

DropKind classifyDrop(const std::string& path) {
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (ec || !fs::exists(st)) throw InputError(path + ": no such file");
  const bool folder = fs::is_directory(st);
  if (!folder && !std::ifstream(path, std::ios::binary)) throw InputError(path + ": cannot be read");
  const std::string name = lower(fs::path(path).filename().string());
  if (!folder) {
    if (endsWith(name, ".json")) return DropKind::Regions;
    for (const char* mesh : {".ply", ".obj"})
      if (endsWith(name, mesh)) return DropKind::Mesh;
    if (endsWith(name, ".vtk") || endsWith(name, ".vtp")) {
      const auto polygons = vtkHoldsPolygons(path);
      if (!polygons)
        throw InputError(path + ": a VTK file with neither polygons (a mesh) nor lines (streamlines)");
      return *polygons ? DropKind::Mesh : DropKind::Tracts;
    }
  }
  if (isTractFileName(path)) return DropKind::Tracts;
  io::InputRequest request;
  request.path = path;
  request.tractograms = true;
  try {
    const io::OpenedInput in = io::openInput(request);
    return in.kind == io::InputKind::Tractogram ? DropKind::Tracts : DropKind::Data;
  } catch (...) {
    rethrowWithContext("while opening the dropped file " + path);
  }
}

ActionList dropActions(const std::vector<std::string>& paths, const std::string& layout,
                       const std::string& tensor) {
  if (paths.empty()) throw InputError("nothing was dropped");
  std::optional<std::string> data, tracts, mesh;
  auto once = [](std::optional<std::string>& slot, const std::string& path, const char* what) {
    if (slot)
      throw InputError("two " + std::string(what) + " dropped at once (" + *slot + " and " + path +
                       "): drop one");
    slot = path;
  };
  for (const std::string& p : paths) {
    const std::string path = fs::absolute(p).lexically_normal().string();
    switch (classifyDrop(path)) {
    case DropKind::Data:
      once(data, path, "volumes");
      break;
    case DropKind::Tracts:
      once(tracts, path, "tractograms");
      break;
    case DropKind::Mesh:
      once(mesh, path, "meshes");
      break;
    case DropKind::Regions: {
      // Read and checked (a bad file says why), but the viewer has no regions to show it in yet.
      const surfaces::RegionSet set = readRegionSetFile(path);
      throw InputError(path + ": a region set of " + std::to_string(set.regions.size()) +
                       " regions; the viewer does not show regions yet (select with them: `dtfabric select "
                       "--roi " +
                       path + "`)");
    }
    }
  }
  ActionList out;
  if (mesh) out.push_back(SetSurfaceSpec{"mesh=" + *mesh});
  if (data) out.push_back(LoadFile{*data, layout.empty() ? "auto" : layout, tensor});
  if (tracts) out.push_back(LoadTracts{*tracts});
  return out;
}

} // namespace dtf::session
