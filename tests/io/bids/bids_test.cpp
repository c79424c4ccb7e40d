// SPDX-License-Identifier: GPL-3.0-or-later
// BIDS dataset scanning, derivative naming, the JSON documents (io/formats/json.h) and the group report's outlier rule
// (io/bids/bids.h, io/bids/bids_report.h), on small trees of empty files and hand-made rows.
#include "io/bids/bids.h"
#include "io/bids/bids_report.h"
#include "io/formats/json.h"
#include "io/model/error.h"
#include "support/test_env.h"

#include <cmath>
#include <fstream>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace {

namespace fs = std::filesystem;
using namespace dtf;

void touch(const fs::path& p, const std::string& text = "x") {
  fs::create_directories(p.parent_path());
  std::ofstream(p) << text;
}

fs::path smallDataset(const fs::path& root) {
  touch(root / "dataset_description.json", "{\"Name\": \"tiny study\", \"BIDSVersion\": \"1.8.0\"}");
  for (const std::string stem : {"sub-01/ses-A/dwi/sub-01_ses-A_acq-b2500_run-1",
                                 "sub-01/ses-B/dwi/sub-01_ses-B", "sub-02/dwi/sub-02_dir-AP"}) {
    touch(root / (stem + "_dwi.nii.gz"));
    touch(root / (stem + "_dwi.bval"));
    touch(root / (stem + "_dwi.bvec"));
  }
  touch(root / "sub-03/dwi/sub-03_dwi.nii");
  touch(root / "sub-03/dwi/sub-03_dwi.bval");              // no bvec
  touch(root / "sub-04/anat/sub-04_T1w.nii.gz");           // a participant without diffusion data
  touch(root / "sub-02/dwi/sub-02_dir-AP_desc-x_dwi.nii"); // desc- is not a raw entity
  return root;
}

TEST(Bids, ScansRunsWithEntitiesAndNamesDerivatives) {
  const fs::path root = smallDataset(test::scratchDir() / "ds");
  const io::BidsDataset ds = io::scanBidsDataset(root.string());
  EXPECT_EQ(ds.name, "tiny study");
  EXPECT_EQ(ds.subjects, (std::vector<std::string>{"01", "02", "03", "04"}));
  ASSERT_EQ(ds.runs.size(), 5u);
  EXPECT_EQ(ds.runs[0].relDir, "sub-01/ses-A/dwi");
  EXPECT_EQ(ds.runs[0].stem, "sub-01_ses-A_acq-b2500_run-1");
  EXPECT_EQ(ds.runs[0].session, "A");
  EXPECT_TRUE(ds.runs[0].problem.empty()) << ds.runs[0].problem;
  EXPECT_EQ(io::derivativeName(ds.runs[0], "fabricAxial", "dwi", ".png"),
            "sub-01_ses-A_acq-b2500_run-1_desc-fabricAxial_dwi.png");
  EXPECT_EQ(ds.runs[1].stem, "sub-01_ses-B");
  // sub-02: the valid run and the one carrying desc-.
  EXPECT_EQ(ds.runs[2].stem, "sub-02_dir-AP");
  EXPECT_TRUE(ds.runs[2].problem.empty());
  EXPECT_NE(ds.runs[3].problem.find("desc-"), std::string::npos) << ds.runs[3].problem;
  EXPECT_EQ(ds.runs[4].subject, "03");
  EXPECT_NE(ds.runs[4].problem.find("no gradient file"), std::string::npos) << ds.runs[4].problem;
  EXPECT_NE(ds.runs[4].problem.find("sub-03_dwi.bvec"), std::string::npos);
}

TEST(Bids, SelectsLabelsAndRejectsUnknownOnes) {
  const fs::path root = smallDataset(test::scratchDir() / "ds");
  const io::BidsDataset ds = io::scanBidsDataset(root.string());
  EXPECT_EQ(io::selectRuns(ds, {"sub-01"}, {}).size(), 2u);
  EXPECT_EQ(io::selectRuns(ds, {"01", "02"}, {"B"}).size(), 1u);
  EXPECT_EQ(io::selectRuns(ds, {}, {}).size(), 5u);
  EXPECT_THROW(io::selectRuns(ds, {"99"}, {}), InputError);
  try {
    io::selectRuns(ds, {"01", "07"}, {});
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no participant 07"), std::string::npos) << e.what();
  }
  EXPECT_THROW(io::selectRuns(ds, {"01"}, {"Z"}), InputError);
}

TEST(Bids, RefusesWhatIsNotBidsAndOutputsInsideTheInput) {
  const fs::path dir = test::scratchDir();
  EXPECT_THROW(io::scanBidsDataset((dir / "absent").string()), InputError);
  touch(dir / "file.txt");
  EXPECT_THROW(io::scanBidsDataset((dir / "file.txt").string()), InputError);
  touch(dir / "nodesc/sub-01/dwi/sub-01_dwi.nii");
  try {
    io::scanBidsDataset((dir / "nodesc").string());
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("dataset_description.json is missing"), std::string::npos);
  }
  touch(dir / "nosub/dataset_description.json", "{}");
  EXPECT_THROW(io::scanBidsDataset((dir / "nosub").string()), InputError);
  touch(dir / "badjson/dataset_description.json", "not json");
  EXPECT_THROW(io::scanBidsDataset((dir / "badjson").string()), InputError);

  const fs::path root = smallDataset(dir / "ds");
  EXPECT_THROW(io::refuseOutputInsideInput(root.string(), (root / "derivatives/dtfabric").string()),
               InputError);
  EXPECT_THROW(io::refuseOutputInsideInput(root.string(), root.string() + "/"), InputError);
  EXPECT_THROW(io::refuseOutputInsideInput(root.string(), dir.string()), InputError);
  EXPECT_NO_THROW(io::refuseOutputInsideInput(root.string(), (dir / "ds-out").string()));
  EXPECT_NO_THROW(
      io::refuseOutputInsideInput(root.string(), (dir / "ds2").string())); // a prefix, not a parent
}

TEST(Bids, JsonDocumentsRoundTripAndHashes) {
  nlohmann::ordered_json j;
  j["message"] = "a \"quoted\"\tline\nwith\\slash, <b>, caf\u00e9 \u6f22";
  j["fa"] = 0.4463614;
  j["missing"] = std::nan("");
  j["flag"] = true;
  j["count"] = std::size_t{1234567};
  const std::string text = io::jsonText(j, 2);
  EXPECT_NE(text.find("\"missing\": null"), std::string::npos) << text; // NaN is written as null
  EXPECT_NE(text.find("\"count\": 1234567\n"), std::string::npos) << text;
  const nlohmann::ordered_json k = io::parseJson(text, "test");
  EXPECT_EQ(io::jsonString(k, "message"), j["message"].get<std::string>());
  EXPECT_DOUBLE_EQ(io::jsonNumber(k, "fa"), 0.4463614);
  EXPECT_TRUE(std::isnan(io::jsonNumber(k, "missing")));
  EXPECT_TRUE(std::isnan(io::jsonNumber(k, "message")));
  EXPECT_TRUE(std::isnan(io::jsonNumber(k, "absent")));
  EXPECT_EQ(io::jsonString(k, "fa"), "");
  EXPECT_EQ(k["flag"], true);
  EXPECT_EQ(io::jsonNumber(k, "count"), 1234567);
  std::vector<std::string> keys;
  for (const auto& [key, v] : k.items())
    keys.push_back(key);
  EXPECT_EQ(keys, (std::vector<std::string>{"message", "fa", "missing", "flag", "count"})); // written order
  // Not an object: the accessors give nothing instead of throwing.
  EXPECT_EQ(io::jsonString(io::parseJson("[1, 2]", "x"), "a"), "");
  EXPECT_TRUE(std::isnan(io::jsonNumber(io::parseJson("\"s\"", "x"), "a")));
  // Bytes that are not UTF-8 (possible in a file name) are replaced, not fatal.
  EXPECT_EQ(io::jsonText(nlohmann::ordered_json("a\xff" "b")), "\"a\xef\xbf\xbd" "b\"");
  // Malformed text names its origin.
  for (const char* bad : {"{\"a\": 1", "{\"a\": 1,}", "{'a': 1}", "{\"a\": NaN}", "{\"a\": 1} x", ""}) {
    SCOPED_TRACE(bad);
    try {
      io::parseJson(bad, "doc.json");
      ADD_FAILURE() << "accepted";
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()).rfind("doc.json: not valid JSON (", 0), 0u) << e.what();
    }
  }

  const fs::path dir = test::scratchDir();
  touch(dir / "a", "123456789");
  EXPECT_EQ(io::fileHash((dir / "a").string()), "crc32:cbf43926:9"); // the CRC-32 check value
  EXPECT_TRUE(io::writeTextIfChanged((dir / "b").string(), "one"));
  EXPECT_FALSE(io::writeTextIfChanged((dir / "b").string(), "one"));
  EXPECT_TRUE(io::writeTextIfChanged((dir / "b").string(), "two"));
}

io::GroupRow row(const std::string& run, double fa, bool ok = true) {
  io::GroupRow r;
  r.participant = run.substr(0, 6);
  r.run = run;
  r.ok = ok;
  r.verdict = ok ? "ok" : "";
  r.metrics.assign(io::groupMetricColumns().size(), std::nan(""));
  r.metrics[0] = fa; // fa_wm_mean
  return r;
}

TEST(BidsReport, ModifiedZScoreFlagsOutliers) {
  // Median 0.45, absolute deviations {0.01, 0, 0.02, 0.01, 0.02, 0.15}: MAD 0.015, so the last row's
  // z = 0.6745 * 0.15 / 0.015 = 6.7 (flagged) and 0.02 gives 0.9 (not).
  std::vector<io::GroupRow> rows = {row("sub-01", 0.44),       row("sub-02", 0.45), row("sub-03", 0.47),
                                    row("sub-04", 0.46),       row("sub-05", 0.43), row("sub-06", 0.60),
                                    row("sub-07", 0.10, false)};
  io::flagOutliers(rows);
  for (std::size_t i = 0; i < rows.size(); ++i)
    EXPECT_EQ(rows[i].outliers.size(), i == 5 ? 1u : 0u) << rows[i].run;
  EXPECT_EQ(rows[5].outliers[0], "fa_wm_mean");

  // MAD 0 (four equal): the mean absolute deviation (0.2 / 5 = 0.04) scales: z = 0.2 / (1.2533 * 0.04) = 4.
  std::vector<io::GroupRow> same = {row("a", 0.4), row("b", 0.4), row("c", 0.4), row("d", 0.4),
                                    row("e", 0.6)};
  io::flagOutliers(same);
  EXPECT_EQ(same[4].outliers.size(), 1u);
  EXPECT_TRUE(same[0].outliers.empty());
  // Within 5% of the median: never flagged, however small the MAD.
  std::vector<io::GroupRow> close = {row("a", 0.4), row("b", 0.4), row("c", 0.4), row("d", 0.4),
                                     row("e", 0.41)};
  io::flagOutliers(close);
  EXPECT_TRUE(close[4].outliers.empty());
  // Fewer than five rows: nothing.
  std::vector<io::GroupRow> few = {row("a", 0.4), row("b", 0.4), row("c", 0.4), row("d", 0.9)};
  io::flagOutliers(few);
  EXPECT_TRUE(few[3].outliers.empty());
}

TEST(BidsReport, TsvAndHtmlCarryEveryRowAndFlag) {
  std::vector<io::GroupRow> rows = {row("sub-01_dwi", 0.44), row("sub-02_dwi", 0.1, false)};
  rows[1].message = "sub-02_dwi.nii.gz: <truncated>";
  rows[0].verdict = "corrected";
  rows[0].correction = "-x y z";
  rows[0].figures.push_back({"axial", "sub-01/dwi/sub-01_desc-fabricAxial_dwi.png"});
  const std::string tsv = io::groupTsv(rows);
  EXPECT_EQ(
      tsv.substr(0, tsv.find('\n')),
      "participant_id\tsession_id\trun\tstatus\tcheck_verdict\tcheck_correction\tfa_wm_mean\tfa_wm_median\t"
      "md_wm_mean\tmd_wm_median\twm_voxels\tbrain_voxels\twm_fraction\tcheck_score_given\tcheck_score_best\t"
      "check_margin\toutliers\tmessage");
  EXPECT_NE(tsv.find("sub-01\tn/a\tsub-01_dwi\tok\tcorrected\t-x y z\t0.44\t"), std::string::npos) << tsv;
  EXPECT_NE(tsv.find("\tfailed\tn/a\tn/a\t"), std::string::npos) << tsv;
  const std::string html = io::groupReportHtml(rows, "t<>", "gen");
  EXPECT_NE(html.find("<title>t&lt;&gt;</title>"), std::string::npos);
  EXPECT_NE(html.find("&lt;truncated&gt;"), std::string::npos);
  EXPECT_EQ(html.find("<truncated>"), std::string::npos);
  EXPECT_NE(html.find("src=\"sub-01/dwi/sub-01_desc-fabricAxial_dwi.png\""), std::string::npos);
  EXPECT_NE(html.find("id=\"list-failed\""), std::string::npos);
  EXPECT_EQ(html.find("http://"), std::string::npos); // nothing fetched from a server
  EXPECT_EQ(html.find("https://"), std::string::npos);
}

} // namespace
