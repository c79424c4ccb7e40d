// SPDX-License-Identifier: GPL-3.0-or-later
// Fuzz-target helper: the readers take file names, so each input is written to a per-process scratch file
// (in /dev/shm when there is one) with the extension the reader dispatches on.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>
#include <unistd.h>

namespace dtf::fuzz {

inline std::string scratchPath(const std::string& stem, const std::string& ext) {
  const std::filesystem::path dir = std::filesystem::is_directory("/dev/shm") ? "/dev/shm" : "/tmp";
  return (dir / ("dtf_fuzz_" + std::to_string(::getpid()) + "_" + stem + ext)).string();
}

// A per-process scratch folder (created once) for targets that write more than one file.
inline std::filesystem::path scratchDir(const std::string& stem) {
  const std::filesystem::path dir = std::filesystem::is_directory("/dev/shm") ? "/dev/shm" : "/tmp";
  const std::filesystem::path d = dir / ("dtf_fuzz_" + std::to_string(::getpid()) + "_" + stem);
  std::filesystem::create_directories(d);
  return d;
}

// Empties `dir` (the files of the previous input), keeping the folder.
inline void clearDir(const std::filesystem::path& dir) {
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator(dir, ec))
    std::filesystem::remove_all(e.path(), ec);
}

inline void writeInput(const std::string& path, const std::uint8_t* data, std::size_t size) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) std::abort();
  if (size && std::fwrite(data, 1, size, f) != size) std::abort();
  std::fclose(f);
}

} // namespace dtf::fuzz
