// SPDX-License-Identifier: GPL-3.0-or-later
#include "io/formats/movie_writer.h"

#include "io/formats/atomic_file.h"

#include "io/formats/png_io.h"
#include "io/formats/process.h"
#include "io/model/error.h"

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

namespace fs = std::filesystem;

namespace dtf::io {

namespace {

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string stripSlash(std::string s) {
  while (s.size() > 1 && s.back() == '/') s.pop_back();
  return s;
}

// A temporary sibling of `target`: DIR/.NAME.tmpPID_N plus `suffix`.
std::string tempSibling(const std::string& target, const std::string& suffix) {
  static std::atomic<unsigned> counter{0};
  const fs::path p(target);
  const fs::path dir = p.has_parent_path() ? p.parent_path() : fs::path(".");
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw InputError("cannot write " + target + ": directory does not exist");
  if (::access(dir.c_str(), W_OK) != 0) throw InputError("cannot write " + target + ": directory not writable");
  return (dir / ("." + p.filename().string() + ".tmp" + std::to_string(::getpid()) + "_" +
                 std::to_string(counter++) + suffix))
      .string();
}

std::string fileTail(const std::string& path, std::size_t n) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  std::string s = ss.str();
  while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
  return s.size() > n ? "..." + s.substr(s.size() - n) : s;
}

// SIGPIPE is ignored while a writer lives, so a dying ffmpeg gives EPIPE instead of ending the process.
struct SigpipeIgnored {
  struct sigaction old {};
  SigpipeIgnored() {
    struct sigaction ign {};
    ign.sa_handler = SIG_IGN;
    sigemptyset(&ign.sa_mask);
    sigaction(SIGPIPE, &ign, &old);
  }
  ~SigpipeIgnored() { sigaction(SIGPIPE, &old, nullptr); }
};

} // namespace

MovieFormat movieFormatOf(const std::string& output) {
  std::error_code ec;
  if (!output.empty() && (output.back() == '/' || fs::is_directory(output, ec))) return MovieFormat::PngFrames;
  const std::string ext = lower(fs::path(output).extension().string());
  if (ext == ".mp4") return MovieFormat::Mp4;
  if (ext == ".gif") return MovieFormat::Gif;
  throw UsageError("the movie output " + output +
                   " must end in .mp4 (H.264), .gif, or / (a directory of numbered PNG frames)");
}

const char* movieFormatName(MovieFormat f) {
  switch (f) {
  case MovieFormat::Mp4: return "MP4";
  case MovieFormat::Gif: return "GIF";
  case MovieFormat::PngFrames: return "PNG frames";
  }
  return "";
}

void refuseMovieOverInputs(const std::string& output, const std::vector<std::string>& inputs) {
  const std::string target = stripSlash(output);
  std::error_code ec;
  if (!fs::exists(target, ec)) return;
  const fs::path out = fs::canonical(target, ec);
  if (ec) return;
  for (const auto& in : inputs) {
    if (in.empty() || !fs::exists(in, ec)) continue;
    const fs::path p = fs::canonical(in, ec);
    if (ec) continue;
    const auto rel = p.lexically_relative(out);
    if (p == out || (!rel.empty() && *rel.begin() != ".."))
      throw InputError("refusing to write " + output + ": it is or holds the input " + in);
  }
}

// An existing output is replaced only with --force, and then only what a movie writes: a folder holding
// nothing but frame_NNNN.png (or nothing), or a regular file.
static void refuseReplacing(const std::string& target, MovieFormat format, bool force) {
  std::error_code ec;
  if (!outputExists(target)) return;
  if (!force) throw InputError(target + " exists (use --force to overwrite it)");
  if (format != MovieFormat::PngFrames) {
    refuseReplacingNonFile(target);
    return;
  }
  if (!fs::is_directory(target, ec)) throw InputError(target + " exists and is not a folder: refusing to replace it");
  for (const auto& e : fs::directory_iterator(target, ec)) {
    const std::string name = e.path().filename().string();
    const bool frame = e.is_regular_file(ec) && name.size() == 14 && name.rfind("frame_", 0) == 0 &&
                       name.compare(10, 4, ".png") == 0 &&
                       std::all_of(name.begin() + 6, name.begin() + 10, [](char c) { return c >= '0' && c <= '9'; });
    if (!frame)
      throw InputError(target + " exists and holds " + name +
                       ", not only the frame_NNNN.png a movie writes: refusing to replace it");
  }
}

MovieWriter::MovieWriter(const std::string& output, int width, int height, double fps, bool force)
    : output_(output), target_(stripSlash(output)), format_(movieFormatOf(output)), width_(width),
      height_(height) {
  if (width < 2 || height < 2) throw UsageError("a movie frame must be at least 2x2 pixels");
  if (!(fps > 0 && fps <= 240)) throw UsageError("the frame rate must be in (0, 240] frames per second");
  if (format_ == MovieFormat::Mp4 && (width % 2 || height % 2))
    throw UsageError("an MP4 (H.264, yuv420p) needs an even width and height, not " + std::to_string(width) +
                     "x" + std::to_string(height));
  std::string ffmpeg;
  if (format_ != MovieFormat::PngFrames) {
    ffmpeg = findOnPath("ffmpeg");
    if (ffmpeg.empty())
      throw InputError(std::string("cannot write ") + output + ": the ffmpeg program is not on PATH (" +
                       movieFormatName(format_) +
                       " movies are encoded by it; install ffmpeg, or write numbered PNG frames with -o DIR/)");
  }
  std::error_code ec;
  refuseReplacing(target_, format_, force);
  if (format_ == MovieFormat::PngFrames) {
    temp_ = tempSibling(target_, "");
    if (!fs::create_directory(temp_, ec) || ec)
      throw InputError("cannot write " + output + ": cannot create " + temp_);
    return;
  }
  temp_ = tempSibling(target_, format_ == MovieFormat::Mp4 ? ".mp4" : ".gif");
  log_ = temp_ + ".log";
  const std::string size = std::to_string(width) + "x" + std::to_string(height);
  char rate[32];
  std::snprintf(rate, sizeof rate, "%g", fps);
  std::vector<std::string> args = {ffmpeg, "-hide_banner", "-loglevel", "error", "-y", "-f", "rawvideo",
                                   "-pix_fmt", "rgb24", "-s", size, "-framerate", rate, "-i", "pipe:0", "-an"};
  if (format_ == MovieFormat::Mp4) {
    for (const char* a : {"-c:v", "libx264", "-preset", "medium", "-crf", "18", "-pix_fmt", "yuv420p", "-movflags",
                          "+faststart", "-f", "mp4"})
      args.emplace_back(a);
  } else {
    // One palette for the whole movie (coherent frames share their colours), ordered dithering.
    for (const char* a : {"-filter_complex", "[0:v]split[a][b];[a]palettegen=stats_mode=full[p];[b][p]paletteuse="
                                             "dither=bayer:bayer_scale=3",
                          "-loop", "0", "-f", "gif"})
      args.emplace_back(a);
  }
  args.push_back(temp_);

  int fds[2];
  if (::pipe(fds) != 0) throw InputError("cannot write " + output + ": pipe: " + std::strerror(errno));
  const int logFd = ::open(log_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
  if (logFd < 0) {
    ::close(fds[0]);
    ::close(fds[1]);
    throw InputError("cannot write " + output + ": cannot create " + log_);
  }
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::dup2(fds[0], 0);
    ::dup2(logFd, 2);
    const int devnull = ::open("/dev/null", O_WRONLY);
    if (devnull >= 0) ::dup2(devnull, 1);
    ::close(fds[0]);
    ::close(fds[1]);
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  ::close(fds[0]);
  ::close(logFd);
  if (pid < 0) {
    ::close(fds[1]);
    fs::remove(log_, ec);
    throw InputError("cannot write " + output + ": cannot start ffmpeg: " + std::strerror(errno));
  }
  ::fcntl(fds[1], F_SETFD, FD_CLOEXEC);
  pid_ = pid;
  pipe_ = fds[1];
  rgb_.resize(static_cast<std::size_t>(width) * height * 3);
}

MovieWriter::~MovieWriter() {
  if (!done_) abort();
}

void MovieWriter::abort() {
  done_ = true;
  if (pipe_ >= 0) ::close(pipe_);
  pipe_ = -1;
  if (pid_ > 0) {
    ::kill(pid_, SIGTERM);
    int status = 0;
    ::waitpid(pid_, &status, 0);
    pid_ = -1;
  }
  std::error_code ec;
  if (!temp_.empty()) fs::remove_all(temp_, ec);
  if (!log_.empty()) fs::remove(log_, ec);
}

void MovieWriter::add(const Image& frame) {
  if (done_) throw InputError("cannot write " + output_ + ": the movie is already finished");
  if (frame.width != width_ || frame.height != height_)
    throw InputError("cannot write " + output_ + ": a frame of " + std::to_string(frame.width) + "x" +
                     std::to_string(frame.height) + " in a " + std::to_string(width_) + "x" +
                     std::to_string(height_) + " movie");
  if (format_ == MovieFormat::PngFrames) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%04d.png", frames_);
    writePng((fs::path(temp_) / name).string(), frame);
    ++frames_;
    return;
  }
  const std::size_t n = static_cast<std::size_t>(width_) * height_;
  for (std::size_t i = 0; i < n; ++i) {
    rgb_[i * 3 + 0] = frame.rgba[i * 4 + 0];
    rgb_[i * 3 + 1] = frame.rgba[i * 4 + 1];
    rgb_[i * 3 + 2] = frame.rgba[i * 4 + 2];
  }
  const SigpipeIgnored quiet;
  const std::uint8_t* p = rgb_.data();
  std::size_t left = rgb_.size();
  while (left > 0) {
    const ssize_t w = ::write(pipe_, p, left);
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0) {
      const std::string why = fileTail(log_, 600);
      abort();
      throw InputError("cannot write " + output_ + ": ffmpeg stopped reading frames" +
                       (why.empty() ? std::string() : ": " + why));
    }
    p += w;
    left -= static_cast<std::size_t>(w);
  }
  ++frames_;
}

void MovieWriter::finish() {
  if (done_) throw InputError("cannot write " + output_ + ": the movie is already finished");
  if (frames_ == 0) {
    abort();
    throw InputError("cannot write " + output_ + ": no frames");
  }
  std::error_code ec;
  if (format_ != MovieFormat::PngFrames) {
    ::close(pipe_);
    pipe_ = -1;
    int status = 0;
    while (::waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
    }
    pid_ = -1;
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
      const std::string why = fileTail(log_, 600);
      abort();
      throw InputError("cannot write " + output_ + ": ffmpeg failed" + (why.empty() ? std::string() : ": " + why));
    }
    fs::remove(log_, ec);
    fs::rename(temp_, target_, ec);
    if (ec) {
      abort();
      throw InputError("cannot write " + target_ + ": " + ec.message());
    }
    done_ = true;
    return;
  }
  // A directory: the old one (with --force) is moved aside, the new one renamed in, then the old removed.
  std::string old;
  if (fs::exists(target_, ec)) {
    old = tempSibling(target_, ".old");
    fs::rename(target_, old, ec);
    if (ec) {
      abort();
      throw InputError("cannot replace " + target_ + ": " + ec.message());
    }
  }
  fs::rename(temp_, target_, ec);
  if (ec) {
    const std::string why = ec.message();
    if (!old.empty()) fs::rename(old, target_, ec);
    abort();
    throw InputError("cannot write " + target_ + ": " + why);
  }
  if (!old.empty()) fs::remove_all(old, ec);
  done_ = true;
}

} // namespace dtf::io
