// SPDX-License-Identifier: GPL-3.0-or-later
#include "ui/panels/file_browser.h"

#include "ui/panels/panels.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <imgui.h>

namespace dtf::ui {

namespace fs = std::filesystem;

namespace {

constexpr std::size_t kMaxRecentFolders = 8;

void copyText(char* dst, std::size_t size, const std::string& src) {
  std::snprintf(dst, size, "%s", src.c_str());
}

std::string sizeText(std::uintmax_t bytes) {
  char buf[32];
  if (bytes >= (1u << 30))
    std::snprintf(buf, sizeof buf, "%.1f GB", static_cast<double>(bytes) / (1u << 30));
  else if (bytes >= (1u << 20))
    std::snprintf(buf, sizeof buf, "%.1f MB", static_cast<double>(bytes) / (1u << 20));
  else
    std::snprintf(buf, sizeof buf, "%.0f kB", static_cast<double>(bytes) / 1024.0);
  return buf;
}

// The browser's choice: closes it, remembers the folder and hands the path to the panels' open path.
void choose(PanelBuffers& pb, const std::string& path, session::ActionList& out) {
  FileBrowserState& b = pb.browser;
  b.open = false;
  b.pickError.clear();
  rememberFolder(b, path);
  choosePath(pb, b.target, path, out);
}

} // namespace

// The part of `path` after its last '/' (the whole path when it has none), without allocating.
static const char* baseName(const std::string& path) {
  const auto slash = path.find_last_of('/');
  return slash == std::string::npos || slash + 1 == path.size() ? path.c_str() : path.c_str() + slash + 1;
}

void enterFolder(FileBrowserState& b, const std::string& folder) {
  b.listing = session::listFolder(folder, b.target);
  copyText(b.folderText.data(), b.folderText.size(), b.listing.folder);
  b.pickError.clear();
  b.labels.clear();
  b.sizes.clear();
  for (const auto& e : b.listing.entries) {
    b.labels.push_back(e.folder ? e.name + "/" : e.name);
    b.sizes.push_back(e.folder ? std::string() : sizeText(e.bytes));
  }
}

void openFileBrowser(FileBrowserState& b, session::FileTarget target, const std::string& folder) {
  b.open = true;
  b.target = target;
  b.name[0] = '\0';
  b.patterns.clear();
  for (const auto& p : session::fileTargetPatterns(target))
    b.patterns += (b.patterns.empty() ? "" : " ") + p;
  std::error_code ec;
  const std::string start = !folder.empty()         ? folder
                            : !b.lastFolder.empty() ? b.lastFolder
                                                    : fs::current_path(ec).string();
  enterFolder(b, start);
}

void rememberFolder(FileBrowserState& b, const std::string& chosenPath) {
  const std::string folder = fs::absolute(chosenPath).lexically_normal().parent_path().string();
  if (folder.empty()) return;
  b.lastFolder = folder;
  auto& r = b.recentFolders;
  r.erase(std::remove(r.begin(), r.end(), folder), r.end());
  r.insert(r.begin(), folder);
  if (r.size() > kMaxRecentFolders) r.resize(kMaxRecentFolders);
}

bool pickInBrowser(PanelBuffers& pb, const std::string& name, session::ActionList& out) {
  FileBrowserState& b = pb.browser;
  if (!b.open) return false;
  if (name == "..") {
    enterFolder(b, fs::path(b.listing.folder).parent_path().string());
    return true;
  }
  for (const auto& e : b.listing.entries)
    if (e.name == name) {
      const std::string path = (fs::path(b.listing.folder) / e.name).string();
      // A folder is entered, except that data may be a bedpostx folder: "open folder" chooses it.
      if (e.folder)
        enterFolder(b, path);
      else
        choose(pb, path, out);
      return true;
    }
  if (session::isSaveTarget(b.target) && !name.empty() && name.find('/') == std::string::npos) {
    choose(pb, (fs::path(b.listing.folder) / name).string(), out);
    return true;
  }
  b.pickError = name + ": not in " + b.listing.folder;
  return false;
}

void fileBrowserPanel(const session::ViewerState& s, PanelBuffers& pb, session::ActionList& out) {
  FileBrowserState& b = pb.browser;
  if (!b.open) return;
  const char* kTitle = "Choose a file###browser";
  if (!ImGui::IsPopupOpen(kTitle)) ImGui::OpenPopup(kTitle);
  const ImGuiIO& io = ImGui::GetIO();
  ImGui::SetNextWindowPos(ImVec2(io.DisplaySize.x * 0.5f, io.DisplaySize.y * 0.5f), ImGuiCond_Always,
                          ImVec2(0.5f, 0.5f));
  ImGui::SetNextWindowSize(ImVec2(std::min(io.DisplaySize.x * 0.9f, 46 * ImGui::GetFontSize()),
                                  std::min(io.DisplaySize.y * 0.85f, 34 * ImGui::GetFontSize())),
                           ImGuiCond_Always);
  bool keep = true;
  if (!ImGui::BeginPopupModal(kTitle, &keep, ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoMove)) {
    b.open = false;
    return;
  }
  ImGui::TextUnformatted(session::fileTargetTitle(b.target));
  ImGui::PushTextWrapPos(0.0f);
  ImGui::TextDisabled("%s", b.patterns.c_str());
  ImGui::PopTextWrapPos();

  if (ImGui::Button("Up")) enterFolder(b, fs::path(b.listing.folder).parent_path().string());
  ImGui::SameLine();
  ImGui::SetNextItemWidth(-1);
  if (ImGui::InputText("##folder", b.folderText.data(), b.folderText.size(),
                       ImGuiInputTextFlags_EnterReturnsTrue))
    enterFolder(b, b.folderText.data());

  const float footer = ImGui::GetFrameHeightWithSpacing() * (session::isSaveTarget(b.target) ? 2.2f : 1.2f) +
                       (b.pickError.empty() ? 0 : ImGui::GetTextLineHeightWithSpacing());
  const float side = 14 * ImGui::GetFontSize();
  // Left: the recent folders and files; right: the folder's entries.
  ImGui::BeginChild("##places", ImVec2(side, -footer), true);
  ImGui::TextDisabled("recent folders");
  for (std::size_t i = 0; i < b.recentFolders.size(); ++i) {
    ImGui::PushID(static_cast<int>(i));
    const std::string& f = b.recentFolders[i];
    if (ImGui::Selectable(baseName(f), f == b.listing.folder)) enterFolder(b, f);
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", f.c_str());
    ImGui::PopID();
  }
  if (!session::isSaveTarget(b.target) && !s.recent.empty()) {
    ImGui::Separator();
    ImGui::TextDisabled("recent files");
    for (std::size_t i = 0; i < s.recent.size(); ++i) {
      const std::string& f = s.recent[i];
      if (!session::fileTargetAccepts(b.target, f)) continue;
      ImGui::PushID(1000 + static_cast<int>(i));
      if (ImGui::Selectable(baseName(f))) choose(pb, f, out);
      if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", f.c_str());
      ImGui::PopID();
    }
  }
  ImGui::EndChild();
  ImGui::SameLine();
  ImGui::BeginChild("##entries", ImVec2(0, -footer), true);
  if (!b.listing.error.empty())
    ImGui::TextColored(ImVec4(1.0f, 0.5f, 0.4f, 1.0f), "%s", b.listing.error.c_str());
  int enter = -1;
  for (std::size_t i = 0; i < b.listing.entries.size() && b.open; ++i) {
    const auto& e = b.listing.entries[i];
    ImGui::PushID(static_cast<int>(i));
    if (ImGui::Selectable(b.labels[i].c_str(), false, ImGuiSelectableFlags_AllowDoubleClick)) {
      if (e.folder)
        enter = static_cast<int>(i); // entered after the loop: the listing is being drawn
      else if (session::isSaveTarget(b.target))
        copyText(b.name.data(), b.name.size(), e.name);
      else
        choose(pb, (fs::path(b.listing.folder) / e.name).string(), out);
    }
    if (pb.itemCentres) probeItem(pb, ("browser " + e.name).c_str());
    if (!e.folder) {
      ImGui::SameLine(ImGui::GetContentRegionAvail().x + ImGui::GetCursorPosX() - 6 * ImGui::GetFontSize());
      ImGui::TextDisabled("%s", b.sizes[i].c_str());
    }
    ImGui::PopID();
  }
  if (b.listing.entries.empty() && b.listing.error.empty())
    ImGui::TextDisabled("no folder or matching file here");
  ImGui::EndChild();
  if (enter >= 0)
    enterFolder(
        b, (fs::path(b.listing.folder) / b.listing.entries[static_cast<std::size_t>(enter)].name).string());

  if (!b.pickError.empty()) ImGui::TextColored(ImVec4(1.0f, 0.5f, 0.4f, 1.0f), "%s", b.pickError.c_str());
  if (b.open && session::isSaveTarget(b.target)) {
    ImGui::SetNextItemWidth(-8 * ImGui::GetFontSize());
    const bool enterName =
        ImGui::InputText("file name", b.name.data(), b.name.size(), ImGuiInputTextFlags_EnterReturnsTrue);
    ImGui::SameLine();
    const bool save = ImGui::Button("Save");
    if ((enterName || save) && b.name[0] != '\0')
      choose(pb, (fs::path(b.listing.folder) / b.name.data()).string(), out);
  }
  if (b.open && b.target == session::FileTarget::Data) {
    if (ImGui::Button("Open this folder (bedpostx)")) choose(pb, b.listing.folder, out);
    ImGui::SameLine();
  }
  if (b.open && ImGui::Button("Cancel")) b.open = false;
  if (!keep) b.open = false;
  if (!b.open) ImGui::CloseCurrentPopup();
  ImGui::EndPopup();
}

} // namespace dtf::ui
