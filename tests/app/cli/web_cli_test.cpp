// SPDX-License-Identifier: GPL-3.0-or-later
// `dtfabric web`: the folder written from a small LAS input with data on one side only (so a mirrored or
// shifted image is caught), its per-voxel table against the tensors, the exported pixel -> world mapping
// against the rendered images, refusals; then the page in headless Chromium from file:// (no console error,
// no request outside the folder, the fabric drawn, a slider change shows another slice, the probe's world
// and voxel agree with the affine).
#include "io/model/tensor.h"
#include "io/phantoms.h"
#include "io/formats/png_io.h"
#include "io/formats/tensor_io.h"
#include "support/chromium.h"
#include "support/cli.h"
#include "support/test_env.h"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <set>

namespace {

namespace fs = std::filesystem;
using namespace dtf;
using nlohmann::json;
using test::readText;
using test::runDtfabric;
using test::shellQuoted;

// The JSON object a page script assigns: "window.NAME = {...};".
json assignedJson(const fs::path& js) {
  std::string text = readText(js);
  const auto eq = text.find('=');
  const auto end = text.rfind(';');
  return json::parse(text.substr(eq + 1, end - eq - 1));
}

std::vector<std::uint8_t> base64Decode(const std::string& s) {
  std::vector<std::uint8_t> out;
  unsigned w = 0;
  int bits = 0;
  for (char c : s) {
    int v = c >= 'A' && c <= 'Z'   ? c - 'A'
            : c >= 'a' && c <= 'z' ? c - 'a' + 26
            : c >= '0' && c <= '9' ? c - '0' + 52
            : c == '+'             ? 62
            : c == '/'             ? 63
                                   : -1;
    if (v < 0) continue;
    w = (w << 6) | static_cast<unsigned>(v);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(static_cast<std::uint8_t>((w >> bits) & 255));
    }
  }
  return out;
}

// The network requests a page opened from file:// made, from Chromium's net log: URL requests started on
// behalf of a file:// frame (the browser's own background requests carry another isolation key) for anything
// but a file: URL.
std::vector<std::string> pageNetworkRequests(const fs::path& netLog) {
  const json log = json::parse(readText(netLog));
  const int start = log["constants"]["logEventTypes"]["URL_REQUEST_START_JOB"];
  std::vector<std::string> out;
  for (const auto& e : log["events"]) {
    if (e["type"] != start || !e.contains("params")) continue;
    const json& p = e["params"];
    if (!p.contains("url") || !p.contains("network_isolation_key")) continue;
    const std::string url = p["url"], key = p["network_isolation_key"];
    if (key.find("file://") != std::string::npos && url.rfind("file:", 0) != 0) out.push_back(url);
  }
  return out;
}

glm::dvec3 vec3(const json& j) {
  return {j[0].get<double>(), j[1].get<double>(), j[2].get<double>()};
}

class WebPage : public ::testing::Test {
protected:
  void SetUp() override {
    scratch_ = test::scratchDir();
    // The brain phantom on an LAS grid, its data kept only where world x > -4 mm (the patient's right and a
    // little beyond the midline): the slices are not mirror-symmetric.
    io::PhantomOptions o;
    o.size = 32;
    o.las = true;
    field_ = io::makePhantom("brain", o).tensors;
    for (int k = 0; k < 32; ++k)
      for (int j = 0; j < 32; ++j)
        for (int i = 0; i < 32; ++i)
          if (field_.grid.toWorld(glm::dvec3(i, j, k)).x < -4.0) {
            field_.valid[field_.grid.index(i, j, k)] = 0;
            field_.at(i, j, k) = SymTensor{};
          }
    input_ = scratch_ / "half_brain.nii.gz";
    io::writeTensorVolume(input_.string(), field_, io::TensorLayout::Mrtrix);
    field_ = io::readTensorVolume(input_.string()).field; // as the command sees it (float32)
  }

  fs::path scratch_, input_;
  TensorField field_;
};

TEST_F(WebPage, WritesTheFolderWithTableAndMappingThatMatchTheImages) {
  const fs::path page = scratch_ / "page";
  auto r = runDtfabric("web " + shellQuoted(input_) + " -o " + shellQuoted(page) + " --size 128", scratch_);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.err.find("web: axial"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("web: sagittal"), std::string::npos) << r.err;
  EXPECT_NE(r.out.find("/index.html"), std::string::npos) << r.out;
  for (const char* f : {"index.html", "viewer.js", "data.js", "voxels.js"})
    EXPECT_TRUE(fs::exists(page / f)) << f;
  // Nothing is left beside it.
  for (const auto& e : fs::directory_iterator(scratch_))
    EXPECT_EQ(e.path().filename().string().find(".page"), std::string::npos) << e.path();
  // No reference outside the folder in the page's own text.
  for (const char* f : {"index.html", "viewer.js"}) {
    const std::string text = readText(page / f);
    EXPECT_EQ(text.find("http://"), std::string::npos) << f;
    EXPECT_EQ(text.find("https://"), std::string::npos) << f;
  }

  const json d = assignedJson(page / "data.js");
  const Grid& g = field_.grid;
  ASSERT_EQ(d["dims"], json({32, 32, 32}));
  for (int row = 0; row < 4; ++row)
    for (int c = 0; c < 4; ++c)
      EXPECT_NEAR(d["affine"][row][c].get<double>(), g.voxelToWorld[c][row], 1e-9);
  EXPECT_EQ(d["orientation"], "LAS");

  // The table: FA and principal direction of every voxel.
  const std::string vtext = readText(page / "voxels.js");
  const auto table = base64Decode(vtext.substr(vtext.find('"') + 1));
  ASSERT_EQ(table.size(), g.voxelCount() * 4);
  std::size_t valid = 0;
  for (std::size_t i = 0; i < g.voxelCount(); ++i) {
    if (!field_.valid[i]) {
      ASSERT_EQ(table[i * 4], 0) << i;
      continue;
    }
    ++valid;
    const EigenSystem e = eigenDecompose(field_.tensors[i]);
    ASSERT_NEAR((table[i * 4] - 1) / 254.0, fractionalAnisotropy(e.values), 0.5 / 254 + 1e-6) << i;
    const glm::dvec3 v((table[i * 4 + 1] - 128) / 127.0, (table[i * 4 + 2] - 128) / 127.0,
                       (table[i * 4 + 3] - 128) / 127.0);
    if (fractionalAnisotropy(e.values) > 0.3) {
      ASSERT_GT(std::abs(glm::dot(glm::normalize(v), e.vectors[0])), 0.99) << i;
    }
  }
  ASSERT_GT(valid, 1000u);

  // Each axis: the slices holding data, radiological framing, and the mapping pixel -> voxel against the
  // rendered image's coverage (alpha) on the middle slice.
  const char* names[3] = {"axial", "coronal", "sagittal"};
  const glm::dvec3 rights[3] = {{-1, 0, 0}, {-1, 0, 0}, {0, -1, 0}}; // patient's right / anterior on the left
  std::size_t pngs = 0;
  for (int a = 0; a < 3; ++a) {
    const json& ax = d["axes"][a];
    SCOPED_TRACE(names[a]);
    EXPECT_EQ(ax["name"], names[a]);
    const int k = ax["voxelAxis"];
    std::set<int> expected;
    for (int kk = 0; kk < 32; ++kk)
      for (int j = 0; j < 32; ++j)
        for (int i = 0; i < 32; ++i)
          if (field_.valid[g.index(i, j, kk)]) expected.insert(glm::ivec3(i, j, kk)[k]);
    const std::vector<int> slices = ax["slices"];
    EXPECT_LE(slices.size(), expected.size());
    EXPECT_GE(slices.size() + 2, expected.size());
    pngs += slices.size();
    EXPECT_LT(glm::length(vec3(ax["right"]) - rights[a]), 1e-9);
    const int w = ax["width"], h = ax["height"];
    EXPECT_EQ(std::max(w, h), 128);
    const int s = slices[slices.size() / 2];
    char file[64];
    std::snprintf(file, sizeof file, "%s%03d.png", ax["image"].get<std::string>().c_str(), s);
    const Image img = io::readPng((page / file).string());
    ASSERT_EQ(img.width, w);
    ASSERT_EQ(img.height, h);
    const glm::dvec3 centre = vec3(ax["centre"]), right = vec3(ax["right"]), up = vec3(ax["up"]),
                     forward = vec3(ax["forward"]);
    const double mm = ax["mmPerPixel"];
    int inside = 0, insideCovered = 0, outside = 0, outsideCovered = 0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const glm::dvec3 p = centre + right * ((x + 0.5 - w / 2.0) * mm) + up * ((h / 2.0 - y - 0.5) * mm);
        const glm::dvec3 v0 = g.toVoxel(p), v1 = g.toVoxel(p + forward);
        const glm::dvec3 v = v0 + (v1 - v0) * ((s - v0[k]) / (v1[k] - v0[k]));
        // Anisotropic data all around (the render's anatomy look draws the fabric where FA is high, FA's grey
        // beneath elsewhere: black where FA is 0) or no data near.
        bool all = true, none = true;
        for (int du = -1; du <= 1; ++du)
          for (int dv = -1; dv <= 1; ++dv) {
            glm::ivec3 q = glm::ivec3(glm::round(v));
            q[(k + 1) % 3] += du;
            q[(k + 2) % 3] += dv;
            const bool in = g.contains(q.x, q.y, q.z) && field_.valid[g.index(q.x, q.y, q.z)];
            all = all && in && fractionalAnisotropy(field_.tensors[g.index(q.x, q.y, q.z)]) > 0.35;
            none = none && !in;
          }
        const std::uint8_t* px = img.pixel(x, y); // the background is opaque black
        const bool covered = (px[0] | px[1] | px[2]) != 0;
        if (all) ++inside, insideCovered += covered;
        if (none) ++outside, outsideCovered += covered;
      }
    std::printf("%s slice %d: %d pixels inside anisotropic data (%d drawn), %d outside (%d drawn)\n", names[a],
                s, inside, insideCovered, outside, outsideCovered);
    EXPECT_GT(inside, w * h / 200);
    EXPECT_GT(outside, w * h / 20);
    EXPECT_GE(insideCovered, inside * 0.97);
    EXPECT_LE(outsideCovered, outside * 0.01);
  }
  std::size_t files = 0;
  for (const auto& e : fs::directory_iterator(page / "slices"))
    files += e.path().extension() == ".png";
  EXPECT_EQ(files, pngs);

  // Refusals: an existing folder without --force (untouched), a folder holding the input, a bad size.
  const auto before = fs::last_write_time(page / "data.js");
  r = runDtfabric("web " + shellQuoted(input_) + " -o " + shellQuoted(page), scratch_);
  EXPECT_EQ(r.exitCode, 2) << r.err;
  EXPECT_NE(r.err.find("exists (use --force"), std::string::npos) << r.err;
  EXPECT_EQ(fs::last_write_time(page / "data.js"), before);
  r = runDtfabric("web " + shellQuoted(input_) + " -o " + shellQuoted(scratch_) + " --force", scratch_);
  EXPECT_EQ(r.exitCode, 1) << r.err;
  EXPECT_NE(r.err.find("holds the input"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::exists(input_));
  r = runDtfabric("web " + shellQuoted(input_) + " -o " + shellQuoted(page) + " --size 8", scratch_);
  EXPECT_EQ(r.exitCode, 1) << r.err;
  r = runDtfabric("web " + shellQuoted(scratch_ / "missing.nii.gz") + " -o " + shellQuoted(scratch_ / "p2"),
                  scratch_);
  EXPECT_EQ(r.exitCode, 2) << r.err;
  EXPECT_NE(r.err.find("missing.nii.gz"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(scratch_ / "p2"));
  // --force replaces only a page this command wrote.
  const fs::path other = scratch_ / "other";
  fs::create_directories(other);
  std::ofstream(other / "notes.txt") << "not a page\n";
  r = runDtfabric("web " + shellQuoted(input_) + " -o " + shellQuoted(other) + " --force", scratch_);
  EXPECT_EQ(r.exitCode, 2) << r.err;
  EXPECT_NE(r.err.find("is not a page dtfabric web wrote"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::exists(other / "notes.txt"));
  // --force replaces it.
  r = runDtfabric("web " + shellQuoted(input_) + " -o " + shellQuoted(page) + " --size 64 --force", scratch_);
  EXPECT_EQ(r.exitCode, 0) << r.err;
  EXPECT_EQ(assignedJson(page / "data.js")["axes"][0]["width"].get<int>() +
                assignedJson(page / "data.js")["axes"][0]["height"].get<int>() - 64,
            std::min(assignedJson(page / "data.js")["axes"][0]["width"].get<int>(),
                     assignedJson(page / "data.js")["axes"][0]["height"].get<int>()));
}

// Pixels of a screenshot in the view (left of the side panel) that are coloured: the fabric's DEC.
int colouredPixels(const Image& img, int viewWidth) {
  int n = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < std::min(viewWidth, img.width); ++x) {
      const std::uint8_t* p = img.pixel(x, y);
      const int hi = std::max({p[0], p[1], p[2]}), lo = std::min({p[0], p[1], p[2]});
      n += hi - lo > 40;
    }
  return n;
}

TEST_F(WebPage, LoadsInChromiumFromFileDrawsProbesAndFollowsTheSlider) {
  DTF_REQUIRE_TOOL("chromium");
  const fs::path page = scratch_ / "page", tracts = scratch_ / "tracts.tck";
  auto r = runDtfabric("track " + shellQuoted(input_) + " -o " + shellQuoted(tracts) +
                           " --step 0.5 --min-length 8 --select 300",
                       scratch_);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  r = runDtfabric("web " + shellQuoted(input_) + " -o " + shellQuoted(page) + " --size 128 --tracts " +
                      shellQuoted(tracts),
                  scratch_);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const json d = assignedJson(page / "data.js");
  const std::vector<int> axial = d["axes"][0]["slices"];
  ASSERT_GT(axial.size(), 8u);
  const int slice = axial[axial.size() / 2];
  char tractFile[64];
  std::snprintf(tractFile, sizeof tractFile, "slices/axial_tracts_%03d.png", slice);
  EXPECT_EQ(d["axes"][0]["tractImage"], "slices/axial_tracts_");
  EXPECT_TRUE(fs::exists(page / tractFile));

  std::string log;
  const fs::path netLog = scratch_ / "net.json";
  const std::string text = test::chromiumSelfCheck(
      page / "index.html", scratch_, log, "axis=axial&slice=" + std::to_string(slice) + "&selfcheck", netLog);
  ASSERT_FALSE(text.empty()) << "the page wrote no self-check; chromium log:\n" << log;
  std::printf("self-check: %s\n", text.c_str());
  const json c = json::parse(text);
  EXPECT_EQ(c["errors"], json::array()) << text;
  EXPECT_EQ(c["outside"], json::array()) << text; // every file it refers to is in the folder
  EXPECT_GE(c["resources"].get<int>(), 5);        // data.js, voxels.js, viewer.js, two slices
  EXPECT_EQ(pageNetworkRequests(netLog), std::vector<std::string>{});
  {
    // The net log check can fail: a copy of the page with one image from the network.
    const fs::path bad = scratch_ / "bad";
    fs::copy(page, bad, fs::copy_options::recursive);
    std::string html = readText(bad / "index.html");
    html.replace(html.find("</body>"), 7, "<img src=\"http://example.invalid/x.png\"></body>");
    std::ofstream(bad / "index.html") << html;
    std::string badLog;
    test::chromiumSelfCheck(bad / "index.html", scratch_, badLog, "selfcheck", scratch_ / "bad_net.json");
    EXPECT_EQ(pageNetworkRequests(scratch_ / "bad_net.json"),
              std::vector<std::string>{"http://example.invalid/x.png"});
  }
  EXPECT_EQ(log.find("Uncaught"), std::string::npos) << log;
  EXPECT_EQ(c["letters"], "RLAP"); // radiological axial: patient's right on the left, anterior up
  const json& b = c["before"];
  EXPECT_EQ(b["slice"], slice);
  EXPECT_TRUE(b["loaded"].get<bool>()) << text;
  EXPECT_EQ(b["width"], d["axes"][0]["width"]);
  EXPECT_GE(b["drawn"].get<int>(), 1);
  const json& a = c["after"];
  EXPECT_NE(a["slice"], slice);
  EXPECT_NE(a["src"], b["src"]);
  EXPECT_TRUE(a["loaded"].get<bool>()) << text;
  EXPECT_GT(a["drawn"].get<int>(), b["drawn"].get<int>());

  // The probe: its voxel lies on the slice shown, its world point maps back into that voxel, its FA is the
  // voxel's, and left of centre is further to the patient's right (+x) than right of centre.
  const Grid& g = field_.grid;
  for (const char* where : {"probeLeft", "probeCentre", "probeRight"}) {
    SCOPED_TRACE(where);
    const json& p = b[where];
    ASSERT_TRUE(p.is_object()) << text;
    const glm::ivec3 v(p["voxel"][0].get<int>(), p["voxel"][1].get<int>(), p["voxel"][2].get<int>());
    EXPECT_EQ(v[d["axes"][0]["voxelAxis"].get<int>()], slice);
    const glm::dvec3 back = g.toVoxel(vec3(p["world"]));
    for (int i = 0; i < 3; ++i)
      EXPECT_LE(std::abs(back[i] - v[i]), 0.5 + 1e-6);
    ASSERT_TRUE(g.contains(v.x, v.y, v.z));
    const std::size_t idx = g.index(v.x, v.y, v.z);
    if (field_.valid[idx]) {
      ASSERT_FALSE(p["fa"].is_null());
      EXPECT_NEAR(p["fa"].get<double>(), fractionalAnisotropy(field_.tensors[idx]), 0.003);
    } else {
      EXPECT_TRUE(p["fa"].is_null());
    }
  }
  EXPECT_GT(b["probeLeft"]["world"][0].get<double>(), b["probeRight"]["world"][0].get<double>() + 3);

  // Keys, wheel and drag as a user gives them.
  const json& i = c["interaction"];
  EXPECT_EQ(i["up"], 1) << text;
  EXPECT_EQ(i["pageDown"], -5) << text;
  EXPECT_EQ(i["axes"], json({"coronal", "sagittal", "axial"}));
  EXPECT_GT(i["zoom"].get<double>(), 1.5);
  ASSERT_TRUE(i["zoomShiftMm"].is_number()) << text;
  EXPECT_LT(i["zoomShiftMm"].get<double>(), 0.01);
  EXPECT_EQ(i["pan"], json({30, -20}));
  EXPECT_EQ(i["reset"], json({1, 0, 0}));
  EXPECT_NE(i["probeText"].get<std::string>().find(" mm\nvoxel  "), std::string::npos) << text;

  // Neurological: the same slice mirrored, so the letters and the probe's sides swap.
  const std::string neuro = test::chromiumSelfCheck(
      page / "index.html", scratch_, log, "axis=axial&neuro=1&slice=" + std::to_string(slice) + "&selfcheck");
  ASSERT_FALSE(neuro.empty()) << log;
  const json n = json::parse(neuro);
  EXPECT_EQ(n["letters"], "LRAP");
  EXPECT_EQ(n["errors"], json::array()) << neuro;
  EXPECT_LT(n["before"]["probeLeft"]["world"][0].get<double>(),
            n["before"]["probeRight"]["world"][0].get<double>() - 3);
  EXPECT_EQ(n["before"]["probeLeft"]["voxel"], b["probeRight"]["voxel"]);

  // Screenshots: the fabric drawn, another slice looks different, the tract overlay changes the picture.
  const std::string url = "file://" + (page / "index.html").string();
  const fs::path shotA = scratch_ / "slice_a.png", shotB = scratch_ / "slice_b.png",
                 shotT = scratch_ / "tracts.png";
  const int other = axial[axial.size() / 2 - 4];
  ASSERT_TRUE(test::chromiumScreenshot(url + "#axis=axial&slice=" + std::to_string(slice), shotA, 900, 600));
  ASSERT_TRUE(test::chromiumScreenshot(url + "#axis=axial&slice=" + std::to_string(other), shotB, 900, 600));
  ASSERT_TRUE(
      test::chromiumScreenshot(url + "#axis=axial&tracts=1&slice=" + std::to_string(slice), shotT, 900, 600));
  std::printf("screenshots: %s %s %s\n", shotA.c_str(), shotB.c_str(), shotT.c_str());
  const Image A = io::readPng(shotA.string()), B = io::readPng(shotB.string()),
              Tr = io::readPng(shotT.string());
  ASSERT_EQ(A.width, 900);
  const int viewWidth = 900 - 300; // the side panel is 290 px plus padding
  const int colouredA = colouredPixels(A, viewWidth);
  EXPECT_GT(colouredA, 600 * 600 / 20) << "the fabric is not drawn";
  int differ = 0, differT = 0;
  for (int y = 0; y < A.height; ++y)
    for (int x = 0; x < viewWidth; ++x) {
      differ += std::memcmp(A.pixel(x, y), B.pixel(x, y), 3) != 0;
      differT += std::memcmp(A.pixel(x, y), Tr.pixel(x, y), 3) != 0;
    }
  EXPECT_GT(differ, 2000) << "another slice shows the same picture";
  EXPECT_GT(differT, 200) << "the tract overlay changes nothing";
}

// The 3D view and the FA sweep: the frames data.js names are in 3d/ and fa/ (36 azimuths at each elevation;
// thresholds 0.15 to 0.6), index.html has the element id="view3d"; in headless Chromium a drag on the 3D
// view shows another azimuth's frame and the sweep's slider another threshold's frame with its threshold
// printed, every frame loads, with no console error and no request; screenshots of both; --slices-only
// --force replaces the folder with one of slices only.
TEST_F(WebPage, TheThreeDViewTurnsWhenDraggedAndTheSweepFollowsItsSlider) {
  DTF_REQUIRE_TOOL("chromium");
  const fs::path page = scratch_ / "page";
  auto r = runDtfabric("web " + shellQuoted(input_) + " -o " + shellQuoted(page) + " --size 96 --elevations 0,20",
                       scratch_);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("72 3D frames, 10 FA thresholds"), std::string::npos) << r.out;
  const json d = assignedJson(page / "data.js");
  ASSERT_TRUE(d["view3d"].is_object()) << d.dump();
  EXPECT_EQ(d["view3d"]["azimuths"], 36);
  EXPECT_EQ(d["view3d"]["elevations"], json({0.0, 20.0}));
  EXPECT_EQ(d["view3d"]["surface"], "FA isosurface at 0.25");
  const std::vector<double> thresholds = d["faSweep"]["thresholds"];
  ASSERT_EQ(thresholds.size(), 10u);
  EXPECT_DOUBLE_EQ(thresholds.front(), 0.15);
  EXPECT_DOUBLE_EQ(thresholds.back(), 0.6);
  std::size_t frames = 0, sweep = 0;
  for (const auto& e : fs::directory_iterator(page / "3d")) frames += e.path().extension() == ".png";
  for (const auto& e : fs::directory_iterator(page / "fa")) sweep += e.path().extension() == ".png";
  EXPECT_EQ(frames, 72u);
  EXPECT_EQ(sweep, 10u);
  const Image f0 = io::readPng((page / "3d/view_01_000.png").string()),
              f9 = io::readPng((page / "3d/view_01_009.png").string());
  ASSERT_EQ(f0.width, 96);
  int differ = 0;
  for (int y = 0; y < f0.height; ++y)
    for (int x = 0; x < f0.width; ++x) differ += std::memcmp(f0.pixel(x, y), f9.pixel(x, y), 3) != 0;
  EXPECT_GT(differ, 500) << "a quarter turn shows the same picture";
  EXPECT_NE(readText(page / "index.html").find("id=\"view3d\""), std::string::npos);

  std::string log;
  const fs::path netLog = scratch_ / "net3d.json";
  const std::string text = test::chromiumSelfCheck(page / "index.html", scratch_, log, "selfcheck3d", netLog);
  ASSERT_FALSE(text.empty()) << "the page wrote no self-check; chromium log:\n" << log;
  std::printf("self-check: %s\n", text.c_str());
  const json c = json::parse(text);
  EXPECT_EQ(c["errors"], json::array()) << text;
  EXPECT_EQ(c["outside"], json::array()) << text;
  EXPECT_EQ(pageNetworkRequests(netLog), std::vector<std::string>{});
  EXPECT_EQ(log.find("Uncaught"), std::string::npos) << log;
  EXPECT_TRUE(c["view3d"].get<bool>());
  EXPECT_EQ(c["framesTotal"], 82) << text; // 72 turning, 10 sweeping
  EXPECT_EQ(c["framesLoaded"], 82) << text;
  const json &b3 = c["before3d"], &a3 = c["after3d"];
  EXPECT_TRUE(b3["loaded"].get<bool>() && b3["visible"].get<bool>()) << text;
  EXPECT_EQ(b3["src"], "3d/view_01_000.png"); // opens at 20 degrees, from the front
  EXPECT_TRUE(a3["loaded"].get<bool>()) << text;
  EXPECT_NE(a3["src"], b3["src"]) << text; // a drag of a quarter of the width: 9 frames round
  EXPECT_EQ(b3["azimuth"], 0) << text;
  EXPECT_EQ(a3["azimuth"], 27) << text; // dragged right by a quarter turn: 9 frames back round
  const json &bf = c["beforeFa"], &af = c["afterFa"];
  EXPECT_TRUE(bf["loaded"].get<bool>() && bf["visible"].get<bool>()) << text;
  EXPECT_EQ(bf["src"], "fa/fa_02.png"); // opens at 0.25
  EXPECT_EQ(bf["text"], "FA \u2265 0.25");
  EXPECT_EQ(af["src"], "fa/fa_09.png");
  EXPECT_EQ(af["text"], "FA \u2265 0.60");
  EXPECT_TRUE(af["loaded"].get<bool>()) << text;

  // Screenshots: the 3D view and the sweep drawn, another azimuth and another threshold look different.
  const std::string url = "file://" + (page / "index.html").string();
  const fs::path a = scratch_ / "view3d_a.png", b = scratch_ / "view3d_b.png", s0 = scratch_ / "sweep_0.png",
                 s9 = scratch_ / "sweep_9.png";
  ASSERT_TRUE(test::chromiumScreenshot(url + "#tab=3d", a, 900, 600));
  ASSERT_TRUE(test::chromiumScreenshot(url + "#tab=3d&az=9", b, 900, 600));
  ASSERT_TRUE(test::chromiumScreenshot(url + "#tab=fa&fa=0", s0, 900, 600));
  ASSERT_TRUE(test::chromiumScreenshot(url + "#tab=fa&fa=9", s9, 900, 600));
  std::printf("screenshots: %s %s %s %s\n", a.c_str(), b.c_str(), s0.c_str(), s9.c_str());
  const Image A = io::readPng(a.string()), B = io::readPng(b.string()), S0 = io::readPng(s0.string()),
              S9 = io::readPng(s9.string());
  const int viewWidth = 900 - 300;
  EXPECT_GT(colouredPixels(A, viewWidth), 2000) << "the 3D view is not drawn";
  EXPECT_GT(colouredPixels(S0, viewWidth), 2000) << "the sweep is not drawn";
  const auto litPixels = [&](const Image& img) {
    int n = 0;
    for (int y = 0; y < img.height - 40; ++y) // above the slider
      for (int x = 0; x < viewWidth; ++x) n += (img.pixel(x, y)[0] | img.pixel(x, y)[1] | img.pixel(x, y)[2]) > 20;
    return n;
  };
  EXPECT_GT(litPixels(S0), litPixels(S9) * 5 / 4) << "the surface at FA 0.15 is not larger than at 0.6";
  int turned = 0;
  for (int y = 0; y < A.height; ++y)
    for (int x = 0; x < viewWidth; ++x) turned += std::memcmp(A.pixel(x, y), B.pixel(x, y), 3) != 0;
  EXPECT_GT(turned, 2000) << "another azimuth shows the same picture";

  // --slices-only --force: the folder replaced by one without the 3D view and the sweep.
  r = runDtfabric("web " + shellQuoted(input_) + " -o " + shellQuoted(page) + " --size 64 --slices-only --force",
                  scratch_);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_TRUE(assignedJson(page / "data.js")["view3d"].is_null());
  EXPECT_TRUE(assignedJson(page / "data.js")["faSweep"].is_null());
  EXPECT_FALSE(fs::exists(page / "3d"));
  EXPECT_FALSE(fs::exists(page / "fa"));
  // Bad values: exit 1, nothing written.
  r = runDtfabric("web " + shellQuoted(input_) + " -o " + shellQuoted(scratch_ / "p3") + " --elevations 20,x",
                  scratch_);
  EXPECT_EQ(r.exitCode, 1) << r.err;
  EXPECT_NE(r.err.find("--elevations"), std::string::npos) << r.err;
  r = runDtfabric("web " + shellQuoted(input_) + " -o " + shellQuoted(scratch_ / "p3") + " --surface fa=2",
                  scratch_);
  EXPECT_NE(r.exitCode, 0) << r.err;
  EXPECT_FALSE(fs::exists(scratch_ / "p3"));
}

// Known anatomy on the real brain: on the page's axial slice 22 the body of the corpus callosum (voxel
// 33,42,22) is red (left-right) and on coronal slice 34 the corticospinal tract (voxel 30,34,15) blue
// (superior-inferior), where the exported mapping puts those voxels; the table holds their FA and direction.
TEST(WebPageRealBrain, CallosumRedAndCorticospinalBlueWhereTheMappingPutsThem) {
  DTF_SHARED_FILE(tensor, "iu_prisma_dwi/derived/dti_tensor.nii.gz");
  const fs::path scratch = test::scratchDir(), page = scratch / "page";
  const auto r =
      runDtfabric("web " + shellQuoted(tensor) + " -o " + shellQuoted(page) + " --size 144", scratch);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const json d = assignedJson(page / "data.js");
  const Grid g = io::readTensorVolume(tensor.string()).field.grid;
  const std::string vtext = readText(page / "voxels.js");
  const auto table = base64Decode(vtext.substr(vtext.find('"') + 1));
  struct Landmark {
    int axis;
    glm::ivec3 voxel;
    int channel; // the dominant colour and direction component: 0 red / x, 2 blue / z
  };
  for (const Landmark& l : {Landmark{0, {33, 42, 22}, 0}, Landmark{1, {30, 34, 15}, 2}}) {
    SCOPED_TRACE(l.channel == 0 ? "corpus callosum" : "corticospinal tract");
    const std::size_t o = g.index(l.voxel.x, l.voxel.y, l.voxel.z) * 4;
    EXPECT_GT((table[o] - 1) / 254.0, 0.5);
    const glm::dvec3 e1((table[o + 1] - 128) / 127.0, (table[o + 2] - 128) / 127.0,
                        (table[o + 3] - 128) / 127.0);
    EXPECT_GT(std::abs(e1[l.channel]), 0.8) << e1.x << " " << e1.y << " " << e1.z;

    const json& ax = d["axes"][l.axis];
    const int slice = l.voxel[ax["voxelAxis"].get<int>()];
    char file[64];
    std::snprintf(file, sizeof file, "%s%03d.png", ax["image"].get<std::string>().c_str(), slice);
    const Image img = io::readPng((page / file).string());
    const glm::dvec3 p = g.toWorld(glm::dvec3(l.voxel)) - vec3(ax["centre"]);
    const double mm = ax["mmPerPixel"];
    const int px = static_cast<int>(img.width / 2.0 + glm::dot(p, vec3(ax["right"])) / mm);
    const int py = static_cast<int>(img.height / 2.0 - glm::dot(p, vec3(ax["up"])) / mm);
    double sum[3] = {0, 0, 0};
    for (int y = py - 3; y <= py + 3; ++y)
      for (int x = px - 3; x <= px + 3; ++x)
        for (int c = 0; c < 3; ++c)
          sum[c] += img.pixel(x, y)[c];
    std::printf("%s slice %d, voxel at pixel (%d, %d): mean colour %.0f %.0f %.0f\n",
                ax["name"].get<std::string>().c_str(), slice, px, py, sum[0] / 49, sum[1] / 49, sum[2] / 49);
    for (int c = 0; c < 3; ++c) {
      if (c != l.channel) {
        EXPECT_GT(sum[l.channel], 1.5 * sum[c]) << "channel " << c;
      }
    }
  }
}

} // namespace
