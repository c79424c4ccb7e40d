// SPDX-License-Identifier: GPL-3.0-or-later
// Movies written frame by frame: H.264 MP4 (yuv420p) or GIF through the `ffmpeg` program found on PATH at
// run time (raw RGB frames piped to its standard input), or numbered PNG frames into a directory. The output
// appears only when finish() succeeds: a file is written to a temporary sibling and renamed into place, a
// directory is filled under a temporary name and renamed; an interrupted or failed movie leaves nothing.
#pragma once

#include "io/model/image.h"

#include <cstdint>
#include <string>
#include <vector>

namespace dtf::io {

enum class MovieFormat { Mp4, Gif, PngFrames };

// By name: a trailing '/' or an existing directory is PngFrames, then .mp4 or .gif (any case). Throws
// UsageError for anything else.
MovieFormat movieFormatOf(const std::string& output);
const char* movieFormatName(MovieFormat format); // "MP4", "GIF", "PNG frames"

// Throws InputError when writing `output` (a file, or a directory replaced as a whole) would overwrite or
// remove one of `inputs`.
void refuseMovieOverInputs(const std::string& output, const std::vector<std::string>& inputs);

class MovieWriter {
public:
  // Checks everything before any frame is rendered: the format, the size (even for MP4), ffmpeg on PATH for
  // MP4 and GIF (InputError naming what to install otherwise), an existing output (InputError unless
  // `force`), the output's directory; then starts ffmpeg. fps in (0, 240].
  MovieWriter(const std::string& output, int width, int height, double fps, bool force);
  ~MovieWriter(); // without finish(): stops ffmpeg and removes everything written
  MovieWriter(const MovieWriter&) = delete;
  MovieWriter& operator=(const MovieWriter&) = delete;

  // One frame of the size given (InputError on a write failure, e.g. ffmpeg exited).
  void add(const Image& frame);
  // Closes the stream, waits for ffmpeg and renames the output into place. Throws InputError (with
  // ffmpeg's message) on failure.
  void finish();

  MovieFormat format() const { return format_; }
  int frames() const { return frames_; }
  const std::string& output() const { return output_; }

private:
  void abort();
  std::string output_, target_, temp_, log_;
  MovieFormat format_;
  int width_, height_, frames_ = 0;
  int pipe_ = -1;
  int pid_ = -1;
  bool done_ = false;
  std::vector<std::uint8_t> rgb_; // one frame, reused
};

} // namespace dtf::io
