// SPDX-License-Identifier: GPL-3.0-or-later
#include "io/formats/atomic_file.h"

#include "io/model/error.h"

#include <atomic>
#include <system_error>
#include <unistd.h>
#include <vector>

namespace fs = std::filesystem;

namespace dtf::io {

namespace {
thread_local OutputBatch* activeBatch = nullptr;

fs::path folderOf(const std::string& target) {
  const fs::path p(target);
  return p.has_parent_path() ? p.parent_path() : fs::path(".");
}
} // namespace

void refuseUnwritableOutput(const std::string& target) {
  std::error_code ec;
  if (!fs::is_directory(folderOf(target), ec))
    throw InputError("cannot write " + target + ": directory does not exist");
  refuseReplacingNonFile(target);
}

AtomicOutput::AtomicOutput(const std::string& target) : target_(target) {
  static std::atomic<unsigned> counter{0};
  refuseUnwritableOutput(target);
  const fs::path p(target);
  const fs::path dir = folderOf(target);
  // A file name has at most 255 bytes: a long output name is cut in its temporary twin, which only has to
  // be unique in the folder (the process id and the counter make it so).
  constexpr std::size_t kNameBytes = 160;
  const std::string name = p.filename().string();
  temp_ = (dir / ("." + name.substr(0, kNameBytes) + ".tmp" + std::to_string(::getpid()) + "_" +
                  std::to_string(counter++)))
              .string();
  // Keep the final extension so libraries that pick a format by name (nifti .gz) see the right one.
  if (p.extension() == ".gz") temp_ += ".nii.gz";
  else temp_ += p.extension().string();
}

AtomicOutput::~AtomicOutput() {
  if (!committed_) {
    std::error_code ec;
    fs::remove(temp_, ec);
  }
}

void AtomicOutput::commit() {
  refuseReplacingNonFile(target_);
  if (activeBatch) {
    activeBatch->pending_.push_back({target_, temp_});
    committed_ = true; // the batch owns the temporary file now
    return;
  }
  std::error_code ec;
  fs::rename(temp_, target_, ec);
  if (ec) throw InputError("cannot write " + target_ + ": " + ec.message());
  committed_ = true;
}

OutputBatch::OutputBatch() : outermost_(activeBatch == nullptr) {
  if (outermost_) activeBatch = this;
}

OutputBatch::~OutputBatch() {
  if (!outermost_) return;
  if (activeBatch == this) activeBatch = nullptr;
  std::error_code ec;
  for (const Pending& p : pending_)
    fs::remove(p.temp, ec);
}

void OutputBatch::commit() {
  if (!outermost_ || done_) return;
  activeBatch = nullptr; // renames below are final, not deferred again
  done_ = true;
  while (!pending_.empty()) {
    const Pending p = pending_.front();
    refuseReplacingNonFile(p.target);
    std::error_code ec;
    fs::rename(p.temp, p.target, ec);
    if (ec) throw InputError("cannot write " + p.target + ": " + ec.message());
    pending_.erase(pending_.begin());
  }
}

void refuseReplacingNonFile(const std::string& target) {
  std::error_code ec;
  if (fs::exists(target, ec) && !fs::is_regular_file(target, ec))
    throw InputError("cannot write " + target + ": it exists and is not a regular file (a folder, device or pipe): "
                     "refusing to replace it");
}

bool outputExists(const std::string& target) {
  std::error_code ec;
  return fs::exists(fs::symlink_status(target, ec));
}

void refuseOverwritingInput(const std::string& output, const std::vector<std::string>& inputs) {
  std::error_code ec;
  for (const auto& in : inputs) {
    if (in.empty()) continue;
    if (fs::exists(output, ec) && fs::exists(in, ec) && fs::equivalent(output, in, ec))
      throw InputError("refusing to write " + output + ": it is an input file");
  }
}

void refuseSameOutputs(const std::vector<std::string>& outputs) {
  std::error_code ec;
  for (std::size_t i = 0; i < outputs.size(); ++i)
    for (std::size_t j = i + 1; j < outputs.size(); ++j) {
      const std::string &a = outputs[i], &b = outputs[j];
      if (a.empty() || b.empty()) continue;
      bool same = fs::exists(a, ec) && fs::exists(b, ec) && fs::equivalent(a, b, ec);
      if (!same) {
        const fs::path pa = fs::weakly_canonical(fs::absolute(a, ec), ec);
        const fs::path pb = fs::weakly_canonical(fs::absolute(b, ec), ec);
        same = !pa.empty() && pa == pb;
      }
      if (same) throw UsageError("two outputs are the same file: " + a + " and " + b);
    }
}

} // namespace dtf::io
