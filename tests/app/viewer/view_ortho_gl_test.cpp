// SPDX-License-Identifier: GPL-3.0-or-later
// The viewer's ortho layout headless: three slice panes through one crosshair beside the 3D pane. A click in
// a slice pane moves the crosshair within that slice's plane (the pane's own slice stays, the other two
// follow to the crosshair's slices, and what they show changes); the crosshair is drawn where it lies; each
// pane carries its orientation letters (radiological by default, neurological when chosen); the exported
// layout has the scene's size.
#include "io/formats/png_io.h"
#include "render/figure_furniture.h"
#include "support/gl_test.h"
#include "support/view_scene.h"
#include "ui/session/orientation_labels.h"
#include "ui/session/roi_outline.h"

namespace {

const std::string kPhantom = (dtf::test::sourceDir() / "sample_data" / "brain_phantom.nii.gz").string();

// Mean absolute RGB difference of two images over the rectangle r (x, y, w, h).
double regionDiff(const dtf::Image& a, const dtf::Image& b, const std::array<int, 4>& r) {
  double sum = 0;
  for (int y = r[1]; y < r[1] + r[3]; ++y)
    for (int x = r[0]; x < r[0] + r[2]; ++x)
      for (int c = 0; c < 3; ++c) sum += std::abs(int(a.pixel(x, y)[c]) - int(b.pixel(x, y)[c]));
  return sum / (3.0 * r[2] * r[3]);
}

// The phantom in the ortho layout, converged.
void showOrthoPhantom(dtf::test::ViewScene& v) {
  v.apply(dtf::session::LoadFile{kPhantom, "auto"});
  v.apply(dtf::session::SetOrtho{true});
  v.converge();
}

bool crosshairColour(const std::uint8_t* p) {
  return p[0] == 255 && p[1] == 230 && p[2] == 90;
}

} // namespace

TEST(ViewOrtho, ClickMovesTheCrosshairAndTheOtherPanesFollow) {
  DTF_GL_TEST_SETUP();
  dtf::test::ViewScene v("fa=0.25");
  showOrthoPhantom(v);
  ASSERT_TRUE(v.state().errorChain.empty()) << v.lastError();
  ASSERT_TRUE(v.state().ortho);
  auto& scene = v.scene;
  const auto data = scene.dataset();
  ASSERT_TRUE(data);
  // The crosshair starts at the centre of the data; the slices through it are the middle ones (48^3 grid).
  const glm::dvec3 c0 = v.state().crosshair;
  EXPECT_LT(glm::length(c0 - 0.5 * (data->lo + data->hi)), 1e-9);
  const auto s0 = v.state().orthoSlice;
  for (int s = 0; s < 3; ++s) EXPECT_NEAR(s0[std::size_t(s)], 24, 1) << s;
  const dtf::Image before = scene.layoutImage();
  EXPECT_EQ(before.width, 256);
  EXPECT_EQ(before.height, 256);

  // A click in the axial pane, up and to the image's left of the crosshair: anterior and (radiological) the
  // patient's right.
  const auto axial = scene.orthoRect(0);
  const glm::dvec2 at = scene.orthoPixel(0, c0);
  const glm::dvec2 click = at + glm::dvec2(-30, -25);
  ASSERT_EQ(scene.orthoPaneAt(click.x, click.y), 0);
  ASSERT_TRUE(scene.clickAt(click.x, click.y));
  EXPECT_FALSE(scene.clickAt(scene.paneRect(0)[0] + 5.0, scene.paneRect(0)[1] + 5.0)); // the 3D pane
  const glm::dvec3 c1 = v.state().crosshair;
  EXPECT_GT(c1.x, c0.x + 5) << "the patient's right lies on the axial pane's left";
  EXPECT_GT(c1.y, c0.y + 5) << "anterior lies up";
  EXPECT_DOUBLE_EQ(c1.z, c0.z) << "a click in the axial pane stays in its slice";
  // The crosshair lies under the clicked pixel.
  const glm::dvec2 back = scene.orthoPixel(0, c1);
  EXPECT_NEAR(back.x, click.x, 1e-6);
  EXPECT_NEAR(back.y, click.y, 1e-6);
  const auto s1 = v.state().orthoSlice;
  EXPECT_EQ(s1[0], s0[0]) << "the axial pane keeps its slice";
  EXPECT_NE(s1[1], s0[1]) << "the coronal pane follows to the crosshair";
  EXPECT_NE(s1[2], s0[2]) << "the sagittal pane follows to the crosshair";
  // The slices are the voxels nearest the crosshair.
  const glm::dvec3 ijk = data->loaded.field.grid.toVoxel(c1);
  EXPECT_EQ(s1[1], int(std::lround(ijk.y)));
  EXPECT_EQ(s1[2], int(std::lround(ijk.x)));
  v.converge();
  const dtf::Image after = scene.layoutImage();
  EXPECT_GT(regionDiff(before, after, scene.orthoRect(1)), 3.0) << "the coronal pane shows another slice";
  EXPECT_GT(regionDiff(before, after, scene.orthoRect(2)), 3.0) << "the sagittal pane shows another slice";
  EXPECT_LT(regionDiff(before, after, scene.paneRect(0)), 0.5) << "the 3D pane is unchanged";
  // The crosshair is drawn through the clicked point of the axial pane (and not elsewhere on that row).
  const int cx = int(std::floor(click.x)), cy = int(std::floor(click.y));
  EXPECT_TRUE(crosshairColour(after.pixel(axial[0] + 3, cy)));
  EXPECT_TRUE(crosshairColour(after.pixel(cx, axial[1] + 3)));
  EXPECT_FALSE(crosshairColour(before.pixel(axial[0] + 3, cy)));
  // ... and through the crosshair's projection in the coronal pane.
  const glm::dvec2 inCoronal = scene.orthoPixel(1, c1);
  EXPECT_TRUE(crosshairColour(after.pixel(int(std::floor(inCoronal.x)), scene.orthoRect(1)[1] + 3)));

  // A crosshair outside the data is clamped to it.
  v.apply(dtf::session::SetCrosshair{glm::dvec3(1e4, 0, 0)});
  EXPECT_DOUBLE_EQ(v.state().crosshair.x, data->hi.x);
}

TEST(ViewOrtho, EachSlicePaneHasItsOrientationLetters) {
  DTF_GL_TEST_SETUP();
  dtf::test::ViewScene v("fa=0.25");
  showOrthoPhantom(v);
  const auto letters = [&](int s) {
    const dtf::render::Camera& c = v.scene.orthoCamera(s);
    const glm::dvec3 right = c.right(), up = glm::normalize(glm::cross(right, c.forward()));
    return std::string(dtf::session::anatomicalLabel(-right)) + dtf::session::anatomicalLabel(right) +
           dtf::session::anatomicalLabel(up) + dtf::session::anatomicalLabel(-up); // left, right, top, bottom
  };
  // Radiological: the patient's right on the image's left; sagittal from the left (anterior on the left).
  EXPECT_EQ(letters(0), "RLAP");
  EXPECT_EQ(letters(1), "RLSI");
  EXPECT_EQ(letters(2), "APSI");
  v.apply(dtf::session::SetNeurological{true});
  v.converge();
  EXPECT_EQ(letters(0), "LRAP");
  EXPECT_EQ(letters(1), "LRSI");
  EXPECT_EQ(letters(2), "PASI");
  // The exported layout carries the letters: yellow text near the middle of the axial pane's left edge.
  const dtf::Image img = v.scene.layoutImage();
  const auto r = v.scene.orthoRect(0);
  int yellow = 0;
  for (int y = r[1] + r[3] / 2 - 8; y < r[1] + r[3] / 2 + 8; ++y)
    for (int x = r[0] + 2; x < r[0] + 18; ++x) yellow += crosshairColour(img.pixel(x, y));
  EXPECT_GT(yellow, 10);
  // Leaving the layout gives the 3D pane the whole scene again.
  v.apply(dtf::session::SetOrtho{false});
  EXPECT_EQ(v.scene.paneRect(0), (std::array<int, 4>{0, 0, 256, 256}));
  EXPECT_EQ(v.scene.orthoPaneAt(10, 10), -1);
}

// The three slice panes share one scale: on the sample DWI (72 x 72 x 39 voxels of 3 mm: the axial slice is
// larger than the coronal and sagittal ones) 10 mm along the world axes a pane shows is as many pixels in
// every pane. Each pane fitting its own slice drew them at different scales (a "50 mm" bar beside "20 mm").
TEST(ViewOrtho, TheSlicePanesShareOneScale) {
  DTF_GL_TEST_SETUP();
  dtf::test::ViewScene v("fa=0.25");
  v.apply(dtf::session::LoadFile{(dtf::test::sourceDir() / "sample_data" / "dwi.nii.gz").string(), "auto"});
  v.apply(dtf::session::SetOrtho{true});
  v.converge();
  ASSERT_TRUE(v.state().errorChain.empty()) << v.lastError();
  // A wide window: panes of aspect 1.5, where a pane fitting its own slice would not match the others.
  v.frame(384, 256);
  v.frame(384, 256);
  const glm::dvec3 c = v.state().crosshair;
  // The world axis across each pane: x across the axial and coronal panes, y across the sagittal one.
  const glm::dvec3 across[3] = {{10, 0, 0}, {10, 0, 0}, {0, 10, 0}};
  double px[3];
  for (int s = 0; s < 3; ++s)
    px[s] = glm::length(v.scene.orthoPixel(s, c + across[s]) - v.scene.orthoPixel(s, c));
  EXPECT_GT(px[0], 2.0);
  EXPECT_NEAR(px[1], px[0], 0.02 * px[0]);
  EXPECT_NEAR(px[2], px[0], 0.02 * px[0]);
}

// A slice opened with the DWI (`view dwi.nii.gz --surface slice=axial:22`): the ortho layout starts on that
// slice, and the slices cover the whole grid as `render` draws them under a background, so the mean b=0
// image shows around the tensor data (scalp, skull), not a staircase of b=0 squares ending at the data's
// mask.
TEST(ViewOrtho, AnOpenedSliceStartsTheLayoutAndTheAnatomyCoversTheGrid) {
  DTF_GL_TEST_SETUP();
  dtf::test::ViewScene v("slice=axial:22");
  v.apply(dtf::session::LoadFile{(dtf::test::sourceDir() / "sample_data" / "dwi.nii.gz").string(), "auto"});
  v.apply(dtf::session::SetOrtho{true});
  v.converge();
  ASSERT_TRUE(v.state().errorChain.empty()) << v.lastError();
  EXPECT_EQ(v.state().orthoSlice[0], 22);
  // Panes large enough for the scalp's voxels to be told from the furniture.
  v.frame(512, 512);
  for (int f = 0; f < 400 && !v.scene.converged(); ++f)
    v.frame(512, 512);
  ASSERT_TRUE(v.scene.converged());
  const auto data = v.scene.dataset();
  ASSERT_TRUE(data);
  const dtf::Grid& grid = data->loaded.field.grid;
  const dtf::ScalarVolume& b0 = data->loaded.meanB0;
  ASSERT_FALSE(b0.data.empty());
  ASSERT_EQ(b0.data.size(), grid.voxelCount());
  const dtf::Image img = v.scene.layoutImage();
  // Voxels of axial slice 22 without tensors, two voxels or more from any with them, where the b=0 image is
  // bright (above half its mean over the data: scalp and skull): each must be drawn grey in the axial pane.
  double sum = 0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < b0.data.size(); ++i)
    if (data->loaded.field.valid[i]) sum += b0.data[i], ++n;
  ASSERT_GT(n, 0u);
  const float bright = float(0.5 * sum / double(n));
  const int k = 22;
  const auto pane = v.scene.orthoRect(0);
  const glm::dvec2 cross = v.scene.orthoPixel(0, v.state().crosshair);
  const int band = dtf::render::letterBand(pane[2], pane[3]);
  int tested = 0, grey = 0;
  for (int j = 0; j < grid.dims.y; ++j)
    for (int i = 0; i < grid.dims.x; ++i) {
      if (b0.data[grid.index(i, j, k)] < bright) continue;
      bool nearData = false;
      for (int dj = -2; dj <= 2 && !nearData; ++dj)
        for (int di = -2; di <= 2 && !nearData; ++di)
          nearData =
              grid.contains(i + di, j + dj, k) && data->loaded.field.valid[grid.index(i + di, j + dj, k)];
      if (nearData) continue;
      const glm::dvec2 p = v.scene.orthoPixel(0, grid.toWorld(glm::dvec3(i, j, k)));
      // Not under the crosshair's lines or the furniture at the pane's edges (letters on black boxes).
      if (std::abs(p.x - cross.x) < 2 || std::abs(p.y - cross.y) < 2) continue;
      if (p.x < pane[0] + band || p.x > pane[0] + pane[2] - band || p.y < pane[1] + band ||
          p.y > pane[1] + pane[3] - band)
        continue;
      const std::uint8_t* c = img.pixel(int(std::floor(p.x)), int(std::floor(p.y)));
      ++tested;
      if (c[0] > 20 && std::abs(int(c[0]) - int(c[1])) < 8 && std::abs(int(c[1]) - int(c[2])) < 8) ++grey;
    }
  ASSERT_GT(tested, 20) << "the slice has bright b=0 voxels away from the tensor data";
  EXPECT_GT(grey, 0.9 * tested) << grey << " of " << tested << " b=0 voxels outside the data drawn grey";
}

// A sphere region is outlined in the slice panes where it cuts their slices, in the include colour: the
// circle is computed here from the sphere and each pane's slice plane (a CPU reference), and the pixels on
// it carry the colour while pixels well inside and outside do not. The region under a pixel is found for
// dragging.
TEST(ViewOrtho, RegionOutlinesFollowTheSphereWhereItCutsEachSlice) {
  DTF_GL_TEST_SETUP();
  dtf::test::ViewScene v("fa=0.25");
  showOrthoPhantom(v);
  ASSERT_TRUE(v.state().errorChain.empty()) << v.lastError();
  auto& scene = v.scene;
  const glm::dvec3 cross = v.state().crosshair;
  const glm::u8vec3 green = dtf::session::regionKindColour(dtf::surfaces::RegionKind::Include);
  auto isGreen = [&](const dtf::Image& img, int x, int y) {
    if (x < 0 || y < 0 || x >= img.width || y >= img.height) return false;
    const std::uint8_t* p = img.pixel(x, y);
    return p[0] == green.x && p[1] == green.y && p[2] == green.z;
  };
  const dtf::Image plain = scene.layoutImage();
  for (int y = 0; y < plain.height; ++y)
    for (int x = 0; x < plain.width; ++x)
      ASSERT_FALSE(isGreen(plain, x, y)) << "the include colour is already on screen at " << x << "," << y;

  dtf::session::RoiAdd add;
  add.spec = std::to_string(cross.x + 3) + "," + std::to_string(cross.y - 2) + "," + std::to_string(cross.z + 1.5) +
             ",24";
  v.apply(add);
  v.converge();
  ASSERT_TRUE(v.state().errorChain.empty()) << v.lastError();
  const glm::dvec3 c(cross.x + 3, cross.y - 2, cross.z + 1.5);
  const double radius = 24;
  const dtf::Image img = scene.layoutImage();
  for (int s = 0; s < 3; ++s) {
    ASSERT_TRUE(scene.orthoPlane(s)) << s;
    const glm::dvec4 plane(*scene.orthoPlane(s));
    const glm::dvec3 n(plane);
    const double d = glm::dot(n, c) + plane.w; // the centre's distance from the slice
    ASSERT_LT(std::abs(d), radius) << s;
    const glm::dvec3 onPlane = c - d * n;
    const double rho = std::sqrt(radius * radius - d * d);
    const glm::dvec2 centre = scene.orthoPixel(s, onPlane);
    const double rPx = glm::length(scene.orthoPixel(s, onPlane + rho * scene.orthoCamera(s).right()) - centre);
    ASSERT_GT(rPx, 10) << s;
    int on = 0, inside = 0, outside = 0;
    const int samples = 72;
    for (int k = 0; k < samples; ++k) {
      const double t = 2 * M_PI * k / samples;
      const glm::dvec2 dir(std::cos(t), std::sin(t));
      auto near = [&](glm::dvec2 p) { // the pixel holding p or a neighbour
        const int x = int(std::floor(p.x)), y = int(std::floor(p.y));
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx)
            if (isGreen(img, x + dx, y + dy)) return true;
        return false;
      };
      on += near(centre + rPx * dir);
      inside += near(centre + 0.6 * rPx * dir);
      outside += near(centre + 1.4 * rPx * dir);
    }
    EXPECT_GE(on, samples * 95 / 100) << "pane " << s << ": the circle of radius " << rPx << " px";
    EXPECT_EQ(inside, 0) << "pane " << s;
    EXPECT_EQ(outside, 0) << "pane " << s;
    // The region under the centre is region 0; nothing well outside.
    EXPECT_EQ(scene.regionAt(centre.x, centre.y), 0) << s;
    EXPECT_EQ(scene.regionAt(centre.x + 1.4 * rPx, centre.y), -1) << s;
  }
  // Hidden, it is not drawn.
  v.apply(dtf::session::RoiVisible{0, false});
  v.converge();
  const dtf::Image hidden = scene.layoutImage();
  std::size_t greens = 0;
  for (int y = 0; y < hidden.height; ++y)
    for (int x = 0; x < hidden.width; ++x)
      greens += isGreen(hidden, x, y);
  EXPECT_EQ(greens, 0u);
}

// A mask region is outlined in each slice pane along the section of its voxels' cells: a 31 mm cube of
// 1 mm voxels around the crosshair gives a square whose four sides carry the include colour, while its
// middle and the pixels well outside do not; in the 3D pane the cube's edges are drawn.
TEST(ViewOrtho, MaskRegionsAreOutlinedAlongTheirVoxels) {
  DTF_GL_TEST_SETUP();
  dtf::test::ViewScene v("fa=0.25");
  showOrthoPhantom(v);
  ASSERT_TRUE(v.state().errorChain.empty()) << v.lastError();
  auto& scene = v.scene;
  const glm::dvec3 cross = v.state().crosshair;
  // Voxels 5..35 of a 41^3 grid whose voxel 20 sits on the crosshair: cells within 15.5 mm of it.
  const dtf::Grid g = dtf::Grid::fromAffine({41, 41, 41}, glm::translate(glm::dmat4(1.0), cross - 20.0));
  auto mask = std::make_shared<dtf::MaskVolume>(g, 1);
  for (int k = 5; k <= 35; ++k)
    for (int j = 5; j <= 35; ++j)
      for (int i = 5; i <= 35; ++i)
        mask->at(i, j, k) = 1;
  dtf::session::RoiAdd add;
  add.kind = add.region.kind = dtf::surfaces::RegionKind::Include;
  add.region.shape = dtf::surfaces::RegionShape::Mask;
  add.region.mask = mask;
  add.region.name = "cube";
  v.apply(add);
  v.converge();
  ASSERT_TRUE(v.state().errorChain.empty()) << v.lastError();
  const glm::u8vec3 green = dtf::session::regionKindColour(dtf::surfaces::RegionKind::Include);
  const dtf::Image img = scene.layoutImage();
  dtf::io::writePng((dtf::test::scratchDir() / "mask_outline.png").string(), img);
  auto greenNear = [&](glm::dvec2 p, int reach) {
    for (int dy = -reach; dy <= reach; ++dy)
      for (int dx = -reach; dx <= reach; ++dx) {
        const int x = int(std::floor(p.x)) + dx, y = int(std::floor(p.y)) + dy;
        if (x < 0 || y < 0 || x >= img.width || y >= img.height) continue;
        const std::uint8_t* c = img.pixel(x, y);
        if (c[0] == green.x && c[1] == green.y && c[2] == green.z) return true;
      }
    return false;
  };
  for (int s = 0; s < 3; ++s) {
    ASSERT_TRUE(scene.orthoPlane(s)) << s;
    const glm::dvec4 plane(*scene.orthoPlane(s));
    const glm::dvec3 n(plane);
    const glm::dvec3 onPlane = cross - (glm::dot(n, cross) + plane.w) * n;
    ASSERT_LT(glm::length(onPlane - cross), 2.0) << "pane " << s << ": its slice passes near the crosshair";
    std::vector<glm::dvec2> outline;
    bool segments = false;
    ASSERT_TRUE(scene.regionOutlinePixels(s, 0, outline, &segments)) << s;
    EXPECT_TRUE(segments);
    int sides = 0;
    for (int axis = 0; axis < 3; ++axis) {
      glm::dvec3 a(0.0);
      a[axis] = 1.0;
      if (std::abs(glm::dot(a, n)) > 0.5) continue; // the axis across the slice
      for (double sign : {-1.0, 1.0}) {
        sides += greenNear(scene.orthoPixel(s, onPlane + sign * 15.5 * a), 2);
        EXPECT_FALSE(greenNear(scene.orthoPixel(s, onPlane + sign * 24.0 * a), 1)) << "pane " << s << " outside";
      }
    }
    EXPECT_EQ(sides, 4) << "pane " << s << ": every side of the square";
    EXPECT_FALSE(greenNear(scene.orthoPixel(s, onPlane), 2)) << "pane " << s << ": the middle";
  }
  // In the 3D pane the cube's edges are drawn (the creases of its voxels' surface): green at each of its
  // eight corners, none well beside it.
  const auto rect = scene.paneRect(0);
  auto inPane = [&](const glm::dvec3& world) {
    glm::dvec2 px(0.0);
    EXPECT_TRUE(scene.panePixel(0, world, rect[2], rect[3], px));
    return px + glm::dvec2(rect[0], rect[1]);
  };
  for (int c = 0; c < 8; ++c) {
    const glm::dvec3 corner = cross + 15.5 * glm::dvec3(c & 1 ? 1 : -1, c & 2 ? 1 : -1, c & 4 ? 1 : -1);
    EXPECT_TRUE(greenNear(inPane(corner), 2)) << "3D pane: corner " << c;
  }
  const glm::dvec3 right = scene.camera(0).right();
  EXPECT_FALSE(greenNear(inPane(cross + 40.0 * right), 3)) << "3D pane: beside the cube";
  EXPECT_FALSE(greenNear(inPane(cross - 40.0 * right), 3)) << "3D pane: beside the cube";
}

// Dragging a region in a slice pane and turning the wheel over it, as the window does on a press, a move
// and a wheel notch: the region moves by the world step under the pointer, within the slice's plane, and
// grows by 1.1 per notch about its centre (a sphere's radius, a box's half-sizes).
TEST(ViewOrtho, ARegionIsDraggedWithinItsSliceAndScaledByTheWheel) {
  DTF_GL_TEST_SETUP();
  dtf::test::ViewScene v("fa=0.25");
  showOrthoPhantom(v);
  ASSERT_TRUE(v.state().errorChain.empty()) << v.lastError();
  auto& scene = v.scene;
  const glm::dvec3 cross = v.state().crosshair;
  dtf::session::RoiAdd add;
  add.spec = std::to_string(cross.x) + "," + std::to_string(cross.y) + "," + std::to_string(cross.z) + ",10";
  v.apply(add);
  v.converge();
  ASSERT_EQ(v.state().roiSet.regions.size(), 1u);
  const int s = 0;
  const glm::dvec4 plane(*scene.orthoPlane(s));
  const glm::dvec3 n(plane);
  const dtf::surfaces::Region start = v.state().roiSet.regions[0];
  const glm::dvec2 c = scene.orthoPixel(s, start.centre - (glm::dot(n, start.centre) + plane.w) * n);
  ASSERT_EQ(scene.regionAt(c.x, c.y), 0);
  // Press at the centre, move 30 px right and 12 px down.
  const glm::dvec3 from = scene.orthoWorld(s, c.x, c.y);
  v.apply(scene.regionDragged(0, start, s, from, c.x + 30, c.y + 12));
  v.converge();
  const dtf::surfaces::Region& moved = v.state().roiSet.regions[0];
  const glm::dvec3 step = moved.centre - start.centre;
  EXPECT_NEAR(glm::dot(step, n), 0.0, 1e-6) << "the drag stays in the slice's plane";
  const glm::dvec2 seen = scene.orthoPixel(s, moved.centre - (glm::dot(n, moved.centre) + plane.w) * n) - c;
  EXPECT_NEAR(seen.x, 30.0, 0.5);
  EXPECT_NEAR(seen.y, 12.0, 0.5);
  EXPECT_DOUBLE_EQ(moved.radius, 10.0);
  EXPECT_EQ(scene.regionAt(c.x + 30, c.y + 12), 0) << "the region is under the pointer";
  EXPECT_EQ(scene.regionAt(c.x - 0.6 * (seen.x + 40), c.y), -1);
  // Two notches up over it, then one down.
  const auto up = scene.regionScaled(c.x + 30, c.y + 12, 2);
  ASSERT_TRUE(up.has_value());
  EXPECT_EQ(up->index, 0u);
  v.apply(*up);
  v.converge();
  EXPECT_NEAR(v.state().roiSet.regions[0].radius, 12.1, 1e-9);
  EXPECT_EQ(v.state().roiSet.regions[0].centre, moved.centre);
  EXPECT_FALSE(scene.regionScaled(c.x - 200, c.y - 200, 1).has_value()) << "no region there: the wheel zooms";
  // A box scales its half-sizes about its centre.
  dtf::session::RoiAdd box;
  box.kind = dtf::surfaces::RegionKind::Exclude;
  box.spec = "box:" + std::to_string(cross.x - 40) + "," + std::to_string(cross.y - 4) + "," +
             std::to_string(cross.z - 4) + "," + std::to_string(cross.x - 30) + "," + std::to_string(cross.y + 4) +
             "," + std::to_string(cross.z + 4);
  v.apply(box);
  v.converge();
  ASSERT_EQ(v.state().roiSet.regions.size(), 2u);
  const dtf::surfaces::Region b = v.state().roiSet.regions[1];
  const glm::dvec3 bc = 0.5 * (b.lo + b.hi);
  const glm::dvec2 bp = scene.orthoPixel(s, bc - (glm::dot(n, bc) + plane.w) * n);
  const auto down = scene.regionScaled(bp.x, bp.y, -1);
  ASSERT_TRUE(down.has_value());
  EXPECT_EQ(down->index, 1u);
  const glm::dvec3 half = 0.5 * (down->region.hi - down->region.lo);
  EXPECT_NEAR(half.x, 5.0 / 1.1, 1e-9);
  EXPECT_NEAR(half.y, 4.0 / 1.1, 1e-9);
  EXPECT_NEAR(glm::length(0.5 * (down->region.lo + down->region.hi) - bc), 0.0, 1e-9);
}
