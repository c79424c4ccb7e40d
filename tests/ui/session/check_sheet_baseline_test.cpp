// SPDX-License-Identifier: GPL-3.0-or-later
// The orientation check's contact sheet (192-pixel panels, two rows) on the real DWI with its x axis negated
// in the table: the given row (threads cutting across the callosum and the corticospinal tracts) above the
// corrected one (threads running with them). The corrected row must reproduce the true table's row pixel for
// pixel (the same tensors up to float rounding), and the sheet is compared with its baseline (looked at when
// made).
#include "ui/session/check_run.h"
#include "io/diffusion/dwi.h"
#include "support/baseline.h"
#include "support/gl_test.h"

#include <cstdio>
#include <fstream>

using namespace dtf;

namespace {

class CheckSheet : public GlTest {};

constexpr int kPanel = 192;

// Mean absolute RGB difference between the panel rows `ra` of a and `rb` of b (rows below the header).
double rowDifference(const Image& a, int ra, const Image& b, int rb) {
  const session::SheetLayout l = session::sheetLayout(kPanel);
  double sum = 0;
  std::size_t n = 0;
  for (int y = 0; y < kPanel; ++y)
    for (int x = 0; x < a.width; ++x) {
      const std::uint8_t* p = a.pixel(x, l.panelTop(ra) + y);
      const std::uint8_t* q = b.pixel(x, l.panelTop(rb) + y);
      for (int c = 0; c < 3; ++c)
        sum += std::abs(int(p[c]) - int(q[c]));
      n += 3;
    }
  return sum / double(n);
}

TEST_F(CheckSheet, FlippedTableAgainstItsCorrection) {
  DTF_SHARED_FILE(dwi, "iu_prisma_dwi/dwi.nii.gz");
  const auto dir = dwi.parent_path();
  const auto scratch = test::scratchDir();
  // The table with its x row negated.
  const auto bvecs = io::readBvecs((dir / "dwi.bvec").string());
  {
    std::ofstream os(scratch / "flipx.bvec");
    for (int row = 0; row < 3; ++row) {
      for (std::size_t n = 0; n < bvecs.size(); ++n)
        os << (n ? " " : "") << (row == 0 ? -bvecs[n][row] : bvecs[n][row]);
      os << "\n";
    }
  }
  session::CheckRequest req;
  req.input = dwi.string();
  req.bval = (dir / "dwi.bval").string();
  req.mask = (dir / "derived/mask.nii.gz").string();
  req.bvec = (scratch / "flipx.bvec").string();
  const session::CheckRun flipped = session::runCheck(req);
  ASSERT_EQ(flipped.report.verdict, surfaces::Verdict::Corrected);
  ASSERT_EQ(flipped.report.correction.name(), "-x y z");
  const auto rows = session::sheetRows(flipped.report, 2);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[1], flipped.report.best);
  const Image sheet = session::renderContactSheet(flipped, rows, kPanel);

  req.bvec = (dir / "dwi.bvec").string();
  const session::CheckRun truth = session::runCheck(req);
  ASSERT_EQ(truth.report.verdict, surfaces::Verdict::Ok);
  const Image trueSheet = session::renderContactSheet(truth, {0}, kPanel);

  ASSERT_EQ(sheet.width, 3 * kPanel);
  ASSERT_EQ(sheet.height, session::sheetLayout(kPanel).panelTop(2) - session::sheetLayout(kPanel).label);
  const double corrected = rowDifference(sheet, 1, trueSheet, 0);
  const double given = rowDifference(sheet, 0, trueSheet, 0);
  std::printf("mean |RGB| difference from the true table's panels: corrected row %.3f, given row %.3f\n",
              corrected, given);
  EXPECT_LT(corrected, 0.5);
  EXPECT_GT(given, 10 * corrected + 2.0);
  test::compareToBaseline("check_sheet_flipx", sheet);
}

} // namespace
