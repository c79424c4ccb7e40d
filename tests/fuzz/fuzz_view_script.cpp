// SPDX-License-Identifier: GPL-3.0-or-later
// libFuzzer target: the viewer script parser (app/viewer/view_script.h), pure text in, steps or a UsageError out;
// then the output check that runs before a window opens (reads the file system only: exists/equivalent).
#include "app/viewer/view_script.h"
#include "io/model/error.h"

#include <cstddef>
#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const dtf::app::ViewScript script = dtf::app::parseViewScript(text, "fuzz.dtfs");
    dtf::render::FabricParams params;
    for (const auto& step : script.steps)
      if (const auto* set = std::get_if<dtf::app::ScriptSetParam>(&step.command))
        dtf::app::applyScriptParam(params, *set);
    dtf::app::checkScriptOutputs(script, {}, false);
  } catch (const dtf::Error&) {
  }
  return 0;
}
