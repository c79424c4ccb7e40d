// SPDX-License-Identifier: GPL-3.0-or-later
// The viewer's orientation check: when the scene's dataset changes (a DWI, tensor file or a new load), the
// check (surfaces/analyses/orientation_check.h) runs on its own thread; its verdict is shown by
// ui/orientation_banner.h over the scene; on request the contact sheet is rendered (on the GUI thread, with
// the window's context) into a texture; "apply the correction" turns the scene's tensors in memory
// (ViewerScene::replaceField). Kept apart from the window and the scene so either can change without touching
// it.
#pragma once

#include "app/viewer/viewer.h"
#include "ui/panels/orientation_banner.h"
#include "ui/session/check_run.h"

#include <future>
#include <memory>
#include <optional>

namespace dtf::app {

class ViewerOrientation {
public:
  ViewerOrientation() = default;
  ~ViewerOrientation(); // waits for a running check; GL resources go with release()
  ViewerOrientation(const ViewerOrientation&) = delete;
  ViewerOrientation& operator=(const ViewerOrientation&) = delete;

  // Once per GUI frame inside the ImGui frame (after the panels), with the window's GL context current:
  // starts a check for a new dataset, collects a finished one, draws the banner over the scene rectangle
  // `rect` (x, y, w, h, window pixels) and performs what it returns.
  // `centres` (tests) receives the banner's button centres.
  void frame(ViewerScene& scene, const float rect[4],
             std::map<std::string, std::array<float, 2>>* centres = nullptr);
  const ui::OrientationBannerState& banner() const { return banner_; }
  // Deletes the contact sheet's texture; call while the window's context is still current.
  void release();

private:
  struct Result {
    std::shared_ptr<const session::ViewerDataset> data;
    session::CheckRun run;
    std::string error;
  };
  void renderSheet();

  std::shared_ptr<const session::ViewerDataset> seen_; // the dataset the last check was started for
  std::future<Result> running_;
  std::optional<Result> result_;
  ui::OrientationBannerState banner_;
  unsigned texture_ = 0;
};

} // namespace dtf::app
