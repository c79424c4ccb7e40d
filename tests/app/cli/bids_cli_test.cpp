// SPDX-License-Identifier: GPL-3.0-or-later
// `dtfabric bids` end to end on a small BIDS dataset made from ../shared/data in the build's scratch folder:
// sessions and entities, the real DWI as given, re-strided to RAS, with its x gradients negated and with its
// b-values doubled (diffusivities halve: an MD outlier), three noisy copies, a corrupt file, a missing bvec,
// a table one direction short and a DIPY crop too small to judge. Both levels, the rerun, a run killed
// part-way, the Snakemake workflow, the report in headless Chromium, and bad input.
#include "io/model/error.h"
#include "io/formats/png_io.h"
#include "io/formats/tensor_io.h"
#include "support/chromium.h"
#include "support/cli.h"
#include "support/test_env.h"
#include "support/volumes.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <fstream>
#include <gtest/gtest.h>
#include <map>
#include <nlohmann/json.hpp>
#include <random>
#include <regex>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

namespace {

namespace fs = std::filesystem;
using namespace dtf;
using test::readText;
using test::chromiumSelfCheck;
using test::runDtfabric;

std::string q(const fs::path& p) {
  return "'" + p.string() + "'";
}

// One shell word holding `s` exactly, whatever it contains.
std::string shellWord(const std::string& s) {
  std::string o = "'";
  for (char c : s)
    o += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return o + "'";
}

// Voxel axis i reversed (LAS -> RAS), the affine adjusted so every voxel keeps its world position. The FSL
// table stays the same: its frame is the voxel axes with x negated when det(affine) > 0, and both the data's
// x axis and that rule flip.
using test::flipI;

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream ss(text);
  for (std::string l; std::getline(ss, l);)
    out.push_back(l);
  return out;
}

std::vector<std::string> fields(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream ss(line);
  for (std::string f; std::getline(ss, f, '\t');)
    out.push_back(f);
  return out;
}

void copyRun(const fs::path& src, const std::string& srcStem, const fs::path& dir, const std::string& stem,
             const char* niiExt = ".nii.gz") {
  fs::create_directories(dir);
  fs::copy_file(src / (srcStem + niiExt), dir / (stem + "_dwi" + niiExt));
  fs::copy_file(src / (srcStem + ".bval"), dir / (stem + "_dwi.bval"));
  fs::copy_file(src / (srcStem + ".bvec"), dir / (stem + "_dwi.bvec"));
}

// Rewrites each line of a text file through `f(row, tokens)`.
void editTable(const fs::path& p, const std::function<void(int, std::vector<std::string>&)>& f) {
  const auto ls = lines(readText(p));
  std::string out;
  for (std::size_t r = 0; r < ls.size(); ++r) {
    std::vector<std::string> t;
    std::stringstream ss(ls[r]);
    for (std::string w; ss >> w;)
      t.push_back(w);
    f(static_cast<int>(r), t);
    for (std::size_t i = 0; i < t.size(); ++i)
      out += (i ? " " : "") + t[i];
    out += "\n";
  }
  std::ofstream(p) << out;
}

// The workflow's log and each participant job's log under `out`/logs, for a failed workflow's message
// (Snakemake's own log says only that a job failed).
std::string workflowLogs(const fs::path& snakemakeLog, const fs::path& out) {
  std::string all = readText(snakemakeLog);
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(out / "logs", ec))
    if (e.path().extension() == ".log") all += "\n--- " + e.path().string() + "\n" + readText(e.path());
  return all;
}

// The dataset, built once per build tree (into a temporary folder, then renamed, so concurrent tests see
// either nothing or all of it).
fs::path cohortDataset() {
  const fs::path root = test::binaryDir() / "test_scratch" / "bids_cohort_dataset";
  if (fs::exists(root / "dataset_description.json")) return root;
  const fs::path shared = test::sharedDataDir();
  const fs::path real = shared / "iu_prisma_dwi", dipy = shared / "dipy_small";
  const fs::path tmp = root.string() + ".tmp" + std::to_string(::getpid());
  fs::remove_all(tmp);
  fs::create_directories(tmp);
  std::ofstream(tmp / "dataset_description.json")
      << "{\"Name\": \"dtfabric test cohort\", \"BIDSVersion\": \"1.8.0\"}\n";
  std::ofstream(tmp / "participants.tsv") << "participant_id\nsub-01\nsub-02\n";
  copyRun(real, "dwi", tmp / "sub-01/ses-1/dwi", "sub-01_ses-1");
  {
    const fs::path d = tmp / "sub-01/ses-2/dwi";
    copyRun(real, "dwi", d, "sub-01_ses-2_acq-ras");
    fs::remove(d / "sub-01_ses-2_acq-ras_dwi.nii.gz");
    io::writeScalarVolume((d / "sub-01_ses-2_acq-ras_dwi.nii.gz").string(),
                          flipI(io::readScalarVolume((real / "dwi.nii.gz").string())));
  }
  copyRun(real, "dwi", tmp / "sub-02/dwi", "sub-02_dir-AP_run-1");
  editTable(tmp / "sub-02/dwi/sub-02_dir-AP_run-1_dwi.bvec", [](int row, std::vector<std::string>& t) {
    if (row == 0)
      for (auto& w : t)
        w = w[0] == '-' ? w.substr(1) : "-" + w;
  });
  copyRun(real, "dwi", tmp / "sub-02/dwi", "sub-02_dir-AP_run-2");
  editTable(tmp / "sub-02/dwi/sub-02_dir-AP_run-2_dwi.bval", [](int, std::vector<std::string>& t) {
    for (auto& w : t)
      w = std::to_string(2 * std::stoi(w));
  });
  {
    const fs::path d = tmp / "sub-03/dwi"; // corrupt: the gzip stream cut short
    copyRun(real, "dwi", d, "sub-03");
    const std::string bytes = readText(real / "dwi.nii.gz");
    std::ofstream(d / "sub-03_dwi.nii.gz", std::ios::binary) << bytes.substr(0, bytes.size() / 3);
  }
  copyRun(real, "dwi", tmp / "sub-04/dwi", "sub-04");
  fs::remove(tmp / "sub-04/dwi/sub-04_dwi.bvec");
  copyRun(real, "dwi", tmp / "sub-05/dwi", "sub-05"); // one direction short of the volume count
  editTable(tmp / "sub-05/dwi/sub-05_dwi.bval", [](int, std::vector<std::string>& t) { t.pop_back(); });
  editTable(tmp / "sub-05/dwi/sub-05_dwi.bvec", [](int, std::vector<std::string>& t) { t.pop_back(); });
  copyRun(dipy, "small_64D", tmp / "sub-06/dwi", "sub-06_acq-dipy", ".nii");
  const ScalarVolume dwi = io::readScalarVolume((real / "dwi.nii.gz").string());
  double b0 = 0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < dwi.grid.voxelCount(); ++i)
    if (dwi.data[i * dwi.components] > 0) b0 += dwi.data[i * dwi.components], ++n;
  b0 /= static_cast<double>(n);
  for (int s = 7; s <= 9; ++s) { // Gaussian noise, 2% of the mean b0, a different seed each
    const std::string sub = "sub-0" + std::to_string(s);
    const fs::path d = tmp / sub / "dwi";
    copyRun(real, "dwi", d, sub);
    fs::remove(d / (sub + "_dwi.nii.gz"));
    ScalarVolume noisy = dwi;
    std::mt19937 rng(static_cast<unsigned>(s));
    std::normal_distribution<float> noise(0.0f, static_cast<float>(0.02 * b0));
    for (auto& v : noisy.data)
      if (v > 0) v = std::max(1.0f, v + noise(rng));
    io::writeScalarVolume((d / (sub + "_dwi.nii")).string(), noisy);
  }
  std::error_code ec;
  fs::rename(tmp, root, ec);
  if (ec) fs::remove_all(tmp); // another test built it first
  return root;
}

struct Expected {
  bool ok;
  std::string verdict; // "" when failed
  std::string message; // a part of the message
  bool sheet;          // a contact sheet is written
};

const std::map<std::string, Expected>& expectedRuns() {
  static const std::map<std::string, Expected> e = {
      {"sub-01_ses-1", {true, "ok", "verdict ok", false}},
      {"sub-01_ses-2_acq-ras", {true, "ok", "verdict ok", false}},
      {"sub-02_dir-AP_run-1", {true, "corrected", "-x y z", true}},
      {"sub-02_dir-AP_run-2", {true, "ok", "verdict ok", false}},
      {"sub-03", {false, "", "sub-03_dwi.nii.gz", false}},
      {"sub-04", {false, "", "no gradient file", false}},
      {"sub-05", {false, "", "volumes", false}},
      {"sub-06_acq-dipy", {true, "inconclusive", "verdict inconclusive", true}},
      {"sub-07", {true, "ok", "verdict ok", false}},
      {"sub-08", {true, "ok", "verdict ok", false}},
      {"sub-09", {true, "ok", "verdict ok", false}},
  };
  return e;
}

std::string relDirOf(const std::string& run) {
  const std::string sub = run.substr(0, 6);
  const auto ses = run.find("_ses-");
  return ses == std::string::npos ? sub + "/dwi" : sub + "/" + run.substr(ses + 1, 5) + "/dwi";
}

using Table = std::map<std::string, std::map<std::string, std::string>>; // run -> column -> value

Table readGroupTsv(const fs::path& p) {
  const auto ls = lines(readText(p));
  Table t;
  if (ls.empty()) return t;
  const auto header = fields(ls[0]);
  for (std::size_t i = 1; i < ls.size(); ++i) {
    const auto f = fields(ls[i]);
    EXPECT_EQ(f.size(), header.size()) << ls[i];
    for (std::size_t c = 0; c < std::min(f.size(), header.size()); ++c)
      t[f.size() > 2 ? f[2] : ""][header[c]] = f[c];
  }
  return t;
}

// Modified z-scores recomputed from group.tsv: |0.6745 (x - median) / MAD| > 3.5, with 1.2533 * mean
// absolute deviation replacing MAD / 0.6745 when the MAD is 0, and a difference above 5% of the median.
std::set<std::pair<std::string, std::string>> recomputedOutliers(const Table& t) {
  std::set<std::pair<std::string, std::string>> out;
  for (const std::string m : {"fa_wm_mean", "md_wm_mean", "wm_fraction", "brain_voxels"}) {
    std::vector<std::pair<std::string, double>> v;
    for (const auto& [run, row] : t)
      if (row.at("status") == "ok") v.emplace_back(run, std::stod(row.at(m)));
    auto med = [](std::vector<double> x) {
      std::sort(x.begin(), x.end());
      return x.size() % 2 ? x[x.size() / 2] : 0.5 * (x[x.size() / 2 - 1] + x[x.size() / 2]);
    };
    std::vector<double> x, d;
    for (auto& p : v)
      x.push_back(p.second);
    const double mdn = med(x);
    double meanAd = 0;
    for (double y : x)
      d.push_back(std::abs(y - mdn)), meanAd += std::abs(y - mdn) / static_cast<double>(x.size());
    const double mad = med(d);
    const double scale = mad > 0 ? mad / 0.6745 : 1.253314 * meanAd;
    for (auto& p : v)
      if (scale > 0 && std::abs(p.second - mdn) / scale > 3.5 &&
          std::abs(p.second - mdn) > 0.05 * std::abs(mdn))
        out.insert({p.first, m});
  }
  return out;
}

// Checks group.tsv against the dataset's design; returns it.
Table checkGroupTable(const fs::path& out) {
  const Table t = readGroupTsv(out / "group.tsv");
  EXPECT_EQ(t.size(), expectedRuns().size());
  for (const auto& [run, e] : expectedRuns()) {
    SCOPED_TRACE(run);
    auto it = t.find(run);
    if (it == t.end()) {
      ADD_FAILURE() << "no row";
      continue;
    }
    const auto& row = it->second;
    EXPECT_EQ(row.at("participant_id"), run.substr(0, 6));
    EXPECT_EQ(row.at("session_id"), run.find("_ses-") == std::string::npos ? "n/a" : run.substr(7, 5));
    EXPECT_EQ(row.at("status"), e.ok ? "ok" : "failed");
    EXPECT_EQ(row.at("check_verdict"), e.ok ? e.verdict : "n/a");
    EXPECT_NE(row.at("message").find(e.message), std::string::npos) << row.at("message");
    if (e.ok) {
      EXPECT_GT(std::stod(row.at("fa_wm_mean")), 0.3);
      EXPECT_LT(std::stod(row.at("fa_wm_mean")), 1.0);
      EXPECT_GT(std::stod(row.at("md_wm_mean")), 0.1); // 1e-3 mm^2/s
      EXPECT_LT(std::stod(row.at("md_wm_mean")), 2.0);
    } else {
      EXPECT_EQ(row.at("fa_wm_mean"), "n/a");
    }
  }
  if (t.size() != expectedRuns().size()) return t;
  // The corrected table is the true one: x negated back.
  EXPECT_EQ(t.at("sub-02_dir-AP_run-1").at("check_correction"), "-x y z");
  // A table's x sign and the voxel order leave FA and MD unchanged; doubled b-values halve MD.
  const double fa = std::stod(t.at("sub-01_ses-1").at("fa_wm_mean"));
  const double md = std::stod(t.at("sub-01_ses-1").at("md_wm_mean"));
  for (const char* same : {"sub-01_ses-2_acq-ras", "sub-02_dir-AP_run-1", "sub-02_dir-AP_run-2"})
    EXPECT_NEAR(std::stod(t.at(same).at("fa_wm_mean")), fa, 2e-4) << same;
  EXPECT_NEAR(std::stod(t.at("sub-01_ses-2_acq-ras").at("md_wm_mean")), md, 2e-4);
  EXPECT_NEAR(std::stod(t.at("sub-02_dir-AP_run-2").at("md_wm_mean")), md / 2, 2e-4);
  // Outliers: the halved MD is one; the copies of the true data are not; the column agrees with the rule.
  EXPECT_NE(t.at("sub-02_dir-AP_run-2").at("outliers").find("md_wm_mean"), std::string::npos);
  for (const char* clean :
       {"sub-01_ses-1", "sub-01_ses-2_acq-ras", "sub-02_dir-AP_run-1", "sub-07", "sub-08", "sub-09"})
    EXPECT_EQ(t.at(clean).at("outliers"), "n/a") << clean;
  std::set<std::pair<std::string, std::string>> listed;
  for (const auto& [run, row] : t) {
    std::stringstream ss(row.at("outliers"));
    for (std::string m; std::getline(ss, m, ',');)
      if (m != "n/a") listed.insert({run, m});
  }
  EXPECT_EQ(listed, recomputedOutliers(t));
  return t;
}

// Every file below `dir`: relative path -> content (PNGs and JSON are small at the tests' figure size).
std::map<std::string, std::string> snapshot(const fs::path& dir) {
  std::map<std::string, std::string> s;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file())
      s[fs::relative(e.path(), dir).string()] =
          readText(e.path()) + "@" + std::to_string(fs::last_write_time(e.path()).time_since_epoch().count());
  return s;
}

std::vector<std::string> temporaries(const fs::path& dir) {
  std::vector<std::string> t;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.path().filename().string().find(".tmp") != std::string::npos) t.push_back(e.path().string());
  return t;
}

// Every visible output decodes: PNGs as images, metrics documents as JSON with a status.
void checkNothingPartial(const fs::path& out) {
  for (const auto& e : fs::recursive_directory_iterator(out)) {
    const std::string name = e.path().filename().string();
    if (!e.is_regular_file() || name[0] == '.') continue;
    if (e.path().extension() == ".png") {
      EXPECT_NO_THROW(io::readPng(e.path().string())) << e.path();
    } else if (name.find("_desc-fabricMetrics_dwi.json") != std::string::npos) {
      const std::string text = readText(e.path());
      EXPECT_NE(text.find("\"status\": "), std::string::npos) << e.path();
      EXPECT_EQ(text.substr(text.size() - 2), "}\n") << e.path();
    }
  }
}

void checkRunFiles(const fs::path& out, int px) {
  for (const auto& [run, e] : expectedRuns()) {
    SCOPED_TRACE(run);
    const fs::path dir = out / relDirOf(run);
    EXPECT_TRUE(fs::exists(dir / (run + "_desc-fabricMetrics_dwi.json")));
    for (const char* desc : {"fabricAxial", "fabricCoronal", "fabricIsoLeft", "fabricIsoSuperior"}) {
      const fs::path png = dir / (run + "_desc-" + desc + "_dwi.png");
      EXPECT_EQ(fs::exists(png), e.ok) << png;
      if (e.ok && fs::exists(png)) {
        const Image img = io::readPng(png.string());
        EXPECT_EQ(img.width, px);
        EXPECT_EQ(img.height, px);
        std::size_t lit = 0;
        for (std::size_t i = 0; i < img.rgba.size(); i += 4)
          lit += img.rgba[i] + img.rgba[i + 1] + img.rgba[i + 2] > 60;
        EXPECT_GT(lit, img.rgba.size() / 4 / 20) << png << ": the figure is nearly empty";
      }
    }
    EXPECT_EQ(fs::exists(dir / (run + "_desc-fabricCheck_dwi.png")), e.sheet);
  }
}

std::string inputDigest(const fs::path& bids) {
  std::string d;
  for (const auto& e : fs::recursive_directory_iterator(bids)) {
    d += e.path().string() + "\n";
    if (e.is_regular_file()) d += std::to_string(std::hash<std::string>{}(readText(e.path()))) + "\n";
  }
  return d;
}

class BidsCohort : public ::testing::Test {
protected:
  void SetUp() override {
    DTF_SHARED_FILE(dwi, "iu_prisma_dwi/dwi.nii.gz");
    DTF_SHARED_FILE(dipy, "dipy_small/small_64D.nii");
    bids_ = cohortDataset();
    scratch_ = test::scratchDir();
  }
  fs::path bids_, scratch_;
};

std::set<std::string> jsonList(const std::string& json, const std::string& key) {
  std::smatch m;
  std::set<std::string> out;
  if (!std::regex_search(json, m, std::regex("\"" + key + "\":\\[([^\\]]*)\\]"))) return out;
  const std::string body = m[1];
  std::regex item("\"([^\"]*)\"");
  for (auto it = std::sregex_iterator(body.begin(), body.end(), item); it != std::sregex_iterator(); ++it)
    out.insert((*it)[1]);
  return out;
}

TEST_F(BidsCohort, BothLevelsRerunAndReportInChromium) {
  const fs::path out = scratch_ / "out";
  const std::string inputBefore = inputDigest(bids_);
  auto r =
      runDtfabric("bids " + q(bids_) + " " + q(out) + " participant --jobs 2 --figure-size 128", scratch_);
  EXPECT_EQ(r.exitCode, 2) << r.err; // three runs fail
  EXPECT_NE(r.err.find("[11/11]"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("left, elapsed"), std::string::npos);
  EXPECT_NE(r.err.find("ETA"), std::string::npos);
  EXPECT_NE(r.err.find("8 ok (0 unchanged), 3 failed"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("FAILED: " + (bids_ / "sub-04/dwi/sub-04_dwi.nii.gz").string()), std::string::npos)
      << r.err;
  checkRunFiles(out, 128);
  EXPECT_TRUE(temporaries(out).empty());
  const nlohmann::json desc = nlohmann::json::parse(readText(out / "dataset_description.json"));
  EXPECT_EQ(desc.at("DatasetType"), "derivative") << desc;
  EXPECT_EQ(desc.at("GeneratedBy").at(0).at("Name"), "dtfabric") << desc;
  EXPECT_TRUE(desc.at("GeneratedBy").at(0).at("Version").is_string()) << desc;
  EXPECT_EQ(desc.at("SourceDatasets").at(0).at("URL"), "file://" + bids_.string()) << desc;
  const std::string doc = readText(out / "sub-02/dwi/sub-02_dir-AP_run-1_desc-fabricMetrics_dwi.json");
  for (const char* key : {"\"input_hash_dwi\": \"crc32:", "\"input_hash_bvec\": ", "\"seconds_fit\": ",
                          "\"seconds_figures\": ", "\"check_score_best\": ", "\"slice_axial\": "})
    EXPECT_NE(doc.find(key), std::string::npos) << key;

  r = runDtfabric("bids " + q(bids_) + " " + q(out) + " group", scratch_);
  EXPECT_EQ(r.exitCode, 0) << r.err;
  checkGroupTable(out);

  // The rerun recomputes nothing that is complete and rewrites nothing.
  const auto before = snapshot(out);
  r = runDtfabric("bids " + q(bids_) + " " + q(out) + " participant --jobs 2 --figure-size 128", scratch_);
  EXPECT_EQ(r.exitCode, 2) << r.err;
  EXPECT_NE(r.err.find("8 ok (8 unchanged), 3 failed"), std::string::npos) << r.err;
  r = runDtfabric("bids " + q(bids_) + " " + q(out) + " group", scratch_);
  EXPECT_EQ(r.exitCode, 0) << r.err;
  EXPECT_TRUE(before == snapshot(out)) << "the rerun changed files";
  // A changed input is recomputed; --force recomputes all.
  EXPECT_EQ(inputDigest(bids_), inputBefore) << "the input dataset changed";

  DTF_REQUIRE_TOOL("chromium");
  std::string log;
  const std::string check = chromiumSelfCheck(out / "group_report.html", scratch_, log);
  ASSERT_FALSE(check.empty()) << "the page wrote no self-check; chromium log:\n" << log;
  std::printf("self-check: %s\n", check.c_str());
  // 8 ok runs x 4 figures + 2 contact sheets in the mosaic.
  EXPECT_NE(check.find("\"images\":34,\"loaded\":34,\"broken\":[]"), std::string::npos) << check;
  EXPECT_NE(check.find("\"errors\":[]"), std::string::npos) << check;
  EXPECT_NE(check.find("\"rows\":11,\"cards\":11"), std::string::npos) << check;
  EXPECT_EQ(log.find("Uncaught"), std::string::npos) << log;
  const std::set<std::string> failed{"sub-03", "sub-04", "sub-05"};
  EXPECT_EQ(jsonList(check, "failed"), failed);
  EXPECT_EQ(jsonList(check, "list-failed"), failed);
  EXPECT_EQ(jsonList(check, "corrected"), std::set<std::string>{"sub-02_dir-AP_run-1"});
  EXPECT_EQ(jsonList(check, "list-corrected"), std::set<std::string>{"sub-02_dir-AP_run-1"});
  EXPECT_EQ(jsonList(check, "inconclusive"), std::set<std::string>{"sub-06_acq-dipy"});
  EXPECT_TRUE(jsonList(check, "outlier").count("sub-02_dir-AP_run-2"));
  EXPECT_EQ(jsonList(check, "outlier"), jsonList(check, "list-outlier"));
  // Clicking a run's card opens its full figures: the corrected run has five (four and the contact sheet).
  EXPECT_NE(check.find("\"detail\":{\"run\":\"sub-02_dir-AP_run-1\",\"open\":true,\"figures\":5,\"loaded\":5,"
                       "\"links\":5}"),
            std::string::npos)
      << check;

  // The self-check can fail: with one figure gone, the page reports it broken.
  const fs::path broken = scratch_ / "broken";
  fs::copy(out, broken, fs::copy_options::recursive);
  fs::remove(broken / "sub-07/dwi/sub-07_desc-fabricCoronal_dwi.png");
  const std::string brokenCheck = chromiumSelfCheck(broken / "group_report.html", scratch_, log);
  EXPECT_NE(brokenCheck.find("\"images\":34,\"loaded\":33,\"broken\":[\"file://" +
                             (broken / "sub-07/dwi/sub-07_desc-fabricCoronal_dwi.png").string() + "\"]"),
            std::string::npos)
      << brokenCheck;

  const fs::path shot = scratch_ / "report.png";
  EXPECT_TRUE(test::chromiumScreenshot("file://" + (out / "group_report.html").string(), shot, 1400, 2200));
  const Image img = io::readPng(shot.string());
  EXPECT_EQ(img.width, 1400);
  std::printf("screenshot: %s\n", shot.c_str());
}

// A crash prints the signal and the call stack on stderr and still ends the process by that signal (what
// Snakemake and the worker pool see). The vehicle: a pool worker waiting for its next run label on stdin,
// so the signal arrives inside the program at a known point.
TEST_F(BidsCohort, AFatalSignalPrintsTheCallStackAndStaysTheExitStatus) {
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
  GTEST_SKIP() << "sanitizer builds keep the sanitizer's own report";
#else
  const fs::path out = scratch_ / "out", errLog = scratch_ / "crash.log";
  int toWorker[2], fromWorker[2];
  ASSERT_EQ(::pipe(toWorker), 0);
  ASSERT_EQ(::pipe(fromWorker), 0);
  const pid_t pid = ::fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    ::dup2(toWorker[0], 0);
    ::dup2(fromWorker[1], 1);
    std::freopen(errLog.c_str(), "w", stderr);
    ::close(toWorker[1]);
    ::close(fromWorker[0]);
    ::execl(DTF_EXE, DTF_EXE, "bids", bids_.c_str(), out.c_str(), "participant", "--worker",
            static_cast<char*>(nullptr));
    ::_exit(127);
  }
  ::close(toWorker[0]);
  ::close(fromWorker[1]);
  // A label of no run: the worker answers "done" at once and waits for the next.
  ASSERT_EQ(::write(toWorker[1], "sub-none\n", 9), 9);
  char reply[5] = {};
  ASSERT_EQ(::read(fromWorker[0], reply, 5), 5) << readText(errLog);
  EXPECT_EQ(std::string(reply, 4), "done");
  ::kill(pid, SIGSEGV);
  int st = 0;
  ::waitpid(pid, &st, 0);
  ::close(toWorker[1]);
  ::close(fromWorker[0]);
  ASSERT_TRUE(WIFSIGNALED(st)) << readText(errLog);
  EXPECT_EQ(WTERMSIG(st), SIGSEGV);
  const std::string err = readText(errLog);
  EXPECT_NE(err.find("dtfabric: fatal signal SEGV"), std::string::npos) << err;
  // The stack names the program's own functions (the executable exports them).
  EXPECT_TRUE(std::regex_search(err, std::regex(R"(\(_ZN3dtf3app\w*cmdBids\w*\+0x[0-9a-f]+\))"))) << err;
  EXPECT_NE(err.find("(_ZN3dtf3app6runCliEiPPc+0x"), std::string::npos) << err;
#endif
}

TEST_F(BidsCohort, KilledRunRestartsAndCompletesWithNothingPartial) {
  const fs::path out = scratch_ / "out";
  const std::string first = (out / "sub-01/ses-1/dwi/sub-01_ses-1_desc-fabricMetrics_dwi.json").string();
  const pid_t pid = ::fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    std::freopen("/dev/null", "w", stdout);
    std::freopen((scratch_ / "killed.log").c_str(), "w", stderr);
    ::execl(DTF_EXE, DTF_EXE, "bids", bids_.c_str(), out.c_str(), "participant", "--jobs", "1",
            "--figure-size", "128", static_cast<char*>(nullptr));
    ::_exit(127);
  }
  bool appeared = false;
  for (int i = 0; i < 1200 && !appeared; ++i) { // up to 60 s
    appeared = fs::exists(first);
    int st = 0;
    if (!appeared && ::waitpid(pid, &st, WNOHANG) == pid) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  ASSERT_TRUE(appeared) << readText(scratch_ / "killed.log");
  std::this_thread::sleep_for(std::chrono::milliseconds(300)); // into the next run's work
  ::kill(pid, SIGKILL);
  int st = 0;
  ::waitpid(pid, &st, 0);
  ASSERT_TRUE(WIFSIGNALED(st)) << "the run ended before it was killed: " << readText(scratch_ / "killed.log");
  checkNothingPartial(out);
  std::size_t docs = 0;
  for (const auto& e : fs::recursive_directory_iterator(out))
    docs += e.path().filename().string().find("fabricMetrics") != std::string::npos &&
            e.path().filename().string()[0] != '.';
  EXPECT_LT(docs, expectedRuns().size()) << "the kill came too late to interrupt anything";

  auto r =
      runDtfabric("bids " + q(bids_) + " " + q(out) + " participant --jobs 1 --figure-size 128", scratch_);
  EXPECT_EQ(r.exitCode, 2) << r.err;
  EXPECT_NE(r.err.find("skipped (complete and unchanged)"), std::string::npos) << r.err;
  EXPECT_TRUE(temporaries(out).empty()) << temporaries(out).front();
  checkNothingPartial(out);
  checkRunFiles(out, 128);
  r = runDtfabric("bids " + q(bids_) + " " + q(out) + " group", scratch_);
  EXPECT_EQ(r.exitCode, 0) << r.err;
  checkGroupTable(out);
}

// A worker process killed while it processes a run: that run is reported failed (the worker's signal), a
// new worker takes the remaining runs, and a rerun completes the killed run.
TEST_F(BidsCohort, KilledWorkerFailsItsRunOnly) {
  const fs::path out = scratch_ / "out", log = scratch_ / "parent.log";
  const pid_t pid = ::fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    std::freopen("/dev/null", "w", stdout);
    std::freopen(log.c_str(), "w", stderr);
    ::execl(DTF_EXE, DTF_EXE, "bids", bids_.c_str(), out.c_str(), "participant", "--jobs", "2",
            "--figure-size", "128", "--participant-label", "01", "07", "08", "09",
            static_cast<char*>(nullptr));
    ::_exit(127);
  }
  // The first line naming a worker: "  running sub-01/ses-1/dwi/sub-01_ses-1 (worker PID)".
  std::smatch m;
  std::string text;
  for (int i = 0; i < 1200; ++i) {
    text = readText(log);
    if (std::regex_search(text, m, std::regex("running (\\S+) \\(worker ([0-9]+)\\)"))) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ASSERT_FALSE(m.empty()) << text;
  const std::string victim = m[1];
  ::kill(static_cast<pid_t>(std::stoi(m[2])), SIGKILL);
  int st = 0;
  ::waitpid(pid, &st, 0);
  text = readText(log);
  ASSERT_TRUE(WIFEXITED(st)) << text;
  EXPECT_EQ(WEXITSTATUS(st), 2) << text;
  EXPECT_NE(text.find(victim + ": FAILED: the worker processing "), std::string::npos) << text;
  EXPECT_NE(text.find("ended by signal 9"), std::string::npos) << text;
  EXPECT_NE(text.find("5 runs in"), std::string::npos) << text; // sub-01 has two sessions
  EXPECT_NE(text.find("4 ok (0 unchanged), 1 failed"), std::string::npos) << text;
  checkNothingPartial(out);

  const auto r = runDtfabric("bids " + q(bids_) + " " + q(out) +
                                 " participant --jobs 2 --figure-size 128 --participant-label 01 07 08 09",
                             scratch_);
  EXPECT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.err.find("5 ok (4 unchanged), 0 failed"), std::string::npos) << r.err;
  EXPECT_TRUE(temporaries(out).empty());
}

TEST_F(BidsCohort, WebPagePerRunLinkedFromTheGroupReport) {
  const fs::path out = scratch_ / "out";
  auto r = runDtfabric("bids " + q(bids_) + " " + q(out) +
                           " participant --jobs 1 --figure-size 128 --web --web-size 64 --participant-label 07",
                       scratch_);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const fs::path dir = out / "sub-07/dwi";
  const std::string doc = readText(dir / "sub-07_desc-fabricMetrics_dwi.json");
  EXPECT_NE(doc.find("\"web_page\": \"sub-07_desc-fabricWeb_dwi/index.html\""), std::string::npos) << doc;
  for (const char* f : {"index.html", "data.js", "voxels.js", "viewer.js"})
    EXPECT_TRUE(fs::exists(dir / "sub-07_desc-fabricWeb_dwi" / f)) << f;
  EXPECT_TRUE(temporaries(out).empty());
  // Complete and unchanged: the rerun skips it.
  r = runDtfabric("bids " + q(bids_) + " " + q(out) +
                      " participant --jobs 1 --figure-size 128 --web --web-size 64 --participant-label 07",
                  scratch_);
  EXPECT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.err.find("1 ok (1 unchanged), 0 failed"), std::string::npos) << r.err;
  EXPECT_EQ(runDtfabric("bids " + q(bids_) + " " + q(out) + " participant --web-size 64", scratch_).exitCode, 1);

  r = runDtfabric("bids " + q(bids_) + " " + q(out) + " group --participant-label 07", scratch_);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  DTF_REQUIRE_TOOL("chromium");
  std::string log;
  const std::string check = chromiumSelfCheck(out / "group_report.html", scratch_, log);
  ASSERT_FALSE(check.empty()) << log;
  EXPECT_EQ(jsonList(check, "web"), std::set<std::string>{"sub-07/dwi/sub-07_desc-fabricWeb_dwi/index.html"})
      << check;
  EXPECT_NE(check.find("\"errors\":[]"), std::string::npos) << check;
  // The linked page itself loads from file:// without errors and shows its slice.
  const std::string page = chromiumSelfCheck(dir / "sub-07_desc-fabricWeb_dwi/index.html", scratch_, log);
  ASSERT_FALSE(page.empty()) << log;
  EXPECT_NE(page.find("\"errors\":[]"), std::string::npos) << page;
  EXPECT_NE(page.find("\"outside\":[]"), std::string::npos) << page;
  EXPECT_NE(page.find("\"loaded\":true"), std::string::npos) << page;
}

TEST_F(BidsCohort, SnakemakeWorkflowGivesTheSameGroupTable) {
  DTF_REQUIRE_TOOL("snakemake");
  const fs::path direct = scratch_ / "direct", viaSnakemake = scratch_ / "snakemake";
  auto r =
      runDtfabric("bids " + q(bids_) + " " + q(direct) + " participant --jobs 2 --figure-size 128", scratch_);
  EXPECT_EQ(r.exitCode, 2) << r.err;
  r = runDtfabric("bids " + q(bids_) + " " + q(direct) + " group", scratch_);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const std::string cmd = "snakemake -s " + q(test::sourceDir() / "app/workflow/Snakefile") + " -d " +
                          q(scratch_ / "work") + " --cores 2 --config bids_dir=" + q(bids_) +
                          " output_dir=" + q(viaSnakemake) + " dtfabric=" + q(DTF_EXE) +
                          " figure_size=128 >" + q(scratch_ / "snakemake.log") + " 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << workflowLogs(scratch_ / "snakemake.log", viaSnakemake);
  const std::string log = readText(scratch_ / "snakemake.log");
  // One job per participant and session (sub-01 has two sessions), then the group job.
  EXPECT_TRUE(std::regex_search(log, std::regex("participant\\s+10\\s"))) << log;
  EXPECT_EQ(readText(viaSnakemake / "group.tsv"), readText(direct / "group.tsv"));
  checkGroupTable(viaSnakemake);
  for (const char* f : {"group_report.html", "dataset_description.json"})
    EXPECT_TRUE(fs::exists(viaSnakemake / f)) << f;
}

// Folder names built to break a shell or a page: quotes of both kinds, `$(...)`, markup, brackets and (in the
// dataset's name) braces. The real workflow runs; nothing is executed from a name, every output is where it
// belongs, and the report shows the names as text.
TEST(BidsCli, SnakemakeWorkflowPassesHostileFolderNamesThrough) {
  DTF_REQUIRE_TOOL("snakemake");
  DTF_SHARED_FILE(dipy, "dipy_small");
  const fs::path dir = test::scratchDir();
  const fs::path bids = dir / "bids 'x\" $(touch PWNED) <b>{w}[1]";
  const fs::path out = dir / "out 'y\" $(touch PWNED) <i>[2]";
  fs::create_directories(bids);
  const std::string name = "<img src=x onerror=alert(1)> & \"co\"";
  std::ofstream(bids / "dataset_description.json")
      << nlohmann::json{{"Name", name}, {"BIDSVersion", "1.8.0"}}.dump(2) << "\n";
  copyRun(dipy, "small_64D", bids / "sub-01/dwi", "sub-01", ".nii");
  copyRun(dipy, "small_64D", bids / "sub-02/dwi", "sub-02", ".nii");
  fs::remove(bids / "sub-02/dwi/sub-02_dwi.bvec"); // fails; its message names the hostile path
  const std::string cmd = "cd " + shellWord(dir.string()) + " && snakemake -s " +
                          shellWord((test::sourceDir() / "app/workflow/Snakefile").string()) + " -d " +
                          shellWord((dir / "work").string()) + " --cores 2 --config " +
                          shellWord("bids_dir=" + bids.string()) + " " + shellWord("output_dir=" + out.string()) +
                          " " + shellWord(std::string("dtfabric=") + DTF_EXE) + " figure_size=64 >" +
                          shellWord((dir / "snakemake.log").string()) + " 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << workflowLogs(dir / "snakemake.log", out);
  const std::string log = readText(dir / "snakemake.log");
  for (const auto& e : fs::recursive_directory_iterator(dir))
    EXPECT_NE(e.path().filename(), "PWNED") << e.path();
  EXPECT_FALSE(fs::exists(fs::current_path() / "PWNED"));
  EXPECT_FALSE(fs::exists(test::sourceDir() / "PWNED"));

  for (const char* f : {"group.tsv", "group_report.html", "dataset_description.json", "logs/sub-01.done",
                        "logs/sub-02.done"})
    EXPECT_TRUE(fs::is_regular_file(out / f)) << f << "\n" << log;
  const nlohmann::json desc = nlohmann::json::parse(readText(out / "dataset_description.json"));
  EXPECT_EQ(desc.at("Name"), "dtfabric QC of " + name);
  EXPECT_EQ(desc.at("SourceDatasets").at(0).at("URL"), "file://" + bids.string());
  const nlohmann::json ok = nlohmann::json::parse(readText(out / "sub-01/dwi/sub-01_desc-fabricMetrics_dwi.json"));
  EXPECT_EQ(ok.at("status"), "ok");
  const nlohmann::json failed =
      nlohmann::json::parse(readText(out / "sub-02/dwi/sub-02_desc-fabricMetrics_dwi.json"));
  EXPECT_EQ(failed.at("status"), "failed");
  const std::string bvec = (bids / "sub-02/dwi/sub-02_dwi.bvec").string();
  EXPECT_NE(failed.at("message").get<std::string>().find(bvec), std::string::npos) << failed.dump();
  const auto tsv = readGroupTsv(out / "group.tsv");
  ASSERT_EQ(tsv.size(), 2u);
  EXPECT_EQ(tsv.at("sub-01").at("status"), "ok");
  EXPECT_EQ(tsv.at("sub-02").at("status"), "failed");

  // The report: every name is text. No element from the names; their escaped forms are there.
  const std::string html = readText(out / "group_report.html");
  for (const char* markup : {"<b>", "<i>", "<img src=x"})
    EXPECT_EQ(html.find(markup), std::string::npos) << markup;
  for (const char* text : {"&lt;img src=x onerror=alert(1)&gt; &amp; &quot;co&quot;", "&lt;b&gt;{w}[1]"})
    EXPECT_NE(html.find(text), std::string::npos) << text;
  // The detail overlay's data: valid JSON carrying the failed run's message exactly.
  const std::string open = "<script type=\"application/json\" id=\"dtf-data\">";
  const auto a = html.find(open), b = html.find("</script>", a);
  ASSERT_NE(a, std::string::npos);
  ASSERT_NE(b, std::string::npos);
  const nlohmann::json data = nlohmann::json::parse(html.substr(a + open.size(), b - a - open.size()));
  ASSERT_EQ(data.size(), 2u);
  int seen = 0;
  for (const auto& run : data)
    if (run.at("run") == "sub-02") {
      EXPECT_EQ(run.at("message"), failed.at("message"));
      ++seen;
    }
  EXPECT_EQ(seen, 1);
}

TEST(BidsCli, BadInputIsRefusedAndNothingInTheInputIsWritten) {
  const fs::path dir = test::scratchDir();
  auto mk = [](const fs::path& p, const std::string& text) {
    fs::create_directories(p.parent_path());
    std::ofstream(p) << text;
  };
  mk(dir / "plain/readme.txt", "not a dataset");
  mk(dir / "nodesc/sub-01/dwi/sub-01_dwi.nii", "x");
  mk(dir / "nosub/dataset_description.json", "{\"Name\": \"x\", \"BIDSVersion\": \"1.8.0\"}");
  mk(dir / "ok/dataset_description.json", "{\"Name\": \"x\", \"BIDSVersion\": \"1.8.0\"}");
  mk(dir / "ok/sub-01/dwi/sub-01_dwi.nii", "x");
  mk(dir / "ok/sub-01/dwi/sub-01_dwi.bval", "0 1000");
  mk(dir / "ok/sub-01/dwi/sub-01_dwi.bvec", "0 1\n0 0\n0 0");
  auto before = snapshot(dir);
  struct Case {
    std::string args, message;
  };
  const std::vector<Case> cases = {
      {q(dir / "plain") + " " + q(dir / "o1") + " participant", "dataset_description.json is missing"},
      {q(dir / "nosub") + " " + q(dir / "o1") + " participant", "no sub-<label> folder"},
      {q(dir / "absent") + " " + q(dir / "o1") + " participant", "no such folder"},
      {q(dir / "plain/readme.txt") + " " + q(dir / "o1") + " participant", "not a folder"},
      {q(dir / "nodesc") + " " + q(dir / "o1") + " participant", "dataset_description.json is missing"},
      {q(dir / "ok") + " " + q(dir / "ok/derivatives/dtfabric") + " participant",
       "lies inside the BIDS dataset"},
      {q(dir / "ok") + " " + q(dir / "ok") + " group", "lies inside the BIDS dataset"},
      {q(dir / "ok") + " " + q(dir / "o1") + " participant --participant-label 02", "no participant 02"},
      {q(dir / "ok") + " " + q(dir / "o1") + " group --participant-label sub-01 sub-7", "no participant 7"},
      {q(dir / "ok") + " " + q(dir / "o1") + " participant --session-label A", "no session A"},
  };
  for (const auto& c : cases) {
    const auto r = runDtfabric("bids " + c.args, dir);
    EXPECT_EQ(r.exitCode, 2) << c.args << "\n" << r.err;
    EXPECT_NE(r.err.find(c.message), std::string::npos) << c.args << "\n" << r.err;
    EXPECT_EQ(r.err.find("unexpected"), std::string::npos) << r.err;
  }
  for (const auto& f : {"cli_stdout.txt", "cli_stderr.txt"})
    before.erase(f);
  auto after = snapshot(dir);
  for (const auto& f : {"cli_stdout.txt", "cli_stderr.txt"})
    after.erase(f);
  EXPECT_TRUE(before == after) << "an input folder changed";
  EXPECT_FALSE(fs::exists(dir / "o1"));
  EXPECT_EQ(runDtfabric("bids " + q(dir / "ok") + " " + q(dir / "o1") + " everything", dir).exitCode, 1);
  EXPECT_EQ(runDtfabric("bids " + q(dir / "ok"), dir).exitCode, 1);
  EXPECT_EQ(
      runDtfabric("bids " + q(dir / "ok") + " " + q(dir / "o1") + " participant --participant-label", dir)
          .exitCode,
      1);
}

} // namespace
