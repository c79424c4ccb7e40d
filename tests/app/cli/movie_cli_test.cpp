// SPDX-License-Identifier: GPL-3.0-or-later
// `dtfabric movie` end to end: frame counts of PNG directories and of MP4/GIF files (decoded by ffprobe), the
// frame size, atomic output (nothing left behind, nothing overwritten without --force, never an input), the
// error without ffmpeg on PATH, and usage errors.
#include "support/cli.h"
#include "support/gl_test.h"

#include "io/formats/png_io.h"

#include <fstream>
#include <iterator>

namespace fs = std::filesystem;

namespace {

using dtf::test::CliRun;

fs::path logFor() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  return dtf::test::binaryDir() / "test_scratch" / (std::string("movie_cli_") + info->name() + ".log");
}

CliRun dtfabric(const std::string& args) {
  return dtf::test::runDtfabricCombined(args, logFor());
}

// The executable with PATH set to `path` only.
CliRun dtfabricWithPath(const std::string& args, const fs::path& path) {
  const fs::path log = logFor();
  const std::string cmd = "/usr/bin/env PATH='" + path.string() + "' '" + DTF_EXE + "' " + args + " > '" +
                          log.string() + "' 2>&1";
  const int status = std::system(cmd.c_str());
  CliRun r;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.output = dtf::test::readText(log);
  return r;
}

std::string bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

const fs::path kPhantom = dtf::test::sourceDir() / "sample_data" / "brain_phantom.nii.gz";

// Entries of `dir` (names).
std::vector<std::string> entries(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

// ffprobe's decoded frame count, size and pixel format of the first video stream ("" on failure).
std::string probe(const fs::path& movie) {
  const fs::path out = movie.string() + ".probe";
  const std::string cmd = "ffprobe -v error -select_streams v:0 -count_frames -show_entries "
                          "stream=codec_name,width,height,pix_fmt,nb_read_frames -of "
                          "default=noprint_wrappers=1 '" +
                          movie.string() + "' > '" + out.string() + "' 2>&1";
  if (std::system(cmd.c_str()) != 0) return "";
  return dtf::test::readText(out);
}

std::string entry(const std::string& probeText, const std::string& key) {
  const auto at = probeText.find(key + "=");
  if (at == std::string::npos) return "";
  const auto end = probeText.find('\n', at);
  return probeText.substr(at + key.size() + 1, end - at - key.size() - 1);
}

bool haveFfmpeg() {
  return std::system("command -v ffmpeg > /dev/null && command -v ffprobe > /dev/null") == 0;
}

} // namespace

TEST(MovieCli, PngFramesOfATurntable) {
  DTF_GL_TEST_SETUP();
  const fs::path dir = dtf::test::scratchDir();
  const fs::path frames = dir / "frames";
  CliRun r = dtfabric("movie " + kPhantom.string() + " --turntable --frames 6 --size 96x80 -o " + frames.string() + "/");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("frame 6/6"), std::string::npos) << r.output; // progress on stderr
  const auto names = entries(frames);
  ASSERT_EQ(names.size(), 6u);
  for (int i = 0; i < 6; ++i) {
    char expect[32];
    std::snprintf(expect, sizeof expect, "frame_%04d.png", i);
    EXPECT_EQ(names[std::size_t(i)], expect);
    const dtf::Image img = dtf::io::readPng((frames / expect).string());
    EXPECT_EQ(img.width, 96);
    EXPECT_EQ(img.height, 80);
    std::size_t lit = 0;
    for (std::size_t p = 0; p < img.rgba.size(); p += 4) lit += (img.rgba[p] | img.rgba[p + 1] | img.rgba[p + 2]) != 0;
    EXPECT_GT(lit, std::size_t(96 * 80 / 20)) << expect;
  }
  // Only the output is left beside it (no temporary directory).
  EXPECT_EQ(entries(dir), std::vector<std::string>{"frames"});
}

// Movie frames carry the figure's furniture as a still does: a turntable seen from the front has S at the top
// edge's middle and I at the bottom's (white letters there), and --no-letters leaves the band without them.
TEST(MovieCli, FramesCarryTheOrientationLetters) {
  DTF_GL_TEST_SETUP();
  const fs::path dir = dtf::test::scratchDir();
  auto whiteAtTopMiddle = [](const dtf::Image& img) {
    std::size_t n = 0;
    for (int y = 0; y < img.height / 10; ++y)
      for (int x = img.width * 2 / 5; x < img.width * 3 / 5; ++x) {
        const std::uint8_t* p = img.pixel(x, y);
        n += p[0] > 230 && p[1] > 230 && p[2] > 230;
      }
    return n;
  };
  for (const bool letters : {true, false}) {
    const fs::path frames = dir / (letters ? "with" : "without");
    const CliRun r = dtfabric("movie " + kPhantom.string() + " --turntable --frames 2 --size 256x256" +
                              (letters ? "" : " --no-letters") + " -o " + frames.string() + "/");
    ASSERT_EQ(r.code, 0) << r.output;
    const dtf::Image img = dtf::io::readPng((frames / "frame_0000.png").string());
    if (letters)
      EXPECT_GT(whiteAtTopMiddle(img), 20u) << "no letter S at the top";
    else
      EXPECT_EQ(whiteAtTopMiddle(img), 0u);
  }
}

TEST(MovieCli, Mp4AndGifDecodeToTheFrameCount) {
  DTF_GL_TEST_SETUP();
  if (!haveFfmpeg()) {
    if (dtf::test::envFlag("DTF_REQUIRE_GL"))
      FAIL() << "ffmpeg/ffprobe not on PATH (.ci/setup installs ffmpeg)";
    GTEST_SKIP() << "ffmpeg not installed";
  }
  const fs::path dir = dtf::test::scratchDir();
  CliRun r = dtfabric("movie " + kPhantom.string() + " --sweep axial --frames 7 --size 96x64 --fps 10 -o " +
                      (dir / "sweep.mp4").string());
  ASSERT_EQ(r.code, 0) << r.output;
  const std::string mp4 = probe(dir / "sweep.mp4");
  EXPECT_EQ(entry(mp4, "codec_name"), "h264") << mp4;
  EXPECT_EQ(entry(mp4, "pix_fmt"), "yuv420p") << mp4;
  EXPECT_EQ(entry(mp4, "width"), "96");
  EXPECT_EQ(entry(mp4, "height"), "64");
  EXPECT_EQ(entry(mp4, "nb_read_frames"), "7") << mp4;

  r = dtfabric("movie " + kPhantom.string() + " --fa-sweep 0.2:0.4 --frames 5 --size 80x60 -o " +
               (dir / "fa.gif").string());
  ASSERT_EQ(r.code, 0) << r.output;
  const std::string gif = probe(dir / "fa.gif");
  EXPECT_EQ(entry(gif, "codec_name"), "gif") << gif;
  EXPECT_EQ(entry(gif, "width"), "80");
  EXPECT_EQ(entry(gif, "nb_read_frames"), "5") << gif;
  // Nothing but the two movies (and the probes' text) is left in the directory.
  for (const auto& n : entries(dir)) EXPECT_TRUE(n == "sweep.mp4" || n == "fa.gif" || n.find(".probe") != std::string::npos) << n;
}

TEST(MovieCli, NeverOverwritesWithoutForceAndNeverAnInput) {
  DTF_GL_TEST_SETUP();
  const fs::path dir = dtf::test::scratchDir();
  const fs::path frames = dir / "frames";
  fs::create_directories(frames);
  { std::ofstream(frames / "keep.txt") << "mine"; }
  const std::string common = kPhantom.string() + " --turntable --frames 2 --size 64x64 ";
  CliRun r = dtfabric("movie " + common + "-o " + frames.string() + "/");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("--force"), std::string::npos) << r.output;
  EXPECT_EQ(entries(frames), std::vector<std::string>{"keep.txt"});
  // --force replaces a folder of frames only: one holding anything else is refused and kept.
  r = dtfabric("movie " + common + "--force -o " + frames.string() + "/");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("keep.txt, not only the frame_NNNN.png"), std::string::npos) << r.output;
  EXPECT_EQ(entries(frames), std::vector<std::string>{"keep.txt"});
  fs::remove(frames / "keep.txt");
  r = dtfabric("movie " + common + "-o " + frames.string() + "/"); // an empty folder needs --force too
  EXPECT_EQ(r.code, 2) << r.output;
  r = dtfabric("movie " + common + "--force -o " + frames.string() + "/");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_EQ(entries(frames), (std::vector<std::string>{"frame_0000.png", "frame_0001.png"}));

  // An input is never the output, nor inside a directory output, even with --force.
  const fs::path input = dir / "in" / "brain.nii.gz";
  fs::create_directories(input.parent_path());
  fs::copy_file(kPhantom, input);
  const std::string before = bytes(input);
  r = dtfabric("movie " + input.string() + " --turntable --frames 2 --size 64x64 --force -o " +
               input.parent_path().string() + "/");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_EQ(bytes(input), before);
  const fs::path gifInput = dir / "in.gif";
  fs::copy_file(kPhantom, gifInput);
  r = dtfabric("movie " + gifInput.string() + " --turntable --frames 2 --size 64x64 --force -o " + gifInput.string());
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_EQ(bytes(gifInput), before);

  // A failed movie (unreadable input) leaves nothing behind.
  const fs::path bad = dir / "bad.nii.gz";
  { std::ofstream(bad) << "not a volume"; }
  r = dtfabric("movie " + bad.string() + " --turntable --frames 2 --size 64x64 -o " + (dir / "bad_frames").string() + "/");
  EXPECT_EQ(r.code, 2) << r.output;
  for (const auto& n : entries(dir)) EXPECT_EQ(n.find(".tmp"), std::string::npos) << n;
  EXPECT_FALSE(fs::exists(dir / "bad_frames"));
}

TEST(MovieCli, WithoutFfmpegOnPathMp4IsRefusedAndPngWorks) {
  DTF_GL_TEST_SETUP();
  const fs::path dir = dtf::test::scratchDir();
  const fs::path noFfmpeg = dir / "empty_path";
  fs::create_directories(noFfmpeg);
  CliRun r = dtfabricWithPath("movie " + kPhantom.string() + " --turntable --frames 3 --size 64x64 -o " +
                          (dir / "a.mp4").string(),
                      noFfmpeg);
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("ffmpeg"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("PATH"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("frame 1/"), std::string::npos) << "refused before rendering:\n" << r.output;
  EXPECT_FALSE(fs::exists(dir / "a.mp4"));
  r = dtfabricWithPath(
      "movie " + kPhantom.string() + " --turntable --frames 3 --size 64x64 -o " + (dir / "a.gif").string(), noFfmpeg);
  EXPECT_EQ(r.code, 2) << r.output;
  r = dtfabricWithPath(
      "movie " + kPhantom.string() + " --turntable --frames 3 --size 64x64 -o " + (dir / "png").string() + "/",
      noFfmpeg);
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_EQ(entries(dir / "png").size(), 3u);
}

TEST(MovieCli, UsageErrors) {
  const fs::path dir = dtf::test::scratchDir();
  const std::string in = kPhantom.string() + " ";
  const std::string out = " -o " + (dir / "m.mp4").string();
  EXPECT_EQ(dtfabric("movie " + in + "--frames 3" + out).code, 1);                           // no motion
  EXPECT_EQ(dtfabric("movie " + in + "--turntable --sweep axial" + out).code, 1);            // two motions
  EXPECT_EQ(dtfabric("movie " + in + "--sweep diagonal" + out).code, 1);                     // bad axis
  EXPECT_EQ(dtfabric("movie " + in + "--fa-sweep 0.3" + out).code, 1);                       // not LO:HI
  EXPECT_EQ(dtfabric("movie " + in + "--fa-sweep 0.3:1.5" + out).code, 1);                  // out of (0, 1)
  EXPECT_EQ(dtfabric("movie " + in + "--turntable --size 101x64" + out).code, 1);            // odd for H.264
  EXPECT_EQ(dtfabric("movie " + in + "--turntable --frames 0" + out).code, 1);               // range
  EXPECT_EQ(dtfabric("movie " + in + "--turntable -o " + (dir / "m.avi").string()).code, 1); // format
  EXPECT_FALSE(fs::exists(dir / "m.mp4"));
  CliRun help = dtfabric("movie --help");
  EXPECT_EQ(help.code, 0);
  EXPECT_NE(help.output.find("--fa-sweep LO:HI"), std::string::npos) << help.output;
  EXPECT_NE(help.output.find("ffmpeg"), std::string::npos);
}
