// SPDX-License-Identifier: GPL-3.0-or-later
// The viewer script parser (app/viewer/view_script.h): every command, comments, and FILE:LINE errors.
#include "app/viewer/view_script.h"
#include "io/model/error.h"
#include "surfaces/tracking/tracking_parameters.h"
#include "ui/session/tract_colouring.h"
#include "support/test_env.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <gtest/gtest.h>

using namespace dtf;
using namespace dtf::app;

namespace {
template <typename T> const T& actionAt(const ViewScript& s, std::size_t i) {
  const auto* a = std::get_if<session::Action>(&s.steps.at(i).command);
  EXPECT_NE(a, nullptr) << "step " << i << " is not a ui action";
  return std::get<T>(*a);
}

std::string parseError(const std::string& text) {
  try {
    parseViewScript(text, "demo.txt");
  } catch (const UsageError& e) {
    return e.what();
  }
  return "(no error)";
}
} // namespace

TEST(ViewScript, ParsesEveryCommand) {
  const std::string text = "# a figure\n"
                           "load /data/my brain.nii.gz\n"
                           "surface slice=coronal:12\n"
                           "fa 0.3   # threshold\n"
                           "\n"
                           "slice sagittal 7\n"
                           "key PgUp\n"
                           "rotate 40 -10\n"
                           "pan 5 6\n"
                           "zoom 2\n"
                           "view anterior\n"
                           "split on\n"
                           "linked off\n"
                           "neurological on\n"
                           "set k 0.2\n"
                           "set colour engineering\n"
                           "set lighting off\n"
                           "wait 5\n"
                           "screenshot out/a.png\n"
                           "screenshot-scene out/b.png\n"
                           "camera-save cam.txt\n"
                           "camera-load cam.txt\n"
                           "quit\n";
  const ViewScript s = parseViewScript(text, "fig.txt");
  ASSERT_EQ(s.steps.size(), 21u);
  EXPECT_EQ(s.file, "fig.txt");
  EXPECT_EQ(s.steps[0].line, 2);
  EXPECT_EQ(actionAt<session::LoadFile>(s, 0).path, "/data/my brain.nii.gz"); // paths keep their spaces
  EXPECT_EQ(actionAt<session::SetSurfaceSpec>(s, 1).text, "slice=coronal:12");
  EXPECT_DOUBLE_EQ(actionAt<session::SetFaThreshold>(s, 2).value, 0.3);
  EXPECT_EQ(actionAt<session::SetSlice>(s, 3).axis, 2);
  EXPECT_EQ(actionAt<session::SetSlice>(s, 3).index, 7);
  EXPECT_EQ(std::get<session::Key>(s.steps[4].command), session::Key::PageUp);
  EXPECT_DOUBLE_EQ(actionAt<session::Rotate>(s, 5).dx, 40);
  EXPECT_DOUBLE_EQ(actionAt<session::Rotate>(s, 5).dy, -10);
  EXPECT_DOUBLE_EQ(actionAt<session::Pan>(s, 6).dy, 6);
  EXPECT_DOUBLE_EQ(actionAt<session::Zoom>(s, 7).factor, 2);
  EXPECT_EQ(actionAt<session::SetView>(s, 8).view, render::StandardView::Anterior);
  EXPECT_TRUE(actionAt<session::SetSplit>(s, 9).on);
  EXPECT_FALSE(actionAt<session::SetLinkedCameras>(s, 10).on);
  EXPECT_TRUE(actionAt<session::SetNeurological>(s, 11).on);
  EXPECT_EQ(std::get<ScriptSetParam>(s.steps[12].command).name, "blend-k");
  EXPECT_EQ(std::get<ScriptWait>(s.steps[15].command).frames, 5);
  EXPECT_FALSE(actionAt<session::Screenshot>(s, 16).sceneOnly);
  EXPECT_TRUE(actionAt<session::Screenshot>(s, 17).sceneOnly);
  EXPECT_EQ(actionAt<session::Screenshot>(s, 17).path, "out/b.png");
  EXPECT_EQ(actionAt<session::LoadCamera>(s, 19).path, "cam.txt");
  EXPECT_TRUE(std::holds_alternative<session::Quit>(std::get<session::Action>(s.steps[20].command)));
  EXPECT_EQ(s.steps[20].line, 23);
}

TEST(ViewScript, SetParamsApplyToFabricParams) {
  const ViewScript s =
      parseViewScript("set k 0.2\nset colour engineering\nset lighting off\nset iterations 7\n"
                      "set lod 3.5\nset silhouette on\nset frame-iterations 5\nset fa-floor 0.1\n",
                      "p.txt");
  render::FabricParams p;
  p.silhouette = false;
  for (const auto& step : s.steps)
    applyScriptParam(p, std::get<ScriptSetParam>(step.command));
  EXPECT_DOUBLE_EQ(p.k, 0.2);
  EXPECT_EQ(p.colour, render::ColourMode::Engineering);
  EXPECT_FALSE(p.lighting);
  EXPECT_EQ(p.stillMaxIterations, 7) << "iterations is the cap of `render --iterations`";
  EXPECT_EQ(p.iterations, 5);
  EXPECT_FLOAT_EQ(p.faFloor, 0.1f);
  EXPECT_DOUBLE_EQ(p.lod, 3.5);
  EXPECT_TRUE(p.silhouette);
}

TEST(ViewScript, TractsLineLoadsStreamlines) {
  const ViewScript s = parseViewScript("tracts /data/cst left.tck\n", "t.txt");
  ASSERT_EQ(s.steps.size(), 1u);
  EXPECT_EQ(actionAt<session::LoadTracts>(s, 0).path, "/data/cst left.tck");
  EXPECT_NE(parseError("tracts").find("usage: tracts PATH"), std::string::npos);
}

TEST(ViewScript, FabricAlongLineSwitchesTheFabricToTheTracts) {
  const ViewScript s = parseViewScript("fabric-along on 3.5\nfabric-along off\n", "a.txt");
  ASSERT_EQ(s.steps.size(), 2u);
  EXPECT_EQ(actionAt<session::SetFabricAlong>(s, 0).on, std::optional<bool>(true));
  EXPECT_EQ(actionAt<session::SetFabricAlong>(s, 0).mm, std::optional<double>(3.5));
  EXPECT_EQ(actionAt<session::SetFabricAlong>(s, 1).on, std::optional<bool>(false));
  EXPECT_FALSE(actionAt<session::SetFabricAlong>(s, 1).mm.has_value());
  EXPECT_NE(parseError("fabric-along on 0").find("(0, 1000]"), std::string::npos);
  EXPECT_NE(parseError("fabric-along maybe").find("fabric-along"), std::string::npos);
  EXPECT_NE(parseError("fabric-along").find("usage: fabric-along on|off [MM]"), std::string::npos);
}

TEST(ViewScript, ProbeLineTakesScenePixels) {
  const ViewScript s = parseViewScript("probe 10 20.5\n", "p.txt");
  ASSERT_EQ(s.steps.size(), 1u);
  EXPECT_DOUBLE_EQ(std::get<ScriptProbe>(s.steps[0].command).y, 20.5);
  EXPECT_NE(parseError("probe -1 3").find("non-negative"), std::string::npos);
}

TEST(ViewScript, ResizeLineTakesAWindowSize) {
  const ViewScript s = parseViewScript("resize 800x600\n", "r.txt");
  ASSERT_EQ(s.steps.size(), 1u);
  EXPECT_EQ(std::get<ScriptResize>(s.steps[0].command).width, 800);
  EXPECT_EQ(std::get<ScriptResize>(s.steps[0].command).height, 600);
  EXPECT_NE(parseError("resize 10x10").find("must lie between"), std::string::npos);
  EXPECT_NE(parseError("resize big").find("usage: resize WxH"), std::string::npos);
}

TEST(ViewScript, EmptyAndCommentOnlyScriptsHaveNoSteps) {
  EXPECT_TRUE(parseViewScript("", "e.txt").steps.empty());
  EXPECT_TRUE(parseViewScript("# only\n   \n\t# comments\r\n", "e.txt").steps.empty());
}

TEST(ViewScript, BadLinesNameFileAndLine) {
  EXPECT_EQ(parseError("fa 0.3\n\nfly away\n").rfind("demo.txt:3: unknown command 'fly'", 0), 0u)
      << parseError("fa 0.3\n\nfly away\n");
  EXPECT_NE(parseError("fa 1.5").find("demo.txt:1: fa threshold must lie in (0, 1)"), std::string::npos);
  EXPECT_NE(parseError("fa x").find("demo.txt:1: fa threshold: 'x' is not a number"), std::string::npos);
  EXPECT_NE(parseError("slice diagonal 3").find("demo.txt:1:"), std::string::npos);
  EXPECT_NE(parseError("slice axial 2.5").find("not an integer"), std::string::npos);
  EXPECT_NE(parseError("slice axial -1").find("must not be negative"), std::string::npos);
  EXPECT_NE(parseError("key F13").find("unknown key 'F13'"), std::string::npos);
  EXPECT_NE(parseError("rotate 1").find("usage: rotate DX DY"), std::string::npos);
  EXPECT_NE(parseError("zoom 0").find("zoom factor must lie in"), std::string::npos);
  EXPECT_NE(parseError("view upside-down").find("demo.txt:1:"), std::string::npos);
  EXPECT_NE(parseError("split maybe").find("split takes on or off"), std::string::npos);
  EXPECT_NE(parseError("set warp 3").find("unknown fabric parameter 'warp'"), std::string::npos);
  EXPECT_NE(parseError("set k 7").find("k must lie in"), std::string::npos);
  EXPECT_NE(parseError("set colour purple").find("colour takes medical, engineering or fibres"), std::string::npos);
  EXPECT_NE(parseError("wait -3").find("wait frames must lie in"), std::string::npos);
  EXPECT_NE(parseError("screenshot out.jpg").find("must end in .png"), std::string::npos);
  EXPECT_NE(parseError("screenshot").find("usage: screenshot [--force] PATH"), std::string::npos);
  EXPECT_NE(parseError("screenshot --force").find("usage: screenshot [--force] PATH"), std::string::npos);
  EXPECT_NE(parseError("camera-save --force  ").find("usage: camera-save [--force] PATH"), std::string::npos);
  EXPECT_NE(parseError("load").find("usage: load [layout=L] PATH"), std::string::npos);
  EXPECT_NE(parseError("quit now").find("usage: quit"), std::string::npos);
  EXPECT_NE(parseError("surface fa=2").find("demo.txt:1: fa threshold must lie in (0, 1)"),
            std::string::npos);
  EXPECT_NE(parseError(std::string("fa 0.3\nfa\0 0.2\n", 16)).find("demo.txt:2: NUL byte"),
            std::string::npos);
}

TEST(ViewScript, MissingFileIsAnInputError) {
  EXPECT_THROW(loadViewScript("/nonexistent/dir/script.txt"), InputError);
}

TEST(ViewScript, TractLinesParse) {
  const ViewScript s = parseViewScript("tracts-visible off\n"
                                       "tracts-near 2.5\n"
                                       "tract-width 3\n"
                                       "split tracts\n"
                                       "split phong\n"
                                       "track-cancel\n"
                                       "tracts-save out/my tracts.tck\n"
                                       "tracts-save --force out/t.trk\n"
                                       "agreement\n"
                                       "agreement 3 18\n",
                                       "t.txt");
  ASSERT_EQ(s.steps.size(), 10u);
  EXPECT_FALSE(actionAt<session::SetTractsVisible>(s, 0).on);
  EXPECT_DOUBLE_EQ(actionAt<session::SetTractsNear>(s, 1).mm, 2.5);
  EXPECT_DOUBLE_EQ(actionAt<session::SetTractWidth>(s, 2).px, 3.0);
  EXPECT_TRUE(actionAt<session::SetSplit>(s, 3).on);
  EXPECT_EQ(actionAt<session::SetSplit>(s, 3).mode, session::SecondPane::Tracts);
  EXPECT_EQ(actionAt<session::SetSplit>(s, 4).mode, session::SecondPane::Phong);
  actionAt<session::CancelTracking>(s, 5);
  EXPECT_EQ(actionAt<session::SaveTracts>(s, 6).path, "out/my tracts.tck");
  EXPECT_FALSE(actionAt<session::SaveTracts>(s, 6).force);
  EXPECT_EQ(actionAt<session::SaveTracts>(s, 7).path, "out/t.trk");
  EXPECT_TRUE(actionAt<session::SaveTracts>(s, 7).force);
  EXPECT_DOUBLE_EQ(actionAt<session::ComputeAgreement>(s, 8).nearMm, 2.0); // `dtfabric compare`'s defaults
  EXPECT_EQ(actionAt<session::ComputeAgreement>(s, 8).bins, 9);
  EXPECT_DOUBLE_EQ(actionAt<session::ComputeAgreement>(s, 9).nearMm, 3.0);
  EXPECT_EQ(actionAt<session::ComputeAgreement>(s, 9).bins, 18);
}

TEST(ViewScript, TrackLineTakesTheOptionsOfTheTrackCommand) {
  const ViewScript s = parseViewScript("track\n"
                                       "track from=slice:coronal:12 seeds=500 fa-stop=0.2 angle=45 step=0.5 "
                                       "min-length=10 max-length=100 seed=7 euler\n"
                                       "track from=sphere:1.5,-2,30,8 select=20\n"
                                       "track from=fa:0.4 per-voxel=2\n"
                                       "track from=slice:axial\n",
                                       "t.txt");
  const session::TrackRequest def = actionAt<session::TrackTracts>(s, 0).request;
  EXPECT_EQ(def.seeds, session::SeedKind::Surface);
  EXPECT_EQ(def.count, session::SeedCount::Select);
  EXPECT_EQ(def.number, 1000);
  EXPECT_DOUBLE_EQ(def.options.faStop, 0.15);
  EXPECT_TRUE(def.options.rk4);
  const session::TrackRequest a = actionAt<session::TrackTracts>(s, 1).request;
  EXPECT_EQ(a.seeds, session::SeedKind::Slice);
  EXPECT_EQ(a.sliceAxis, 1);
  EXPECT_EQ(a.sliceIndex, 12);
  EXPECT_EQ(a.count, session::SeedCount::Seeds);
  EXPECT_EQ(a.number, 500);
  EXPECT_DOUBLE_EQ(a.options.faStop, 0.2);
  EXPECT_DOUBLE_EQ(a.options.maxAngleDeg, 45);
  EXPECT_DOUBLE_EQ(a.options.stepMm, 0.5);
  EXPECT_DOUBLE_EQ(a.options.minLengthMm, 10);
  EXPECT_DOUBLE_EQ(a.options.maxLengthMm, 100);
  EXPECT_EQ(a.rngSeed, 7u);
  EXPECT_FALSE(a.options.rk4);
  const session::TrackRequest b = actionAt<session::TrackTracts>(s, 2).request;
  EXPECT_EQ(b.seeds, session::SeedKind::Sphere);
  EXPECT_EQ(b.centre, glm::dvec3(1.5, -2, 30));
  EXPECT_DOUBLE_EQ(b.radiusMm, 8);
  EXPECT_EQ(b.number, 20);
  const session::TrackRequest c = actionAt<session::TrackTracts>(s, 3).request;
  EXPECT_EQ(c.seeds, session::SeedKind::FaMask);
  EXPECT_DOUBLE_EQ(c.faMask, 0.4);
  EXPECT_EQ(c.count, session::SeedCount::PerVoxel);
  EXPECT_EQ(c.number, 2);
  EXPECT_EQ(actionAt<session::TrackTracts>(s, 4).request.sliceIndex, -1)
      << "no index: the viewer's current slice";
}

TEST(ViewScript, TractClipLinesParse) {
  const ViewScript s = parseViewScript("tracts-clip 4 -12.5\ntracts-clip 2\ntracts-clip 0\n", "t.txt");
  ASSERT_EQ(s.steps.size(), 3u);
  EXPECT_DOUBLE_EQ(actionAt<session::SetTractsClip>(s, 0).mm, 4.0);
  EXPECT_DOUBLE_EQ(actionAt<session::SetTractsClip>(s, 0).offsetMm, -12.5);
  EXPECT_DOUBLE_EQ(actionAt<session::SetTractsClip>(s, 1).mm, 2.0);
  EXPECT_DOUBLE_EQ(actionAt<session::SetTractsClip>(s, 1).offsetMm, 0.0)
      << "no depth: through the surface's centre";
  EXPECT_DOUBLE_EQ(actionAt<session::SetTractsClip>(s, 2).mm, 0.0);
  EXPECT_NE(parseError("tracts-clip -1").find("demo.txt:1: tracts-clip must lie in [0, 1000]"),
            std::string::npos);
  EXPECT_NE(parseError("tracts-clip 3 2000").find("tracts-clip depth must lie in [-1000, 1000]"),
            std::string::npos);
  EXPECT_NE(parseError("tracts-clip").find("usage: tracts-clip MM [DEPTH_MM]"), std::string::npos);
  EXPECT_NE(parseError("tracts-clip 1 2 3").find("usage: tracts-clip MM [DEPTH_MM]"), std::string::npos);
}

TEST(ViewScript, BadTractLinesNameTheProblem) {
  EXPECT_NE(parseError("tracts-near -1").find("demo.txt:1: tracts-near must lie in [0, 1000]"),
            std::string::npos);
  EXPECT_NE(parseError("tract-width 0").find("tract-width must lie in (0, 32]"), std::string::npos);
  EXPECT_NE(parseError("tracts-visible maybe").find("tracts-visible takes on or off"), std::string::npos);
  EXPECT_NE(parseError("tracts-save").find("usage: tracts-save [--force] [--selected [--as-group NAME]] PATH"),
            std::string::npos);
  EXPECT_NE(parseError("agreement 2 0").find("agreement bins must lie in 1..90"), std::string::npos);
  EXPECT_NE(parseError("agreement 1 2 3").find("usage: agreement"), std::string::npos);
  EXPECT_NE(parseError("track-cancel now").find("usage: track-cancel"), std::string::npos);
  EXPECT_NE(parseError("track from=moon").find("track: from=surface | slice"), std::string::npos);
  EXPECT_NE(parseError("track from=slice:diagonal").find("demo.txt:1:"), std::string::npos);
  EXPECT_NE(parseError("track from=sphere:1,2,3").find("from=sphere:X,Y,Z,R"), std::string::npos);
  EXPECT_NE(parseError("track from=sphere:1,2,3,0").find("radius must lie in"), std::string::npos);
  EXPECT_NE(parseError("track select=10 seeds=5").find("give one of select=, seeds=, per-voxel="),
            std::string::npos);
  EXPECT_NE(parseError("track per-voxel=2").find("per-voxel needs from=fa:T"), std::string::npos);
  EXPECT_NE(parseError("track select=0").find("select must lie in [1, 10^7]"), std::string::npos);
  EXPECT_NE(parseError("track angle=200").find("track: angle must lie in (0, 180] degrees, got 200"), std::string::npos);
  EXPECT_NE(parseError("track min-length=50 max-length=20").find("track: min-length 50 mm exceeds max-length 20 mm"), std::string::npos);
  EXPECT_NE(parseError("track warp=9").find("track: unknown option 'warp'"), std::string::npos);
  EXPECT_NE(parseError("track fast").find("track: expected KEY=VALUE, got 'fast'"), std::string::npos);
  EXPECT_NE(parseError("split sideways").find("split takes on or off (or colour, phong, tracts)"),
            std::string::npos);
}

TEST(ViewScript, OutputLinesTakeForceBeforeThePath) {
  const ViewScript s = parseViewScript("screenshot a b.png\nscreenshot --force out/a.png\n"
                                       "screenshot-scene --force  my shot.png\ncamera-save --force cam 1\n"
                                       "camera-save --forced.cam\n",
                                       "f.txt");
  ASSERT_EQ(s.steps.size(), 5u);
  EXPECT_FALSE(actionAt<session::Screenshot>(s, 0).force);
  EXPECT_EQ(actionAt<session::Screenshot>(s, 0).path, "a b.png");
  EXPECT_TRUE(actionAt<session::Screenshot>(s, 1).force);
  EXPECT_EQ(actionAt<session::Screenshot>(s, 1).path, "out/a.png");
  EXPECT_TRUE(actionAt<session::Screenshot>(s, 2).force);
  EXPECT_TRUE(actionAt<session::Screenshot>(s, 2).sceneOnly);
  EXPECT_EQ(actionAt<session::Screenshot>(s, 2).path, "my shot.png");
  EXPECT_TRUE(actionAt<session::SaveCamera>(s, 3).force);
  EXPECT_EQ(actionAt<session::SaveCamera>(s, 3).path, "cam 1");
  EXPECT_FALSE(actionAt<session::SaveCamera>(s, 4).force); // a path that merely starts with --force
  EXPECT_EQ(actionAt<session::SaveCamera>(s, 4).path, "--forced.cam");
}

namespace {
// The message of checkScriptOutputs, or "(no error)".
std::string outputError(const ViewScript& s, const std::vector<std::string>& inputs, bool force) {
  try {
    checkScriptOutputs(s, inputs, force);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}
} // namespace

TEST(ViewScript, ExistingOutputsNeedForceAndInputsAreNeverOutputs) {
  namespace fs = std::filesystem;
  const fs::path dir = dtf::test::scratchDir();
  const std::string shot = (dir / "old.png").string(), cam = (dir / "old.camera").string();
  const std::string volume = (dir / "brain.nii.gz").string(), tracts = (dir / "t.tck").string();
  const std::string script = (dir / "fig.txt").string();
  for (const auto& f : {shot, cam, volume, (dir / "brain.bval").string(), tracts, script})
    std::ofstream(f) << "x";
  const std::string fresh = (dir / "new.png").string();
  auto parse = [&](const std::string& text) { return parseViewScript(text, script); };

  EXPECT_EQ(
      outputError(parse("screenshot " + fresh + "\ncamera-save " + (dir / "new.camera").string()), {}, false),
      "(no error)");
  // An existing screenshot or camera file: FILE:LINE, the path, and how to force it.
  const std::string e1 = outputError(parse("fa 0.3\nscreenshot " + shot), {}, false);
  EXPECT_EQ(e1.rfind(script + ":2: " + shot + " exists (use --force", 0), 0u) << e1;
  const std::string e2 = outputError(parse("camera-save " + cam), {}, false);
  EXPECT_EQ(e2.rfind(script + ":1: " + cam + " exists (use --force", 0), 0u) << e2;
  // --force on the line or for the whole script lets them through.
  EXPECT_EQ(outputError(parse("screenshot --force " + shot + "\ncamera-save --force " + cam), {}, false),
            "(no error)");
  EXPECT_EQ(outputError(parse("screenshot " + shot + "\ncamera-save " + cam), {}, true), "(no error)");
  // Inputs are refused whatever --force says: the command line's, the script's own loads (and the DWI's
  // gradient tables beside them), tracts, and the script itself.
  const std::string png = (dir / "input.png").string();
  std::ofstream(png) << "x";
  for (const auto& [text, inputs] : std::vector<std::pair<std::string, std::vector<std::string>>>{
           {"screenshot --force " + png, {png}},
           {"load " + volume + "\ncamera-save --force " + volume, {}},
           {"load " + volume + "\ncamera-save --force " + (dir / "brain.bval").string(), {}},
           {"tracts " + tracts + "\ncamera-save --force " + tracts, {}},
           {"camera-save --force " + script, {}}}) {
    const std::string e = outputError(parse(text), inputs, true);
    EXPECT_NE(e.find("it is an input file"), std::string::npos) << text << "\n" << e;
    EXPECT_EQ(e.rfind(script + ":", 0), 0u) << e;
  }
}

TEST(ViewScript, TractColourAndGroupLinesParse) {
  const ViewScript s =
      parseViewScript("tracts-color z\ntracts-color fa 0.2 0.8\ntracts-color dec\ntracts-groups ARC_L\n"
                      "tracts-groups ARC_L,ARC_R\ntracts-groups all\ntracts-groups none\n",
                      "t.txt");
  ASSERT_EQ(s.steps.size(), 7u);
  EXPECT_EQ(actionAt<session::SetTractColour>(s, 0).value, "z");
  EXPECT_FALSE(actionAt<session::SetTractColour>(s, 0).range) << "no range: the value's min..max";
  EXPECT_EQ(actionAt<session::SetTractColour>(s, 1).value, "fa");
  ASSERT_TRUE(actionAt<session::SetTractColour>(s, 1).range);
  EXPECT_DOUBLE_EQ(actionAt<session::SetTractColour>(s, 1).range->first, 0.2);
  EXPECT_DOUBLE_EQ(actionAt<session::SetTractColour>(s, 1).range->second, 0.8);
  EXPECT_EQ(actionAt<session::SetTractColour>(s, 2).value, "") << "dec: direction colours";
  EXPECT_FALSE(actionAt<session::SetTractGroups>(s, 3).all);
  EXPECT_EQ(actionAt<session::SetTractGroups>(s, 3).shown, std::vector<std::string>{"ARC_L"});
  EXPECT_EQ(actionAt<session::SetTractGroups>(s, 4).shown, (std::vector<std::string>{"ARC_L", "ARC_R"}));
  EXPECT_TRUE(actionAt<session::SetTractGroups>(s, 5).all);
  EXPECT_FALSE(actionAt<session::SetTractGroups>(s, 6).all);
  EXPECT_TRUE(actionAt<session::SetTractGroups>(s, 6).shown.empty()) << "none hides every streamline";
  EXPECT_EQ(session::describe(std::get<session::Action>(s.steps[1].command)), "SetTractColour fa 0.2 0.8");
  EXPECT_EQ(session::describe(std::get<session::Action>(s.steps[4].command)), "SetTractGroups ARC_L ARC_R");

  EXPECT_NE(parseError("tracts-color").find("demo.txt:1: usage: tracts-color NAME|dec [LO HI]"),
            std::string::npos);
  EXPECT_NE(parseError("tracts-color z 1").find("usage: tracts-color"), std::string::npos);
  EXPECT_NE(parseError("tracts-color z 2 1").find("tracts-color needs LO < HI"), std::string::npos);
  EXPECT_NE(parseError("tracts-color dec 0 1").find("tracts-color dec takes no range"), std::string::npos);
  EXPECT_NE(parseError("tracts-groups").find("usage: tracts-groups"), std::string::npos);
  EXPECT_NE(parseError("tracts-groups A,,B").find("empty group name"), std::string::npos);
  EXPECT_NE(parseError("tracts-groups A,").find("empty group name"), std::string::npos);
  // The reserved values: the profile's node index and the profile's value.
  const ViewScript r = parseViewScript("tracts-color node\ntracts-color profile\n", "t.txt");
  EXPECT_EQ(actionAt<session::SetTractColour>(r, 0).value, session::kNodeColouring);
  EXPECT_EQ(actionAt<session::SetTractColour>(r, 1).value, session::kProfileColouring);
}

TEST(ViewScript, FibresLinesOpenAFibreSetWithItsLayoutAndPairedTensor) {
  const ViewScript s = parseViewScript("fibres /data/my peaks.nii.gz\n"
                                       "fibres layout=dipy-peaks tensor=/data/dti.nii.gz /data/peaks.nii.gz\n"
                                       "fibres layout=auto /data/bedpostx\n",
                                       "f.txt");
  const auto& a = actionAt<session::LoadFile>(s, 0);
  EXPECT_EQ(a.path, "/data/my peaks.nii.gz"); // the path keeps its spaces
  EXPECT_EQ(a.layout, "fibres-auto");         // detected among the fibre layouts, never read as a tensor
  EXPECT_TRUE(a.tensor.empty());
  const auto& b = actionAt<session::LoadFile>(s, 1);
  EXPECT_EQ(b.path, "/data/peaks.nii.gz");
  EXPECT_EQ(b.layout, "dipy-peaks");
  EXPECT_EQ(b.tensor, "/data/dti.nii.gz");
  EXPECT_EQ(actionAt<session::LoadFile>(s, 2).layout, "fibres-auto");
  EXPECT_NE(parseError("fibres").find("usage: fibres"), std::string::npos);
  EXPECT_NE(parseError("fibres layout=dipy-peaks").find("usage: fibres"), std::string::npos);
  EXPECT_NE(parseError("fibres layout=fsl /p.nii").find("layout must be"), std::string::npos);
  EXPECT_NE(parseError("fibres tensor= /p.nii").find("usage: fibres"), std::string::npos);
}

TEST(ViewScript, OrthoLayoutCrosshairClickAndMovieLines) {
  const ViewScript s = parseViewScript("layout ortho\ncrosshair 1.5 -20 30\nclick 12 34\n"
                                       "movie turntable 24 out dir/turntable.mp4\nmovie turntable 6 --force frames/\n"
                                       "layout single\n",
                                       "demo.txt");
  ASSERT_EQ(s.steps.size(), 6u);
  EXPECT_TRUE(actionAt<session::SetOrtho>(s, 0).on);
  EXPECT_EQ(actionAt<session::SetCrosshair>(s, 1).world, glm::dvec3(1.5, -20, 30));
  const auto* click = std::get_if<ScriptClick>(&s.steps[2].command);
  ASSERT_NE(click, nullptr);
  EXPECT_EQ(click->x, 12);
  EXPECT_EQ(click->y, 34);
  const auto& movie = actionAt<session::RecordMovie>(s, 3);
  EXPECT_EQ(movie.frames, 24);
  EXPECT_EQ(movie.path, "out dir/turntable.mp4"); // paths may hold spaces
  EXPECT_FALSE(movie.force);
  EXPECT_TRUE(actionAt<session::RecordMovie>(s, 4).force);
  EXPECT_EQ(actionAt<session::RecordMovie>(s, 4).path, "frames/");
  EXPECT_FALSE(actionAt<session::SetOrtho>(s, 5).on);
  EXPECT_NE(parseError("layout triple\n").find("demo.txt:1: layout takes single or ortho"), std::string::npos);
  EXPECT_NE(parseError("crosshair 1 2\n").find("demo.txt:1:"), std::string::npos);
  EXPECT_NE(parseError("click -1 2\n").find("non-negative"), std::string::npos);
  EXPECT_NE(parseError("movie sweep 3 a.mp4\n").find("usage: movie turntable"), std::string::npos);
  EXPECT_NE(parseError("movie sweep oblique 3 a.mp4\n").find("axial, coronal or sagittal"), std::string::npos);
  EXPECT_NE(parseError("movie fa-sweep 0.5:0.5 3 a.mp4\n").find("two different thresholds"), std::string::npos);
  const ViewScript sweeps =
      parseViewScript("movie sweep coronal 20 --force sweep.gif\nmovie fa-sweep 0.2:0.45 12 fa dir/\n", "demo.txt");
  ASSERT_EQ(sweeps.steps.size(), 2u);
  const auto& sweep = actionAt<session::RecordMovie>(sweeps, 0);
  EXPECT_EQ(sweep.kind, session::RecordMovie::Kind::Sweep);
  EXPECT_EQ(sweep.axis, "coronal");
  EXPECT_EQ(sweep.frames, 20);
  EXPECT_TRUE(sweep.force);
  EXPECT_EQ(sweep.path, "sweep.gif");
  const auto& faSweep = actionAt<session::RecordMovie>(sweeps, 1);
  EXPECT_EQ(faSweep.kind, session::RecordMovie::Kind::FaSweep);
  EXPECT_DOUBLE_EQ(faSweep.faLo, 0.2);
  EXPECT_DOUBLE_EQ(faSweep.faHi, 0.45);
  EXPECT_EQ(faSweep.frames, 12);
  EXPECT_EQ(faSweep.path, "fa dir/");
  EXPECT_NE(parseError("movie turntable 0 a.mp4\n").find("[1, 10000]"), std::string::npos);
  EXPECT_NE(parseError("movie turntable 5 a.avi\n").find(".mp4"), std::string::npos);
}

// The `track` line takes every tracking parameter of the table under its name, and refuses a value outside
// the parameter's range with the table's message.
TEST(ViewScript, TrackLineTakesEveryTrackingParameter) {
  for (const auto& p : dtf::surfaces::trackingParameters()) {
    SCOPED_TRACE(p.name);
    const double inside = (p.slider.lo + p.slider.hi) / 2; // inside the range (the table test checks it)
    const std::string key = p.name;
    const ViewScript s = parseViewScript("track " + key + "=" + dtf::shortestNumber(inside) + "\n", "t.txt");
    EXPECT_DOUBLE_EQ(p.get(actionAt<session::TrackTracts>(s, 0).request.options), inside);
    const double outside = std::isfinite(p.range.hi) ? p.range.hi * 2 + 1 : -1;
    const std::string error = parseError("track " + key + "=" + dtf::shortestNumber(outside));
    EXPECT_NE(error.find("track: " + key + " must lie in " + p.range.text()), std::string::npos) << error;
  }
}

TEST(ViewScript, DesktopLinesParse) {
  const ViewScript s =
      parseViewScript("session 1\n"
                      "load layout=mrtrix /data/my dti.nii.gz\n"
                      "camera eye=1,2,300.5 target=0,0,0 up=0,1,0 ortho=95.25 near=1 far=900\n"
                      "camera pane=1 eye=0,-400,0 target=0,0,0 up=0,0,1 fov=30 near=2 far=800\n"
                      "drop /a/dti.nii.gz '/b/my tracts.tck' \"/c/mesh.ply\"\n"
                      "browse tracts /data/tracts folder\n"
                      "browser-pick my file.tck\n"
                      "session-save --force /out/view.dtfview\n"
                      "ui-scale 2\n"
                      "ui-scale auto\n"
                      "help on\n"
                      "key F1\n",
                      "s.dtfview");
  EXPECT_TRUE(s.session);
  ASSERT_EQ(s.steps.size(), 12u);
  EXPECT_EQ(actionAt<session::LoadFile>(s, 1).path, "/data/my dti.nii.gz");
  EXPECT_EQ(actionAt<session::LoadFile>(s, 1).layout, "mrtrix");
  const auto& cam = actionAt<session::SetCamera>(s, 2);
  EXPECT_EQ(cam.pane, -1);
  EXPECT_DOUBLE_EQ(cam.camera.eye.z, 300.5);
  EXPECT_TRUE(cam.camera.orthographic);
  EXPECT_DOUBLE_EQ(cam.camera.orthoHalfHeight, 95.25);
  EXPECT_DOUBLE_EQ(cam.camera.farPlane, 900);
  const auto& persp = actionAt<session::SetCamera>(s, 3);
  EXPECT_EQ(persp.pane, 1);
  EXPECT_FALSE(persp.camera.orthographic);
  EXPECT_DOUBLE_EQ(persp.camera.fovYDeg, 30);
  EXPECT_EQ(std::get<ScriptDrop>(s.steps[4].command).paths,
            (std::vector<std::string>{"/a/dti.nii.gz", "/b/my tracts.tck", "/c/mesh.ply"}));
  EXPECT_EQ(actionAt<session::Browse>(s, 5).target, session::FileTarget::Tracts);
  EXPECT_EQ(actionAt<session::Browse>(s, 5).folder, "/data/tracts folder");
  EXPECT_EQ(std::get<ScriptBrowserPick>(s.steps[6].command).name, "my file.tck");
  EXPECT_TRUE(actionAt<session::SaveSession>(s, 7).force);
  EXPECT_EQ(actionAt<session::SaveSession>(s, 7).path, "/out/view.dtfview");
  EXPECT_DOUBLE_EQ(actionAt<session::SetUiScale>(s, 8).scale, 2);
  EXPECT_DOUBLE_EQ(actionAt<session::SetUiScale>(s, 9).scale, 0);
  EXPECT_TRUE(*actionAt<session::ShowHelp>(s, 10).on);
  EXPECT_EQ(std::get<session::Key>(s.steps[11].command), session::Key::Help);

  EXPECT_NE(parseError("fa 0.3\nsession 1\n").find("demo.txt:2: session must be the script's first command"),
            std::string::npos);
  EXPECT_NE(parseError("session 2").find("session version 1"), std::string::npos);
  EXPECT_NE(parseError("camera eye=1,2 target=0,0,0 up=0,1,0 ortho=1").find("camera eye=X,Y,Z"),
            std::string::npos);
  EXPECT_NE(parseError("camera eye=0,0,1 target=0,0,0 up=0,0,1 ortho=1").find("make no view"),
            std::string::npos);
  EXPECT_NE(parseError("camera eye=0,0,1 target=0,0,0 up=0,1,0").find("usage: camera"), std::string::npos);
  EXPECT_NE(parseError("drop 'a b").find("unmatched quote"), std::string::npos);
  EXPECT_NE(parseError("browse everything").find("unknown target 'everything'"), std::string::npos);
  EXPECT_NE(parseError("ui-scale 9").find("[0.5, 4]"), std::string::npos);
  EXPECT_NE(parseError("load layout=diagonal x.nii").find("demo.txt:1: load:"), std::string::npos);
  EXPECT_FALSE(parseViewScript("fa 0.3\n", "x").session);
}

// A session names files that must exist: the first missing one is named with its line, before any window.
TEST(ViewScript, SessionInputsAreCheckedBeforeTheWindowOpens) {
  const std::string phantom = (dtf::test::sourceDir() / "sample_data" / "brain_phantom.nii.gz").string();
  EXPECT_NO_THROW(
      checkSessionInputs(parseViewScript("session 1\nload " + phantom + "\nbackground fa\n", "s")));
  // Not a session: the window reports a missing file at its line.
  EXPECT_NO_THROW(checkSessionInputs(parseViewScript("tracts /nowhere/t.tck\n", "s")));
  try {
    checkSessionInputs(
        parseViewScript("session 1\nload " + phantom + "\nfa 0.3\ntracts /nowhere/t.tck\n", "s.dtfview"));
    ADD_FAILURE() << "a missing tract file passed";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("s.dtfview:4: /nowhere/t.tck: no such file"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(checkSessionInputs(parseViewScript("session 1\nsurface mesh=/nowhere/m.ply\n", "s")),
               InputError);
  EXPECT_THROW(checkSessionInputs(parseViewScript("session 1\nbackground /nowhere/t1.nii.gz\n", "s")),
               InputError);
}

TEST(ViewScript, RoiLinesAndSavingTheSelection) {
  const ViewScript s = parseViewScript("roi add include 18,3.7,21.6,6\n"
                                       "roi add exclude box:-5,-100,-100,5,100,100\n"
                                       "roi add include-ordered /data/my atlas.nii.gz:7,8\n"
                                       "roi ends-only on\n"
                                       "roi others dim\n"
                                       "roi clear\n"
                                       "roi save --force /out/set.json\n"
                                       "roi load /in/my set.json\n"
                                       "tracts-save --selected /out/cst.tck\n"
                                       "tracts-save --force --selected --as-group cst /out/all.trx\n",
                                       "roi.txt");
  ASSERT_EQ(s.steps.size(), 10u);
  EXPECT_EQ(actionAt<session::RoiAdd>(s, 0).kind, surfaces::RegionKind::Include);
  EXPECT_EQ(actionAt<session::RoiAdd>(s, 0).spec, "18,3.7,21.6,6");
  EXPECT_EQ(actionAt<session::RoiAdd>(s, 1).kind, surfaces::RegionKind::Exclude);
  EXPECT_EQ(actionAt<session::RoiAdd>(s, 1).spec, "box:-5,-100,-100,5,100,100");
  EXPECT_EQ(actionAt<session::RoiAdd>(s, 2).kind, surfaces::RegionKind::IncludeOrdered);
  EXPECT_EQ(actionAt<session::RoiAdd>(s, 2).spec, "/data/my atlas.nii.gz:7,8");
  EXPECT_TRUE(actionAt<session::RoiEndsOnly>(s, 3).on);
  EXPECT_FALSE(actionAt<session::RoiHideOthers>(s, 4).on);
  actionAt<session::RoiClear>(s, 5);
  EXPECT_EQ(actionAt<session::SaveRegions>(s, 6).path, "/out/set.json");
  EXPECT_TRUE(actionAt<session::SaveRegions>(s, 6).force);
  EXPECT_EQ(actionAt<session::LoadRegions>(s, 7).path, "/in/my set.json");
  const auto& cst = actionAt<session::SaveTracts>(s, 8);
  EXPECT_TRUE(cst.selected);
  EXPECT_FALSE(cst.force);
  EXPECT_EQ(cst.path, "/out/cst.tck");
  const auto& all = actionAt<session::SaveTracts>(s, 9);
  EXPECT_TRUE(all.selected && all.force);
  EXPECT_EQ(all.asGroup, "cst");
  EXPECT_EQ(all.path, "/out/all.trx");
  EXPECT_NE(parseError("roi add maybe 1,2,3,4").find("demo.txt:1: roi add: the kind is include, exclude or "
                                                     "include-ordered, got 'maybe'"),
            std::string::npos);
  EXPECT_NE(parseError("roi add include").find("usage: roi add"), std::string::npos);
  EXPECT_NE(parseError("roi spin").find("roi: unknown 'spin'"), std::string::npos);
  EXPECT_NE(parseError("roi ends-only maybe").find("roi ends-only takes on or off"), std::string::npos);
  EXPECT_NE(parseError("tracts-save --as-group g x.trx").find("--as-group needs --selected"), std::string::npos);
  EXPECT_NE(parseError("tracts-save --frobnicate x.tck").find("unknown option '--frobnicate'"), std::string::npos);
}
