// SPDX-License-Identifier: GPL-3.0-or-later
// Output files are written to a temporary sibling and renamed into place, so a failed or interrupted
// write never leaves a partial file and never truncates an existing one.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace dtf::io {

class AtomicOutput {
public:
  // Prepares a temporary path beside `target`. Throws InputError if the directory is not writable.
  explicit AtomicOutput(const std::string& target);
  ~AtomicOutput(); // removes the temporary file unless commit() ran
  AtomicOutput(const AtomicOutput&) = delete;
  AtomicOutput& operator=(const AtomicOutput&) = delete;

  const std::string& tempPath() const { return temp_; }
  // Renames the temporary file onto the target.
  void commit();

private:
  std::string target_, temp_;
  bool committed_ = false;
};

// All or nothing for the several files of one result (a tensor volume and its scalar map, a bedpostx
// folder, an .mih header and its data). While a batch lives on this thread, AtomicOutput::commit() hands
// its finished temporary file to the batch instead of renaming it; the batch's commit() renames them all,
// and a batch destroyed without commit() removes them, so a write that fails part-way leaves none of the
// set. A batch opened inside another defers to the outer one. A rename that fails inside commit() (the
// disk vanished) can still leave the files renamed before it.
class OutputBatch {
public:
  OutputBatch();
  ~OutputBatch();
  OutputBatch(const OutputBatch&) = delete;
  OutputBatch& operator=(const OutputBatch&) = delete;

  void commit();

private:
  friend class AtomicOutput;
  struct Pending {
    std::string target, temp;
  };
  bool outermost_;
  bool done_ = false;
  std::vector<Pending> pending_;
};

// Throws InputError naming `target` if it cannot be written: its folder is missing or it exists and is not
// a regular file. Commands call it for every output before long work, so a typo fails at once.
void refuseUnwritableOutput(const std::string& target);

// Throws InputError if `target` exists and is not a regular file (a folder, a device, a pipe): an output
// replaces only a file. AtomicOutput checks it before writing and again before the rename.
void refuseReplacingNonFile(const std::string& target);

// Whether an output would replace something at `target`: a file, a folder, or a symbolic link, even one
// whose target is missing (writing would replace the link itself). The commands' --force checks ask this.
bool outputExists(const std::string& target);

// Throws InputError if `output` names the same file as any of `inputs`.
void refuseOverwritingInput(const std::string& output, const std::vector<std::string>& inputs);

// Throws UsageError if two of one command's outputs (empty: not asked for) name the same file, however
// spelled (./x, a/../x, a symbolic link, a hard link): the second write would replace the first.
void refuseSameOutputs(const std::vector<std::string>& outputs);

} // namespace dtf::io
