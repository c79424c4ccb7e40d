// SPDX-License-Identifier: GPL-3.0-or-later
// Tract colouring and groups in the viewer scene (app/viewer/viewer.h), headless: the AFQ .trx's two
// arcuate bundles shown or hidden by group, and the dpsv.trx tracts coloured by a per-point value through
// the tract colour map, checked against the library (Polylines::subset, tractValueColour). No volume is
// loaded, so every streamline is drawn (the near-surface selection's carrying of per-point data is tested
// with surfaces/analyses/near_surface.h).
#include "app/viewer/viewer.h"
#include "io/model/error.h"
#include "render/tract_renderer.h"
#include "support/gl_test.h"
#include "ui/session/tract_files.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <set>
#include <thread>

using namespace dtf;

namespace {

using Clock = std::chrono::steady_clock;

struct Scene {
  app::ViewerScene scene{"fa=0.3"};
  void converge() {
    const auto t0 = Clock::now();
    do {
      scene.update();
      scene.render(256, 256);
      if (!scene.settled()) std::this_thread::sleep_for(std::chrono::milliseconds(5));
      ASSERT_LT(std::chrono::duration<double>(Clock::now() - t0).count(), 120.0) << "did not settle";
    } while (!scene.settled());
    scene.update();
    scene.render(256, 256);
  }
  std::string lastError() const {
    return scene.state().errorChain.empty() ? "" : scene.state().errorChain.back();
  }
};

const TractGroup& group(const Polylines& l, const std::string& name) {
  for (const auto& g : l.groups)
    if (g.name == name) return g;
  throw InputError("no group " + name);
}

} // namespace

TEST(ViewTractColouring, GroupsShowOnlyTheirStreamlines) {
  DTF_GL_TEST_SETUP();
  DTF_SHARED_FILE(afq, "niivue_tracts/afq_tractography.trx");
  const Polylines all = session::readTracts(afq.string());
  const Polylines left = all.subset(group(all, "ARC_L").lines);
  ASSERT_EQ(left.lineCount(), 486u);
  Scene s;
  s.scene.apply(session::LoadTracts{afq.string()});
  s.converge();
  ASSERT_EQ(s.lastError(), "");
  EXPECT_EQ(s.scene.state().tractGroupNames, (std::vector<std::string>{"ARC_L", "ARC_R"}));
  EXPECT_EQ(s.scene.state().tractsShownLines, 508u) << "no surface: every streamline";

  session::SetTractGroups onlyLeft;
  onlyLeft.all = false;
  onlyLeft.shown = {"ARC_L"};
  s.scene.apply(onlyLeft);
  s.converge();
  ASSERT_EQ(s.lastError(), "");
  EXPECT_EQ(s.scene.state().tractGroupShown, (std::vector<char>{1, 0}));
  ASSERT_NE(s.scene.shownTracts(), nullptr);
  EXPECT_EQ(s.scene.shownTracts()->lineCount(), 486u) << "hiding ARC_R leaves ARC_L";
  EXPECT_EQ(s.scene.shownTracts()->points, left.points) << "ARC_L's streamlines, in file order";
  EXPECT_EQ(s.scene.state().tractsShownLines, 486u);
  EXPECT_EQ(s.scene.state().tractCount, 508u) << "analysis and saving keep every streamline";

  session::SetTractGroups none;
  none.all = false;
  s.scene.apply(none);
  s.converge();
  EXPECT_EQ(s.scene.shownTracts()->lineCount(), 0u);
  s.scene.apply(session::SetTractGroups{});
  s.converge();
  EXPECT_EQ(s.scene.state().tractsShownLines, 508u);

  // An unknown group is an error naming the file and the groups; the choice on screen stays.
  session::SetTractGroups wrong;
  wrong.all = false;
  wrong.shown = {"CST_L"};
  s.scene.apply(wrong);
  EXPECT_NE(s.lastError().find("no group 'CST_L' (groups: 'ARC_L', 'ARC_R')"), std::string::npos)
      << s.lastError();
  EXPECT_EQ(s.scene.shownTracts()->lineCount(), 508u);
}

TEST(ViewTractColouring, ValueColoursFollowTheColourMapAndItsRange) {
  DTF_GL_TEST_SETUP();
  DTF_SHARED_FILE(dpsv, "niivue_tracts/dpsv.trx");
  const Polylines all = session::readTracts(dpsv.string());
  const std::vector<float> z = all.valuesPerPoint("z");
  ASSERT_EQ(z.size(), all.points.size());
  const auto [zlo, zhi] = std::minmax_element(z.begin(), z.end());
  Scene s;
  s.scene.apply(session::LoadTracts{dpsv.string()});
  s.converge();
  ASSERT_EQ(s.lastError(), "");
  const auto& names = s.scene.state().tractDataNames;
  EXPECT_NE(std::find(names.begin(), names.end(), "z"), names.end());
  EXPECT_NE(std::find(names.begin(), names.end(), "DataSetID"), names.end()) << "per-streamline data too";
  ASSERT_NE(s.scene.displayedTracts(), nullptr);
  EXPECT_TRUE(s.scene.displayedTracts()->colours.empty()) << "DEC by default";

  s.scene.apply(session::SetTractColour{"z", {}});
  s.converge();
  ASSERT_EQ(s.lastError(), "");
  EXPECT_EQ(s.scene.state().tractColourBy, "z");
  EXPECT_DOUBLE_EQ(s.scene.state().tractColourLo, *zlo);
  EXPECT_DOUBLE_EQ(s.scene.state().tractColourHi, *zhi);
  const render::DisplayTracts* d = s.scene.displayedTracts();
  ASSERT_NE(d, nullptr);
  ASSERT_EQ(d->colours.size(), d->points.size()) << "a colour per drawn point";
  // Each drawn point's colour is the colour map at its z (the display keeps original points).
  std::size_t checked = 0, distinct = 0;
  std::set<std::uint32_t> seen;
  for (std::size_t i = 0; i < d->points.size(); i += 97) {
    const auto it = std::find(all.points.begin(), all.points.end(), d->points[i]);
    ASSERT_NE(it, all.points.end());
    const float v = z[static_cast<std::size_t>(it - all.points.begin())];
    const glm::vec3 want = render::tractValueColour((v - *zlo) / (*zhi - *zlo));
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(d->colours[i][c], want[c] * 255.0f, 1.5f) << "point " << i;
    EXPECT_EQ(d->colours[i][3], 255);
    ++checked;
    const glm::u8vec4 col = d->colours[i];
    distinct += seen.insert(std::uint32_t(col.x) << 16 | std::uint32_t(col.y) << 8 | col.z).second;
  }
  EXPECT_GT(checked, 100u);
  EXPECT_GT(distinct, 20u) << "z varies along the tracts: many colours";

  // A chosen range: values below it take the low end of the map.
  s.scene.apply(session::SetTractColour{"z", std::make_pair(double(*zhi) - 1.0, double(*zhi))});
  s.converge();
  EXPECT_DOUBLE_EQ(s.scene.state().tractColourLo, *zhi - 1.0);
  const glm::vec3 low = render::tractValueColour(0.0f);
  const render::DisplayTracts* r = s.scene.displayedTracts();
  std::size_t atLow = 0;
  for (const auto& c : r->colours)
    atLow += std::abs(c.x - low.x * 255) < 1.5f && std::abs(c.y - low.y * 255) < 1.5f &&
             std::abs(c.z - low.z * 255) < 1.5f;
  EXPECT_GT(atLow, r->colours.size() / 2) << "most of the tracts lie below the top 1 mm";

  // Unknown data: an error naming the file and the data; DEC restores the default.
  s.scene.apply(session::SetTractColour{"fa", {}});
  EXPECT_NE(s.lastError().find("no per-point or per-streamline data 'fa'"), std::string::npos)
      << s.lastError();
  s.scene.apply(session::SetTractColour{});
  s.converge();
  EXPECT_TRUE(s.scene.displayedTracts()->colours.empty());
  EXPECT_EQ(s.scene.state().tractColourBy, "");
}
