// SPDX-License-Identifier: GPL-3.0-or-later
// Viewer scripts (`dtfabric view --script FILE`): one command per line, replayed by the viewer as if the
// user had done it, so every figure can be reproduced. Parsing is pure (text in, steps out) and checks
// everything it can before a window opens; a bad line is a UsageError "FILE:LINE: ...".
//
// The commands, their arguments and help are the table scriptCommands() (`dtfabric view --help` prints it,
// `dtfabric help --markdown` the reference's table). Outputs (screenshots, camera and tract files) never
// replace an input; an existing file only with --force on the line or `view --force`.
// `#` starts a comment; blank lines are skipped.
#pragma once

#include "render/fabric_renderer.h"
#include "ui/session/actions.h"
#include "ui/session/keymap.h"

#include <string>
#include <variant>
#include <vector>

namespace dtf::app {

struct ScriptWait {
  int frames;
};
struct ScriptProbe {
  double x, y; // scene pixels, y down
};
struct ScriptClick {
  double x, y; // scene pixels, y down: in the ortho layout, a click in a slice pane moves the crosshair
};
struct ScriptResize {
  int width, height; // window pixels
};
struct ScriptSetParam {
  std::string name; // the option's name in render/fabric_options.h
  double value;     // on/off -> 1/0, medical/engineering -> 0/1
};

struct ScriptStep {
  int line = 0; // 1-based line in the file
  std::variant<session::Action, session::Key, ScriptWait, ScriptSetParam, ScriptProbe, ScriptResize, ScriptClick> command;
};

struct ViewScript {
  std::string file;
  std::vector<ScriptStep> steps;
};

struct ScriptLine; // one line split into words (view_script.cpp)
// One script command: its name, arguments and one-line help (as `view --help` and the reference show them) and
// its parser. A new command is one entry in scriptCommands().
struct ScriptCommand {
  const char* name;
  const char* args; // e.g. "[--force] PATH"; "" none
  const char* help;
  void (*parse)(const ScriptLine& line, ScriptStep& step); // throws for a bad line
};
// Every script command, in the order help lists them.
const std::vector<ScriptCommand>& scriptCommands();
// `view --help`'s list of them: "  NAME ARGS   help" per line.
std::string scriptCommandsHelp();

// Parses script text; `file` names it in messages. Throws UsageError "FILE:LINE: what is wrong".
ViewScript parseViewScript(const std::string& text, const std::string& file);
// Reads and parses a script file. Throws InputError when it cannot be read, UsageError for a bad line.
ViewScript loadViewScript(const std::string& path);
// Checks the outputs of screenshot/camera-save lines before a window opens: a path naming one of `inputs`,
// the script itself or a file the script reads (load with its .bval/.bvec, tracts, surface files) is
// refused whatever --force says; an existing file is refused unless its line or `force` says --force.
// Throws InputError "FILE:LINE: ...". The viewer checks again when it writes (files may appear meanwhile).
void checkScriptOutputs(const ViewScript& script, std::vector<std::string> inputs, bool force);
// Applies a `set` line to fabric parameters (values already validated by the parser).
void applyScriptParam(render::FabricParams& params, const ScriptSetParam& param);

} // namespace dtf::app
