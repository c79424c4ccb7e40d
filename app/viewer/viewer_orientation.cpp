// SPDX-License-Identifier: GPL-3.0-or-later
#include "app/viewer/viewer_orientation.h"

#include "io/diffusion/dwi.h"
#include "io/model/error.h"

#include <epoxy/gl.h>

namespace dtf::app {

namespace {

// The same rule loadTensorInput uses to treat a file as a DWI: 4D, not 6 volumes, not SYMMATRIX.
bool fittedFromDwi(const io::LoadedTensors& loaded) {
  const auto& dims = loaded.header.dims;
  return dims.size() == 4 && dims[3] > 1 && dims[3] != 6 && loaded.header.intentCode != 1005;
}

} // namespace

ViewerOrientation::~ViewerOrientation() {
  if (running_.valid()) running_.wait();
}

void ViewerOrientation::release() {
  if (running_.valid()) running_.wait();
  if (texture_) glDeleteTextures(1, &texture_);
  texture_ = 0;
  banner_.sheetTexture = 0;
}

void ViewerOrientation::frame(ViewerScene& scene, const float rect[4],
                              std::map<std::string, std::array<float, 2>>* centres) {
  const std::shared_ptr<const session::ViewerDataset> data = scene.dataset();
  if (data && data->fibres && data != seen_ && !running_.valid()) {
    // A fibre set is checked by `dtfabric check PEAKS`; its carrier field here is no diffusion tensor.
    seen_ = data;
    banner_ = {};
    result_.reset();
  } else if (data && data != seen_ && !running_.valid()) {
    seen_ = data;
    if (texture_) glDeleteTextures(1, &texture_);
    texture_ = 0;
    banner_ = {};
    banner_.visible = true;
    banner_.running = true;
    result_.reset();
    running_ = std::async(std::launch::async, [data] {
      Result r;
      r.data = data;
      try {
        r.run.dwi = fittedFromDwi(data->loaded);
        r.run.field = data->loaded.field;
        r.run.tableToWorld = r.run.dwi ? io::bvecFrameToWorld(r.run.field.grid) : glm::dmat3(1.0);
        r.run.report = surfaces::checkOrientation(r.run.field, r.run.tableToWorld);
      } catch (...) {
        r.error = currentExceptionMessage();
      }
      return r;
    });
  }
  if (running_.valid() && running_.wait_for(std::chrono::seconds(0)) == std::future_status::ready) {
    result_ = running_.get();
    banner_.running = false;
    if (result_->data != seen_) {
      banner_.visible = false; // the data changed while it ran: check again next frame
      seen_.reset();
    } else if (!result_->error.empty()) {
      banner_.verdict = "inconclusive";
      banner_.reason = "the check failed: " + result_->error;
    } else {
      const auto& rep = result_->run.report;
      banner_.verdict = surfaces::verdictName(rep.verdict);
      banner_.reason = rep.reason;
      banner_.correction = rep.candidates[rep.best].transform.name();
    }
  }

  switch (ui::orientationBanner(banner_, rect, centres)) {
  case ui::OrientationAction::ShowSheet:
    banner_.sheetShown = true;
    if (result_ && result_->error.empty() && texture_ == 0) renderSheet();
    break;
  case ui::OrientationAction::HideSheet:
    banner_.sheetShown = false;
    break;
  case ui::OrientationAction::Dismiss:
    banner_.visible = false;
    break;
  case ui::OrientationAction::ApplyCorrection:
    if (result_ && result_->error.empty()) {
      const session::CheckRun& run = result_->run;
      scene.replaceField(surfaces::transformedField(run.field, run.tableToWorld, run.report.correction));
      seen_ = scene.dataset(); // the corrected data is not checked again
      banner_.applied = true;
    }
    break;
  case ui::OrientationAction::None:
    break;
  }
}

void ViewerOrientation::renderSheet() {
  try {
    // Rendered on the GUI thread with the window's context (a second, headless context would not share it);
    // the fabric passes leave their own framebuffer bound, so the window's state is restored after.
    GLint fbo = 0, viewport[4];
    glGetIntegerv(GL_FRAMEBUFFER_BINDING, &fbo);
    glGetIntegerv(GL_VIEWPORT, viewport);
    const Image sheet =
        session::renderContactSheet(result_->run, session::sheetRows(result_->run.report), 192, false);
    glBindFramebuffer(GL_FRAMEBUFFER, static_cast<GLuint>(fbo));
    glViewport(viewport[0], viewport[1], viewport[2], viewport[3]);
    glGenTextures(1, &texture_);
    glBindTexture(GL_TEXTURE_2D, texture_);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, sheet.width, sheet.height, 0, GL_RGBA, GL_UNSIGNED_BYTE,
                 sheet.rgba.data());
    glBindTexture(GL_TEXTURE_2D, 0);
    banner_.sheetTexture = texture_;
    banner_.sheetWidth = sheet.width;
    banner_.sheetHeight = sheet.height;
  } catch (...) {
    banner_.reason += " (the contact sheet failed: " + currentExceptionMessage() + ")";
    banner_.sheetShown = false;
  }
}

} // namespace dtf::app
