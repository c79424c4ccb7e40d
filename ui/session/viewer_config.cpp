// SPDX-License-Identifier: GPL-3.0-or-later
#include "ui/session/viewer_config.h"

#include "io/formats/atomic_file.h"
#include "io/model/error.h"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace dtf::session {

namespace fs = std::filesystem;

namespace {

constexpr std::size_t kMaxRecent = 8;

std::string restOfLine(std::istringstream& in) {
  std::string rest;
  std::getline(in >> std::ws, rest);
  return rest;
}

} // namespace

std::string viewerConfigPath() {
  const char* xdg = std::getenv("XDG_CONFIG_HOME");
  if (xdg && *xdg && fs::path(xdg).is_absolute())
    return (fs::path(xdg) / "dtfabric" / "viewer.conf").string();
  const char* home = std::getenv("HOME");
  if (home && *home) return (fs::path(home) / ".config" / "dtfabric" / "viewer.conf").string();
  return {};
}

std::string formatViewerConfig(const ViewerConfig& c) {
  std::ostringstream out;
  out << "# dtfabric viewer settings, written when the viewer closes\n";
  if (c.width && c.height) out << "size " << *c.width << " " << *c.height << "\n";
  if (c.uiScale) out << "ui-scale " << *c.uiScale << "\n";
  if (!c.lastFolder.empty()) out << "last-folder " << c.lastFolder << "\n";
  for (const auto& f : c.recentFiles)
    out << "recent-file " << f << "\n";
  for (const auto& f : c.recentFolders)
    out << "recent-folder " << f << "\n";
  for (const auto& [name, open] : c.panelsOpen)
    out << "panel " << (open ? "open " : "closed ") << name << "\n";
  return out.str();
}

ViewerConfig parseViewerConfig(const std::string& text, std::vector<std::string>* warnings) {
  ViewerConfig c;
  std::istringstream lines(text);
  std::string line;
  int n = 0;
  auto warn = [&](const std::string& what) {
    if (warnings) warnings->push_back("line " + std::to_string(n) + ": " + what);
  };
  while (std::getline(lines, line)) {
    ++n;
    if (line.empty() || line[0] == '#') continue;
    std::istringstream in(line);
    std::string key;
    in >> key;
    if (key == "size") {
      int w = 0, h = 0;
      if (in >> w >> h && w >= 320 && h >= 240 && w <= 8192 && h <= 8192) {
        c.width = w;
        c.height = h;
      } else {
        warn("size takes W H between 320x240 and 8192x8192");
      }
    } else if (key == "ui-scale") {
      double s = 0;
      if (in >> s && std::isfinite(s) && s >= 0.5 && s <= 4)
        c.uiScale = s;
      else
        warn("ui-scale takes a number in [0.5, 4]");
    } else if (key == "last-folder") {
      c.lastFolder = restOfLine(in);
    } else if (key == "recent-file" || key == "recent-folder") {
      auto& list = key == "recent-file" ? c.recentFiles : c.recentFolders;
      const std::string path = restOfLine(in);
      if (!path.empty() && list.size() < kMaxRecent) list.push_back(path);
    } else if (key == "panel") {
      std::string state;
      in >> state;
      const std::string name = restOfLine(in);
      if ((state == "open" || state == "closed") && !name.empty())
        c.panelsOpen[name] = state == "open";
      else
        warn("panel takes open|closed NAME");
    } else {
      warn("unknown setting '" + key + "'");
    }
  }
  return c;
}

ViewerConfig readViewerConfig(const std::string& path, std::vector<std::string>* warnings) {
  std::error_code ec;
  if (path.empty() || !fs::exists(path, ec)) return {};
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  if (in) text << in.rdbuf();
  if (!in || text.str().size() > (1u << 20)) {
    if (warnings) warnings->push_back(path + ": cannot be read; the viewer starts with its defaults");
    return {};
  }
  std::vector<std::string> lineWarnings;
  ViewerConfig c = parseViewerConfig(text.str(), &lineWarnings);
  if (warnings)
    for (const auto& w : lineWarnings)
      warnings->push_back(path + ":" + w.substr(5));
  return c;
}

void writeViewerConfig(const std::string& path, const ViewerConfig& config) {
  if (path.empty())
    throw InputError("viewer settings: no folder for them ($XDG_CONFIG_HOME and $HOME unset)");
  std::error_code ec;
  fs::create_directories(fs::path(path).parent_path(), ec);
  if (ec)
    throw InputError(fs::path(path).parent_path().string() + ": cannot create the folder: " + ec.message());
  io::AtomicOutput file(path);
  {
    std::ofstream out(file.tempPath());
    out << formatViewerConfig(config);
    out.close();
    if (!out) throw InputError(path + ": cannot write the viewer settings");
  }
  file.commit();
}

StartSettings mergeConfig(const ViewerConfig& remembered, std::optional<int> width, std::optional<int> height,
                          std::optional<double> uiScale) {
  StartSettings s;
  if (width && height) {
    s.width = *width;
    s.height = *height;
  } else if (remembered.width && remembered.height) {
    s.width = *remembered.width;
    s.height = *remembered.height;
  }
  s.uiScale = uiScale ? uiScale : remembered.uiScale;
  return s;
}

} // namespace dtf::session
