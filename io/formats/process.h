// SPDX-License-Identifier: GPL-3.0-or-later
// Runs another program without a shell: every argument reaches it as it is (a path holding spaces, quotes,
// `$(...)` or markup is one argument, never a command). Movies find ffmpeg with it; the benchmarks' peers
// (MRtrix, nibabel, Chromium, ParaView, a worker dtfabric) start through it.
#pragma once

#include <string>
#include <vector>

namespace dtf::io {

struct ProgramIo {
  std::string stdoutPath = "/dev/null"; // "" = this process's stdout
  std::string stderrPath = "/dev/null"; // "" = this process's stderr; == stdoutPath: both into that file
  std::vector<std::string> environment; // "NAME=VALUE" set (or replaced) for the program only
};

// Runs argv[0] (searched on PATH when it holds no '/') with argv and waits for it. Stdin is /dev/null.
// Returns its exit status, 128 + the signal when a signal ended it, 127 when it could not start.
int runProgram(const std::vector<std::string>& argv, const ProgramIo& io = {});

// The absolute path of an executable file `name` on PATH ("" when there is none).
std::string findOnPath(const std::string& name);

} // namespace dtf::io
