// SPDX-License-Identifier: GPL-3.0-or-later
// The web page's slices are the render's: the middle slice of each axis in the folder equals, pixel for
// pixel, runRender's image of the same slice with the page's camera at the same size (the render's default
// look: the anatomy look, smooth data edges), for a tensor file and for a DWI (fitted, its mean b=0 image
// beneath, every slice of the grid).
#include "support/gl_test.h"
#include "support/test_env.h"

#include "io/diffusion/dwi.h"
#include "io/formats/png_io.h"
#include "io/formats/tensor_io.h"
#include "io/phantoms.h"
#include "surfaces/slices.h"
#include "ui/session/render_job.h"
#include "ui/session/web_page.h"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

using namespace dtf;
namespace fs = std::filesystem;

namespace {

class WebPageSlices : public GlTest {};

// The slice indices of `axis` the page wrote (slices/AXIS_NNN.png), ascending.
std::vector<int> writtenSlices(const fs::path& page, const std::string& axis) {
  std::vector<int> out;
  for (const auto& e : fs::directory_iterator(page / "slices")) {
    const std::string name = e.path().filename().string();
    int s = 0;
    if (name.rfind(axis + "_", 0) == 0 && std::sscanf(name.c_str() + axis.size() + 1, "%d.png", &s) == 1 &&
        name.find("tracts") == std::string::npos)
      out.push_back(s);
  }
  std::sort(out.begin(), out.end());
  return out;
}

// Compares the middle slice of every axis with runRender's image of it; `input` as the page read it.
void expectSlicesEqualTheRender(const fs::path& page, const std::string& input, const Grid& grid, int size) {
  const char* names[3] = {"axial", "coronal", "sagittal"};
  for (int a = 0; a < 3; ++a) {
    SCOPED_TRACE(names[a]);
    const std::vector<int> slices = writtenSlices(page, names[a]);
    ASSERT_FALSE(slices.empty());
    const int s = slices[slices.size() / 2];
    char file[64];
    std::snprintf(file, sizeof file, "%s_%03d.png", names[a], s);
    const Image got = io::readPng((page / "slices" / file).string());

    const session::WebSliceView view = session::webSliceView(grid, a, size);
    session::RenderRequest r;
    r.input = input;
    r.tensorOptions.quiet = true;
    r.surface = session::parseSurfaceSpec(std::string("slice=") + names[a] + ":" + std::to_string(s));
    r.width = view.width;
    r.height = view.height;
    r.camera = view.camera;
    r.furniture = {false, false, false, false, 0};
    const Image want = session::runRender(r).image;
    ASSERT_EQ(got.width, want.width);
    ASSERT_EQ(got.height, want.height);
    EXPECT_EQ(std::max(got.width, got.height), size);
    int differ = 0, lit = 0;
    for (int y = 0; y < got.height; ++y)
      for (int x = 0; x < got.width; ++x) {
        differ += std::memcmp(got.pixel(x, y), want.pixel(x, y), 4) != 0;
        lit += (got.pixel(x, y)[0] | got.pixel(x, y)[1] | got.pixel(x, y)[2]) != 0;
      }
    std::printf("%s slice %d: %dx%d, %d pixels lit, %d differ from the render\n", names[a], s, got.width,
                got.height, lit, differ);
    EXPECT_EQ(differ, 0);
    EXPECT_GT(lit, got.width * got.height / 50); // not an empty image
  }
}

} // namespace

TEST_F(WebPageSlices, EachSliceEqualsTheRenderOfTheSameSliceAndSizeForATensorFile) {
  DTF_GL_TEST_SETUP();
  const fs::path dir = test::scratchDir();
  io::PhantomOptions o;
  o.size = 24;
  const fs::path input = dir / "phantom.nii.gz";
  io::writeTensorVolume(input.string(), io::makePhantom("brain", o).tensors, io::TensorLayout::Fsl);
  session::WebPageRequest w;
  w.input = input.string();
  w.output = (dir / "page").string();
  w.size = 96;
  w.slicesOnly = true;
  const session::WebPageResult res = session::writeWebPage(w);
  EXPECT_EQ(res.frames3d, 0);
  EXPECT_EQ(res.faFrames, 0);
  expectSlicesEqualTheRender(dir / "page", input.string(), io::readTensorVolume(input.string()).field.grid, 96);
}

TEST_F(WebPageSlices, EachSliceEqualsTheRenderOfTheSameSliceAndSizeForADwi) {
  DTF_GL_TEST_SETUP();
  DTF_SHARED_FILE(dwi, "dipy_small/small_64D.nii");
  const fs::path dir = test::scratchDir();
  session::WebPageRequest w;
  w.input = dwi.string();
  w.tensorOptions.quiet = true;
  w.output = (dir / "page").string();
  w.size = 64;
  w.slicesOnly = true;
  const session::WebPageResult res = session::writeWebPage(w);
  // The mean b=0 image beneath: every slice of the 10 x 10 x 10 grid.
  EXPECT_EQ(res.slices[0] + res.slices[1] + res.slices[2], 30);
  Grid grid = io::readDwi(dwi.string(), (dwi.parent_path() / "small_64D.bval").string(),
                          (dwi.parent_path() / "small_64D.bvec").string())
                  .signal.grid;
  expectSlicesEqualTheRender(dir / "page", dwi.string(), grid, 64);
}
