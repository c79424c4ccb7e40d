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

// Throws InputError if `target` exists and is not a regular file (a folder, a device, a pipe): an output
// replaces only a file. AtomicOutput checks it before writing and again before the rename.
void refuseReplacingNonFile(const std::string& target);

// Throws InputError if `output` names the same file as any of `inputs`.
void refuseOverwritingInput(const std::string& output, const std::vector<std::string>& inputs);

// Throws UsageError if two of one command's outputs (empty: not asked for) name the same file, however
// spelled (./x, a/../x, a symbolic link, a hard link): the second write would replace the first.
void refuseSameOutputs(const std::vector<std::string>& outputs);

} // namespace dtf::io
