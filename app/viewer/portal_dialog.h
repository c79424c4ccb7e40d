// SPDX-License-Identifier: GPL-3.0-or-later
// The desktop's own file dialog through the XDG desktop portal (libportal), for the window's Browse actions:
// asked asynchronously, its answer taken from GLib's default main context, which the window iterates once a
// frame without blocking. connect() gives none where no session bus or no portal runs (as under Xvfb); the
// window then shows its in-window browser (ui/panels/file_browser.h). GLib stays inside this file's source.
#pragma once

#include "ui/session/actions.h"

#include <memory>
#include <optional>
#include <string>

namespace dtf::app {

class PortalDialog {
public:
  // The portal on the session bus (org.freedesktop.portal.Desktop running or activatable), or null.
  static std::unique_ptr<PortalDialog> connect();
  ~PortalDialog();
  PortalDialog(const PortalDialog&) = delete;
  PortalDialog& operator=(const PortalDialog&) = delete;

  // Asks for a file for `target` (an output: where to save, starting in `folder`); false when a question is
  // still open.
  bool ask(session::FileTarget target, const std::string& folder);
  // Runs the main context's pending work without blocking: the portal's answer arrives here.
  void iterate();

  struct Answer {
    session::FileTarget target = session::FileTarget::Data;
    std::string path;  // empty: cancelled (or failed)
    std::string error; // the portal failed: the caller falls back to the in-window browser
  };
  // The answer to the last question, once.
  std::optional<Answer> take();

  struct State; // libportal's objects (portal_dialog.cpp)

private:
  explicit PortalDialog(std::unique_ptr<State> state);
  std::unique_ptr<State> state_;
};

} // namespace dtf::app
