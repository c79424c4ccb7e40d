// SPDX-License-Identifier: GPL-3.0-or-later
#include "ui/panels/orientation_banner.h"

#include <cstdint>
#include <imgui.h>

namespace dtf::ui {

void orientationBannerColour(const std::string& verdict, float rgb[3]) {
  if (verdict == "ok") {
    rgb[0] = 0.15f, rgb[1] = 0.45f, rgb[2] = 0.2f;
  } else if (verdict == "corrected") {
    rgb[0] = 0.65f, rgb[1] = 0.12f, rgb[2] = 0.1f;
  } else {
    rgb[0] = 0.6f, rgb[1] = 0.45f, rgb[2] = 0.05f;
  }
}

namespace {
bool button(const char* label, std::map<std::string, std::array<float, 2>>* centres) {
  const bool pressed = ImGui::Button(label);
  if (centres) {
    const ImVec2 a = ImGui::GetItemRectMin(), b = ImGui::GetItemRectMax();
    (*centres)[label] = {0.5f * (a.x + b.x), 0.5f * (a.y + b.y)};
  }
  return pressed;
}
} // namespace

OrientationAction orientationBanner(const OrientationBannerState& s, const float rect[4],
                                    std::map<std::string, std::array<float, 2>>* centres) {
  // Nothing while the check runs or when the table checks out: the banner is a warning.
  if (!s.visible || s.running || s.verdict == "ok") return OrientationAction::None;
  OrientationAction action = OrientationAction::None;
  float rgb[3];
  orientationBannerColour(s.verdict, rgb);
  ImGui::SetNextWindowPos(ImVec2(rect[0], rect[1]), ImGuiCond_Always);
  ImGui::SetNextWindowSize(ImVec2(rect[2], 0), ImGuiCond_Always);
  ImGui::PushStyleColor(ImGuiCol_WindowBg, ImVec4(rgb[0], rgb[1], rgb[2], 0.92f));
  ImGui::PushStyleVar(ImGuiStyleVar_WindowPadding, ImVec2(6, 3));
  const ImGuiWindowFlags flags = ImGuiWindowFlags_NoTitleBar | ImGuiWindowFlags_NoResize |
                                 ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoSavedSettings |
                                 ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoFocusOnAppearing;
  if (ImGui::Begin("##orientation", nullptr, flags)) {
    if (s.verdict == "corrected" && !s.applied)
      ImGui::Text("Orientation check: the gradient table looks wrong; [%s] fits the anatomy better.",
                  s.correction.c_str());
    else if (s.verdict == "corrected")
      ImGui::Text("Orientation check: [%s] applied in memory (save it: dtfabric check --fix-bvec).",
                  s.correction.c_str());
    else
      ImGui::Text("Orientation check: %s.", s.verdict.c_str());
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", s.reason.c_str());
    if (button(s.sheetShown ? "Hide evidence" : "Show evidence", centres))
      action = s.sheetShown ? OrientationAction::HideSheet : OrientationAction::ShowSheet;
    if (s.verdict == "corrected" && !s.applied) {
      ImGui::SameLine();
      if (button("Apply correction", centres)) action = OrientationAction::ApplyCorrection;
    }
    ImGui::SameLine();
    if (button("Dismiss", centres)) action = OrientationAction::Dismiss;
  }
  ImGui::End();
  ImGui::PopStyleVar();
  ImGui::PopStyleColor();

  if (s.sheetShown) {
    ImGui::SetNextWindowPos(ImVec2(rect[0] + 20, rect[1] + 80), ImGuiCond_Appearing);
    bool open = true;
    if (ImGui::Begin("Orientation evidence", &open, ImGuiWindowFlags_AlwaysAutoResize)) {
      if (s.sheetTexture == 0)
        ImGui::TextUnformatted("rendering the contact sheet...");
      else
        ImGui::Image(reinterpret_cast<ImTextureID>(static_cast<std::uintptr_t>(s.sheetTexture)),
                     ImVec2(static_cast<float>(s.sheetWidth), static_cast<float>(s.sheetHeight)));
    }
    ImGui::End();
    if (!open) action = OrientationAction::HideSheet;
  }
  return action;
}

} // namespace dtf::ui
