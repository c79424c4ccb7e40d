// SPDX-License-Identifier: GPL-3.0-or-later
// The stage a DWI load reports while it fits (the viewer's status bar shows it): the file and the share done.
#include "support/test_env.h"
#include "ui/session/tensor_input.h"

#include <gtest/gtest.h>
#include <string>
#include <vector>

namespace {

const std::string kDwi = (dtf::test::sourceDir() / "sample_data" / "dwi.nii.gz").string();
const std::string kTensors = (dtf::test::sourceDir() / "sample_data" / "brain_phantom.nii.gz").string();

} // namespace

TEST(TensorInputStage, DwiFitReportsItsFileAndRisingPercentageUpTo100) {
  std::vector<std::string> stages;
  dtf::session::TensorInputOptions in;
  in.quiet = true;
  in.onStage = [&](const std::string& s) { stages.push_back(s); };
  const auto loaded = dtf::session::loadTensorInput(kDwi, in);
  EXPECT_EQ(loaded.field.grid.dims, glm::ivec3(72, 72, 39));
  ASSERT_GE(stages.size(), 2u);
  const std::string prefix = "fitting tensors to " + kDwi + ": ";
  int last = -1;
  for (const auto& s : stages) {
    ASSERT_EQ(s.rfind(prefix, 0), 0u) << s;
    const int percent = std::stoi(s.substr(prefix.size()));
    EXPECT_GE(percent, last) << s;
    EXPECT_LE(percent, 100) << s;
    last = percent;
  }
  EXPECT_EQ(stages.back(), prefix + "100%");
}

TEST(TensorInputStage, TensorFileReportsNoFit) {
  std::vector<std::string> stages;
  dtf::session::TensorInputOptions in;
  in.quiet = true;
  in.onStage = [&](const std::string& s) { stages.push_back(s); };
  dtf::session::loadTensorInput(kTensors, in);
  EXPECT_TRUE(stages.empty());
}
