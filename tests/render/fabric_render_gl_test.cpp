// SPDX-License-Identifier: GPL-3.0-or-later
// The whole fabric pipeline on synthetic fields: threads follow the data, crossings show both directions,
// degenerate regions render calmly, same input gives the same image.
#include "support/gl_test.h"

#include "render/fabric_renderer.h"
#include "render/reference/scenes.h"

#include <limits>

using namespace dtf;
using namespace dtf::render;

namespace {

class FabricRender : public GlTest {};

struct AxialScene {
  Mesh mesh = reference::planeMesh({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 60, 60, 8);
  Grid grid = reference::centredGrid(32, 2.0);
  glm::dvec3 lo{-30, -30, -1}, hi{30, 30, 1};
};

// r draws the axial plane of s with a field along x, 96 x 96, and the camera that sees it from superior.
Camera horizontalThreads(FabricRenderer& r, const AxialScene& s) {
  r.setMesh(s.mesh);
  r.setField(reference::constantField(s.grid, {1, 0, 0}));
  r.resize(96, 96);
  return Camera::standard(StandardView::Superior, s.lo, s.hi, 1.0);
}

Image channelImage(const std::vector<float>& rg, int w, int h, int c, int x0, int y0) {
  // GL rows (bottom first) of the guarded target -> an image of the viewport (top first).
  Image img(w, h);
  int tw = w + 2 * x0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      float v = rg[(static_cast<std::size_t>(h - 1 - y + y0) * tw + x + x0) * 2 + c];
      auto* p = img.pixel(x, y);
      p[0] = p[1] = p[2] = static_cast<std::uint8_t>(std::clamp(v, 0.0f, 1.0f) * 255.0f + 0.5f);
      p[3] = 255;
    }
  return img;
}

} // namespace

TEST_F(FabricRender, ThreadsFollowConstantDirectionsOnAnAxialSliceSeenFromSuperior) {
  AxialScene s;
  FabricRenderer r;
  r.setMesh(s.mesh);
  r.resize(256, 256);
  Camera cam = Camera::standard(StandardView::Superior, s.lo, s.hi, 1.0);
  for (double angle : {0.0, 30.0, 60.0, 120.0}) {
    SCOPED_TRACE(angle);
    double a = glm::radians(angle);
    r.setField(reference::constantField(s.grid, {std::cos(a), std::sin(a), 0}));
    Image img = r.renderStill(cam, FabricParams{});
    double coherence = 0;
    double measured = test::dominantOrientation(img, 40, 40, 216, 216, &coherence);
    // Seen from superior, image right = +x and image up = +y: the world angle is the image angle.
    EXPECT_LT(test::orientationDiff(measured, angle), 4.0) << "measured " << measured;
    EXPECT_GT(coherence, 0.3);
    // Medical colour: DEC of the direction (red = x, green = y), no blue.
    const auto* c = img.pixel(128, 128);
    if (angle == 0.0) {
      EXPECT_GT(c[0], 3 * std::max<int>(c[1], 1));
    }
    if (angle == 60.0) {
      EXPECT_GT(c[1], c[0]);
    }
    EXPECT_LT(c[2], 30);
  }
}

TEST_F(FabricRender, CrossingFieldShowsBothDirections) {
  AxialScene s;
  FabricRenderer r;
  r.setMesh(s.mesh);
  const double a = glm::radians(20.0), b = glm::radians(110.0);
  r.setField(reference::crossingField(s.grid, {std::cos(a), std::sin(a), 0}, {std::cos(b), std::sin(b), 0}, 0.6));
  r.resize(256, 256);
  Camera cam = Camera::standard(StandardView::Superior, s.lo, s.hi, 1.0);
  FabricParams p;
  p.colour = ColourMode::Engineering;
  r.renderStill(cam, p);
  auto rg = r.advection().readFields();
  const int g = r.frameView().guard;
  for (int c = 0; c < 2; ++c) {
    Image img = channelImage(rg, 256, 256, c, g, g);
    double coherence = 0;
    double measured = test::dominantOrientation(img, 40, 40, 216, 216, &coherence);
    EXPECT_LT(test::orientationDiff(measured, c == 0 ? 20.0 : 110.0), 4.0) << "field " << c << " measured " << measured;
    EXPECT_GT(coherence, 0.3);
  }
}

TEST_F(FabricRender, IsotropicRegionsRenderCalmlyAndStillsAreDeterministic) {
  AxialScene s;
  FabricRenderer r;
  r.setMesh(s.mesh);
  r.setField(reference::constantField(s.grid, {1, 0, 0}, 1e-3, 1e-3));
  r.resize(128, 128);
  Camera cam = Camera::standard(StandardView::Superior, s.lo, s.hi, 1.0);
  FabricParams p;
  p.look = Look::Plain; // the fabric itself (the anatomy look shows FA 0 beneath it here)
  Image a = r.renderStill(cam, p);
  Image b = r.renderStill(cam, p);
  EXPECT_EQ(a.rgba, b.rgba);
  double coherence = 1;
  test::dominantOrientation(a, 20, 20, 108, 108, &coherence);
  EXPECT_LT(coherence, 0.2); // no direction: the noise stays unsmeared
  int lit = 0;
  for (int y = 20; y < 108; ++y)
    for (int x = 20; x < 108; ++x) lit += a.pixel(x, y)[0] + a.pixel(x, y)[1] + a.pixel(x, y)[2] > 0;
  EXPECT_GT(lit, 88 * 88 * 9 / 10); // drawn, not black
}

// Counting changed pixels costs an atomic increment per changed pixel: frames count only once a still could
// stop on them, from FabricParams::stillMinIterations iterations after the restart (29 for k 0.1, epsilon
// 0.05); before that changedPixels() says "not known".
TEST_F(FabricRender, FramesCountChangedPixelsOnlyOnceAStillCouldStop) {
  AxialScene s;
  FabricRenderer r;
  const Camera cam = horizontalThreads(r, s);
  FabricParams p;
  const int least = p.stillMinIterations();
  ASSERT_EQ(least, 29);
  int iterations = 0;
  for (int f = 0; f < 14; ++f) {
    r.renderFrame(cam, p); // the first restarts from beta
    iterations += p.iterations;
    const unsigned changed = r.changedPixels();
    if (iterations < least)
      EXPECT_EQ(changed, std::numeric_limits<unsigned>::max()) << "frame " << f;
    else
      EXPECT_LE(changed, r.coveredPixels()) << "frame " << f;
  }
  // A camera turn restarts the count.
  Camera turned = cam;
  turned.trackball({0, 0}, {0.05, 0});
  r.renderFrame(turned, p);
  EXPECT_EQ(r.changedPixels(), std::numeric_limits<unsigned>::max());
  r.renderFrame(turned, p);
  EXPECT_EQ(r.changedPixels(), std::numeric_limits<unsigned>::max());
}

TEST_F(FabricRender, InteractiveFramesContinueAndRestartOnCameraMotion) {
  AxialScene s;
  FabricRenderer r;
  Camera cam = horizontalThreads(r, s);
  FabricParams p;
  for (int i = 0; i < 20; ++i) r.renderFrame(cam, p);
  // With a still camera the state converges: few pixels change by more than epsilon.
  EXPECT_LT(r.changedPixels(), 96u * 96u / 50u);
  Image still = r.readback();
  cam.trackball({0, 0}, {0.05, 0});
  r.renderFrame(cam, p);
  Image moved = r.readback();
  EXPECT_NE(still.rgba, moved.rgba);
  EXPECT_TRUE(r.projection().size() == glm::ivec2(96 + 2 * p.guard, 96 + 2 * p.guard));
  // Lower internal resolution while moving; full resolution again once the camera stops.
  p.movingScale = 0.5;
  cam.trackball({0, 0}, {0.05, 0});
  r.renderFrame(cam, p);
  EXPECT_TRUE(r.projection().size() == glm::ivec2(48 + 2 * p.guard, 48 + 2 * p.guard));
  Image half = r.readback();
  std::size_t lit = 0;
  for (std::size_t i = 0; i < half.rgba.size(); i += 4) lit += (half.rgba[i] | half.rgba[i + 1]) != 0;
  EXPECT_GT(lit, half.rgba.size() / 4 / 2);
  r.renderFrame(cam, p);
  EXPECT_TRUE(r.projection().size() == glm::ivec2(96 + 2 * p.guard, 96 + 2 * p.guard));
}

TEST_F(FabricRender, OutputDepthIsTheRasterisedDepthOfTheSurface) {
  // The composite computes gl_FragDepth from the linear depth; overlays depth-test against it, so it must
  // agree with the depth the rasteriser wrote, in both projections.
  Mesh sphere = reference::uvSphere({0, 0, 0}, 20.0, 24, 32);
  FabricRenderer r;
  r.setMesh(sphere);
  r.setField(reference::constantField(reference::centredGrid(24, 2.0), {1, 0, 0}));
  const int n = 96;
  r.resize(n, n);
  for (bool ortho : {true, false}) {
    SCOPED_TRACE(ortho ? "orthographic" : "perspective");
    Camera cam = Camera::standard(StandardView::Anterior, {-20, -20, -20}, {20, 20, 20}, 1.0);
    cam.orthographic = ortho;
    cam.fit({-20, -20, -20}, {20, 20, 20}, 1.0);
    FabricParams p;
    r.renderFrame(cam, p);
    GLint id = 0;
    glGetNamedFramebufferAttachmentParameteriv(r.output().id(), GL_DEPTH_ATTACHMENT,
                                               GL_FRAMEBUFFER_ATTACHMENT_OBJECT_NAME, &id);
    std::vector<float> out(static_cast<std::size_t>(n) * n);
    glGetTextureImage(static_cast<GLuint>(id), 0, GL_DEPTH_COMPONENT, GL_FLOAT, static_cast<GLsizei>(out.size() * 4),
                      out.data());
    const Texture& projected = r.projection().depth();
    const int g = (projected.width() - n) / 2; // guard border
    std::vector<float> raster(static_cast<std::size_t>(projected.width()) * projected.height());
    glGetTextureImage(projected.id(), 0, GL_DEPTH_COMPONENT, GL_FLOAT, static_cast<GLsizei>(raster.size() * 4),
                      raster.data());
    int covered = 0;
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        const float want = raster[static_cast<std::size_t>(y + g) * projected.width() + x + g];
        const float got = out[static_cast<std::size_t>(y) * n + x];
        if (want >= 1.0f) {
          EXPECT_EQ(got, 1.0f) << "background keeps the cleared depth";
          continue;
        }
        ++covered;
        ASSERT_NEAR(got, want, 2e-6) << x << "," << y;
      }
    EXPECT_GT(covered, n * n / 4);
  }
}

// The composite shades only FrameView::coverRect: every viewport pixel that shows a covered internal texel
// (the rasteriser's depth of the surface, nearest-upsampled as the composite reads it) lies inside it, at
// full and at half resolution while moving, in both projections and obliquely; a sphere small in the view
// leaves most of the viewport outside it, and the frame's image has no surface pixel outside it.
TEST_F(FabricRender, CompositeRectHoldsEveryPixelTheSurfaceCovers) {
  Mesh sphere = reference::uvSphere({0, 0, 0}, 20.0, 24, 32);
  FabricRenderer r;
  r.setMesh(sphere);
  r.setField(reference::constantField(reference::centredGrid(24, 2.0), {1, 0, 0}));
  const int w = 128, h = 96;
  r.resize(w, h);
  int cases = 0;
  for (bool ortho : {true, false})
    for (double scale : {1.0, 0.5})
      for (bool oblique : {false, true}) {
        SCOPED_TRACE(std::string(ortho ? "orthographic" : "perspective") + (oblique ? " oblique" : "") +
                     " scale " + std::to_string(scale));
        Camera cam = Camera::standard(StandardView::Anterior, {-20, -20, -20}, {20, 20, 20}, double(w) / h);
        cam.orthographic = ortho;
        cam.fit({-20, -20, -20}, {20, 20, 20}, double(w) / h);
        cam.zoom(2.2); // the sphere small, off centre
        cam.farPlane *= 4.0; // a perspective zoom moves the eye back
        const glm::dvec3 shift = -25.0 * cam.right() + 15.0 * glm::normalize(cam.up);
        cam.lookAt(cam.eye + shift, cam.target + shift, cam.up);
        if (oblique) cam.trackball({0.0, 0.0}, {0.4, 0.3});
        FabricParams p;
        p.movingScale = scale;
        r.renderFrame(cam, p);
        cam.trackball({0.0, 0.0}, {0.01, 0.0}); // a moving frame: at movingScale
        r.renderFrame(cam, p);
        const FrameView& v = r.frameView();
        ASSERT_NEAR(v.scale, scale, 1e-6);
        const glm::ivec4 rect = v.coverRect;
        ASSERT_GE(rect.z, 0);
        const Texture& depth = r.projection().depth();
        std::vector<float> raster(static_cast<std::size_t>(depth.width()) * depth.height());
        glGetTextureImage(depth.id(), 0, GL_DEPTH_COMPONENT, GL_FLOAT,
                          static_cast<GLsizei>(raster.size() * 4), raster.data());
        glm::ivec2 lo(w, h), hi(-1, -1);
        int covered = 0;
        for (int y = 0; y < h; ++y)
          for (int x = 0; x < w; ++x) {
            const glm::ivec2 t = glm::ivec2((glm::vec2(x, y) + 0.5f) * v.scale) + v.guard;
            if (raster[static_cast<std::size_t>(t.y) * depth.width() + t.x] >= 1.0f) continue;
            ++covered;
            lo = glm::min(lo, glm::ivec2(x, y));
            hi = glm::max(hi, glm::ivec2(x, y));
            ASSERT_TRUE(x >= rect.x && x < rect.x + rect.z && y >= rect.y && y < rect.y + rect.w)
                << "covered pixel " << x << "," << y << " outside " << rect.x << "," << rect.y << " "
                << rect.z << "x" << rect.w;
          }
        ASSERT_GT(covered, 100);
        // Tight enough to matter: the bounds box's corners lie up to sqrt(3) radii from the sphere's centre
        // (3x the area of the sphere's own box when seen along a diagonal), plus the margin.
        const double box = double(hi.x - lo.x + 1 + 8) * (hi.y - lo.y + 1 + 8);
        EXPECT_LT(double(rect.z) * rect.w, 3.0 * box);
        EXPECT_LT(double(rect.z) * rect.w, 0.6 * w * h);
        const Image img = r.readback(); // row 0 at the top
        for (int y = 0; y < h; ++y)
          for (int x = 0; x < w; ++x) {
            const auto* px = img.pixel(x, h - 1 - y);
            if ((px[0] | px[1] | px[2]) == 0) continue;
            ASSERT_TRUE(x >= rect.x && x < rect.x + rect.z && y >= rect.y && y < rect.y + rect.w);
          }
        ++cases;
      }
  EXPECT_EQ(cases, 8);
}

// A still camera reuses the previous frame's projection and silhouettes: three frames of 3 iterations give
// the image of one frame of 9, and the projection is not run again (no projection time). A camera, data or
// parameter change projects again: the frame equals a fresh renderer's.
TEST_F(FabricRender, StillCameraFramesReuseTheProjectionAndMatchTheWholeFrame) {
  AxialScene s;
  const TensorField crossing = reference::constantField(s.grid, {1, 1, 0});
  auto fresh = [&](const Camera& cam, const FabricParams& p, const TensorField& field) {
    FabricRenderer f;
    f.setMesh(s.mesh);
    f.setField(field);
    f.resize(96, 96);
    f.renderFrame(cam, p);
    return f.readback();
  };
  FabricRenderer r;
  r.setMesh(s.mesh);
  r.setField(crossing);
  r.resize(96, 96);
  Camera cam = Camera::standard(StandardView::Superior, s.lo, s.hi, 1.0);
  FabricParams p;
  p.iterations = 3;
  r.setTiming(true);
  r.renderFrame(cam, p);
  EXPECT_GT(r.coveredPixels(), 0u);
  for (int i = 0; i < 2; ++i) {
    r.renderFrame(cam, p);
    EXPECT_EQ(r.lastTimes().projection, 0.0) << "the projection ran for a still camera";
    EXPECT_EQ(r.lastTimes().silhouette, 0.0) << "the silhouettes ran for a still camera";
  }
  r.setTiming(false);
  FabricParams nine = p;
  nine.iterations = 9;
  EXPECT_EQ(r.readback().rgba, fresh(cam, nine, crossing).rgba);

  cam.trackball({0, 0}, {0.05, 0});
  r.renderFrame(cam, p);
  EXPECT_EQ(r.readback().rgba, fresh(cam, p, crossing).rgba) << "after a camera step";
  FabricParams engineering = p;
  engineering.colour = ColourMode::Engineering;
  r.renderFrame(cam, engineering);
  EXPECT_EQ(r.readback().rgba, fresh(cam, engineering, crossing).rgba) << "after a parameter change";
  const TensorField other = reference::constantField(s.grid, {0, 1, 0});
  r.setField(other);
  r.renderFrame(cam, engineering);
  EXPECT_EQ(r.readback().rgba, fresh(cam, engineering, other).rgba) << "after a data change";
  r.setMesh(reference::planeMesh({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 40, 40, 8));
  r.renderFrame(cam, engineering);
  EXPECT_NE(r.readback().rgba, fresh(cam, engineering, other).rgba) << "after a mesh change";
}

// The tensor stage and the advection as compute shaders (the default on hardware GPUs) draw the fragment
// passes' images: a still of many iterations, then interactive frames that continue and restart. The
// advection is the same arithmetic (bit for bit, FabricPass.AdvectionComputeShaderEqualsTheFragmentPass);
// the compute tensor stage rebuilds each pixel's ray from the inverse projection where the fragment pass
// interpolates it, which moves world positions in their last bits.
TEST_F(FabricRender, ComputePassesDrawTheFragmentPassesImages) {
  AxialScene s;
  const TensorField field = reference::constantField(s.grid, {1, 1, 0});
  // A hole of missing voxels in the middle: the data's smooth edge in view.
  TensorField holed = field;
  if (holed.valid.empty()) holed.valid.assign(holed.tensors.size(), 1);
  const glm::ivec3 d = holed.grid.dims;
  for (int k = 0; k < d.z; ++k)
    for (int j = 0; j < d.y; ++j)
      for (int i = 0; i < d.x; ++i)
        if (glm::length(glm::vec2(i - d.x / 2, j - d.y / 2)) < 6.0f) {
          holed.at(i, j, k) = SymTensor{};
          holed.valid[holed.grid.index(i, j, k)] = 0;
        }
  std::vector<Image> images[2];
  unsigned covered[2] = {0, 0};
  int ramp[2] = {0, 0}; // pixels of the cover ramp (0 < cover < 1)
  for (int compute = 0; compute < 2; ++compute) {
    FabricRenderer r;
    r.setComputePasses(compute == 1);
    EXPECT_EQ(r.computePasses(), compute == 1);
    r.setMesh(s.mesh);
    r.setField(field);
    r.resize(96, 96);
    Camera cam = Camera::standard(StandardView::Superior, s.lo, s.hi, 1.0);
    FabricParams p;
    images[compute].push_back(r.renderStill(cam, p));
    covered[compute] = r.coveredPixels();
    p.iterations = 3;
    r.renderFrame(cam, p);
    r.renderFrame(cam, p);
    images[compute].push_back(r.readback());
    cam.trackball({0, 0}, {0.05, 0});
    r.renderFrame(cam, p);
    images[compute].push_back(r.readback());
    // Moving at half the internal resolution (FabricParams::movingScale): the targets' own size.
    FabricParams half = p;
    half.movingScale = 0.5;
    cam.trackball({0, 0}, {0.05, 0});
    r.renderFrame(cam, half);
    images[compute].push_back(r.readback());
    // The cover ramp across the hole's edge, one pixel wide from the edge field's screen-space change.
    r.setField(holed);
    images[compute].push_back(r.renderStill(cam, FabricParams{}));
    const Texture& t = r.projection().lambda();
    std::vector<std::uint8_t> lam(static_cast<std::size_t>(t.width()) * t.height() * 4);
    glGetTextureImage(t.id(), 0, GL_RGBA, GL_UNSIGNED_BYTE, static_cast<GLsizei>(lam.size()), lam.data());
    for (std::size_t k = 3; k < lam.size(); k += 4) ramp[compute] += lam[k] > 0 && lam[k] < 255;
  }
  EXPECT_EQ(covered[0], covered[1]);
  EXPECT_GT(covered[0], 96u * 96u / 2u);
  EXPECT_GT(ramp[0], 30);
  EXPECT_NEAR(ramp[1], ramp[0], ramp[0] / 10 + 2);
  ASSERT_EQ(images[0].size(), images[1].size());
  for (std::size_t i = 0; i < images[0].size(); ++i) {
    // Not an empty frame: most pixels drawn, and threads (bright and dark) among them.
    std::size_t drawn = 0, bright = 0, dark = 0, off = 0;
    int worst = 0;
    const auto& px = images[0][i].rgba;
    const auto& cx = images[1][i].rgba;
    ASSERT_EQ(px.size(), cx.size());
    for (std::size_t k = 0; k < px.size(); k += 4) {
      int d = 0;
      for (int c = 0; c < 4; ++c) d = std::max(d, std::abs(int(px[k + c]) - int(cx[k + c])));
      worst = std::max(worst, d);
      off += d > 2;
      if (px[k + 3] == 0) continue;
      ++drawn;
      const int sum = px[k] + px[k + 1] + px[k + 2];
      bright += sum > 300;
      dark += sum < 150;
    }
    EXPECT_GT(drawn, px.size() / 4 / 2) << "frame " << i;
    EXPECT_GT(bright, drawn / 20) << "frame " << i;
    EXPECT_GT(dark, drawn / 20) << "frame " << i;
    EXPECT_LE(off, px.size() / 4 / 200) << "frame " << i << ": pixels more than 2 levels apart; worst " << worst;
  }
}

// renderFrame and renderMovieFrame run a frame's last iteration in the composite's pass where they can
// (FabricRenderer::setFusedComposite): the images, the state and the count of changed pixels are those of
// the separate passes, in every look and option the fused pass takes, and the frames it cannot fuse (lower
// resolution while moving, the unsharp mask) take the separate passes.
TEST_F(FabricRender, TheFusedLastIterationDrawsTheSeparatePassesImages) {
  AxialScene s;
  TensorField field = reference::crossingField(s.grid, {1, 0.3, 0}, {-0.2, 1, 0.4}, 0.7);
  if (field.valid.empty()) field.valid.assign(field.tensors.size(), 1);
  const glm::ivec3 d = field.grid.dims;
  for (int k = 0; k < d.z; ++k) // a hole of missing voxels: the data's edge in view
    for (int j = 0; j < d.y; ++j)
      for (int i = 0; i < d.x; ++i)
        if (glm::length(glm::vec2(i - d.x / 2 - 4, j - d.y / 2)) < 5.0f) {
          field.at(i, j, k) = SymTensor{};
          field.valid[field.grid.index(i, j, k)] = 0;
        }
  const ScalarVolume grey = reference::sampleFunction(s.grid, [](const glm::dvec3& x) { return 0.5 + 0.01 * x.x; });
  struct Variant {
    const char* name;
    FabricParams p;
    bool background = false;
  };
  std::vector<Variant> variants;
  auto add = [&](const char* name, auto edit, bool background = false) {
    Variant v{name, FabricParams{}, background};
    v.p.iterations = 3;
    edit(v.p);
    variants.push_back(v);
  };
  add("anatomy", [](FabricParams&) {});
  add("anatomy over a background volume", [](FabricParams&) {}, true);
  add("plain", [](FabricParams& p) { p.look = Look::Plain; });
  add("plain over a background volume", [](FabricParams& p) { p.look = Look::Plain; }, true);
  add("dec-fa", [](FabricParams& p) { p.look = Look::DecFa; });
  add("engineering", [](FabricParams& p) {
    p.look = Look::Plain;
    p.colour = ColourMode::Engineering;
  });
  add("depth colour, fade out of plane", [](FabricParams& p) {
    p.depthColour = 0.6;
    p.fadeOutOfPlane = 0.5f;
  });
  add("no silhouettes, no lighting, no guard", [](FabricParams& p) {
    p.silhouette = false;
    p.lighting = false;
    p.guard = 0;
  });
  add("a coloured background, two iterations a frame", [](FabricParams& p) {
    p.background = {0.2f, 0.45f, 0.7f};
    p.iterations = 2;
  });
  add("one iteration a frame", [](FabricParams& p) { p.iterations = 1; });
  for (const Variant& v : variants) {
    SCOPED_TRACE(v.name);
    std::vector<Image> images[2];
    std::vector<unsigned> changed[2];
    bool fusedFrames = true;
    for (int fuse = 0; fuse < 2; ++fuse) {
      FabricRenderer r;
      r.setFusedComposite(fuse == 1);
      r.setMesh(s.mesh);
      r.setField(field);
      if (v.background) r.setBackground(&grey, 0.0f, 1.0f);
      r.resize(96, 80);
      Camera cam = Camera::standard(StandardView::Superior, s.lo, s.hi, 96.0 / 80.0);
      cam.zoom(1.1);
      // A restart, then frames that continue it past the point where a still could stop (they count).
      for (int f = 0; f < 14; ++f) {
        r.renderFrame(cam, v.p);
        if (fuse == 1) fusedFrames = fusedFrames && r.lastFrameFused();
        if (f % 3 == 0 || f == 13) images[fuse].push_back(r.readback());
        changed[fuse].push_back(r.changedPixels());
      }
      cam.trackball({0, 0}, {0.04, 0.02}); // moving: every pass again
      r.renderFrame(cam, v.p);
      images[fuse].push_back(r.readback());
      // A movie: its first frame converges as a still, the next ones reproject and advect.
      r.renderMovieFrame(cam, v.p, true);
      images[fuse].push_back(r.readback());
      for (int f = 0; f < 2; ++f) {
        cam.trackball({0, 0}, {0.03, 0.0});
        r.renderMovieFrame(cam, v.p, false);
        if (fuse == 1) fusedFrames = fusedFrames && r.lastFrameFused();
        images[fuse].push_back(r.readback());
      }
    }
    EXPECT_TRUE(fusedFrames);
    EXPECT_EQ(changed[0], changed[1]);
    ASSERT_EQ(images[0].size(), images[1].size());
    for (std::size_t i = 0; i < images[0].size(); ++i) {
      SCOPED_TRACE("image " + std::to_string(i));
      std::size_t lit = 0;
      for (std::size_t k = 0; k < images[0][i].rgba.size(); k += 4)
        lit += (images[0][i].rgba[k] | images[0][i].rgba[k + 1] | images[0][i].rgba[k + 2]) != 0;
      EXPECT_GT(lit, images[0][i].rgba.size() / 4 / 3); // the fabric fills much of the view
      EXPECT_EQ(images[0][i].rgba, images[1][i].rgba);
    }
  }
}

TEST_F(FabricRender, FramesTheFusedPassCannotDrawTakeTheSeparatePasses) {
  AxialScene s;
  FabricRenderer r;
  Camera cam = horizontalThreads(r, s);
  FabricParams p;
  p.iterations = 3;
  r.renderFrame(cam, p);
  EXPECT_TRUE(r.lastFrameFused());
  FabricParams half = p;
  half.movingScale = 0.5;
  cam.trackball({0, 0}, {0.05, 0});
  r.renderFrame(cam, half); // moving at half resolution
  EXPECT_FALSE(r.lastFrameFused());
  r.renderFrame(cam, half); // still: full resolution again
  EXPECT_TRUE(r.lastFrameFused());
  FabricParams sharp = p;
  sharp.sharpen = 0.5;
  r.renderFrame(cam, sharp);
  EXPECT_FALSE(r.lastFrameFused());
  r.setFusedComposite(false);
  r.renderFrame(cam, p);
  EXPECT_FALSE(r.lastFrameFused());
}
