// SPDX-License-Identifier: GPL-3.0-or-later
// The viewer scene's outputs and GL limits without a window (headless GL): camera files and screenshots
// never replace an input, replace an existing file only when forced (the GUI's overwrite prompt, a script's
// --force), and a tensor field beyond GL_MAX_3D_TEXTURE_SIZE ends in the error modal and a GL failure while
// the scene goes on to load a good file.
#include "app/viewer/viewer.h"
#include "io/formats/tensor_io.h"
#include "support/gl_test.h"

#include <chrono>
#include <epoxy/gl.h>
#include <filesystem>
#include <fstream>
#include <thread>

namespace fs = std::filesystem;
using namespace dtf;

namespace {

std::string readAll(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void settle(app::ViewerScene& scene) {
  for (int i = 0; i < 3000 && !scene.settled(); ++i) {
    scene.update();
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  scene.update();
}

std::string errors(const app::ViewerScene& scene) {
  std::string s;
  for (const auto& e : scene.state().errorChain)
    s += e + " | ";
  return s;
}

const fs::path kSample = test::sourceDir() / "sample_data" / "brain_phantom.nii.gz";

} // namespace

TEST(ViewerOutputs, ExistingFilesWaitForThePromptAndInputsAreRefused) {
  DTF_GL_TEST_SETUP();
  const fs::path dir = test::scratchDir();
  const fs::path volume = dir / "brain.nii.gz", cam = dir / "view.camera";
  fs::copy_file(kSample, volume);
  app::ViewerScene scene("slice=axial");
  scene.apply(session::LoadFile{volume.string(), "auto"});
  settle(scene);
  ASSERT_TRUE(scene.state().hasData) << errors(scene);

  // A new file is written at once.
  scene.apply(session::SaveCamera{cam.string()});
  EXPECT_TRUE(scene.state().errorChain.empty()) << errors(scene);
  EXPECT_NO_THROW(app::readCameraFile(cam.string()));
  // An existing one waits for the prompt; Cancel keeps it, Overwrite replaces it.
  std::ofstream(cam) << "precious";
  scene.apply(session::SaveCamera{cam.string()});
  EXPECT_EQ(scene.state().overwritePath, cam.string());
  EXPECT_EQ(readAll(cam), "precious");
  scene.apply(session::ConfirmOverwrite{false});
  EXPECT_TRUE(scene.state().overwritePath.empty());
  EXPECT_EQ(readAll(cam), "precious");
  scene.apply(session::SaveCamera{cam.string()});
  scene.apply(session::ConfirmOverwrite{true});
  EXPECT_TRUE(scene.state().overwritePath.empty());
  EXPECT_NO_THROW(app::readCameraFile(cam.string()));
  EXPECT_TRUE(scene.state().errorChain.empty()) << errors(scene);
  // A screenshot's prompt hands the window the forced action to perform.
  const fs::path shot = dir / "shot.png";
  std::ofstream(shot) << "precious";
  const session::Action shotAction = session::Screenshot{shot.string(), true};
  EXPECT_FALSE(scene.mayWrite(shot.string(), false, shotAction));
  EXPECT_EQ(scene.state().overwritePath, shot.string());
  const auto forced = scene.answerOverwrite(true);
  ASSERT_TRUE(forced && std::holds_alternative<session::Screenshot>(*forced));
  EXPECT_TRUE(std::get<session::Screenshot>(*forced).force);
  EXPECT_TRUE(std::get<session::Screenshot>(*forced).sceneOnly);
  EXPECT_TRUE(scene.mayWrite(shot.string(), true, *forced));

  // The loaded volume is an input: refused even when forced, and left as it was.
  const std::string before = readAll(volume);
  scene.apply(session::SaveCamera{volume.string(), true});
  ASSERT_FALSE(scene.state().errorChain.empty());
  EXPECT_NE(errors(scene).find("it is an input file"), std::string::npos) << errors(scene);
  EXPECT_EQ(readAll(volume), before);
  EXPECT_TRUE(scene.state().overwritePath.empty());
  scene.apply(session::DismissError{});

  // Without asking (a script), an existing file is an error naming it unless forced.
  scene.setAskBeforeOverwrite(false);
  std::ofstream(cam) << "precious";
  scene.apply(session::SaveCamera{cam.string()});
  EXPECT_NE(errors(scene).find(cam.string() + " exists (use --force"), std::string::npos) << errors(scene);
  EXPECT_EQ(readAll(cam), "precious");
  EXPECT_TRUE(scene.state().overwritePath.empty());
  scene.apply(session::DismissError{});
  scene.apply(session::SaveCamera{cam.string(), true});
  EXPECT_TRUE(scene.state().errorChain.empty()) << errors(scene);
  EXPECT_NO_THROW(app::readCameraFile(cam.string()));
  // Written through a temporary file: nothing but the outputs is left in the folder.
  for (const auto& e : fs::directory_iterator(dir))
    EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos) << e.path();
  EXPECT_FALSE(scene.glFailed());
}

TEST(ViewerOutputs, CameraFileInAMissingFolderIsAnInputError) {
  EXPECT_THROW(app::writeCameraFile("/nonexistent/folder/view.camera", render::Camera{}), InputError);
}

TEST(ViewerGlLimits, FieldBeyondTheMax3DTextureSizeIsAGlErrorAndTheSceneGoesOn) {
  DTF_GL_TEST_SETUP();
  GLint max3d = 0;
  glGetIntegerv(GL_MAX_3D_TEXTURE_SIZE, &max3d);
  ASSERT_GT(max3d, 0);
  if (max3d >= 32767) GTEST_SKIP() << "GL_MAX_3D_TEXTURE_SIZE " << max3d << " is beyond a NIfTI-1 axis";
  // One voxel wider than the limit along x, 2x2 across: a few MiB, well within memory.
  const fs::path dir = test::scratchDir();
  TensorField f = makeTensorField(Grid::fromAffine({max3d + 1, 2, 2}, glm::dmat4(1.0)));
  for (std::size_t i = 0; i < f.tensors.size(); ++i) {
    f.tensors[i] = SymTensor{1.7e-3f, 0, 0, 0.3e-3f, 0, 0.3e-3f};
    f.valid[i] = 1;
  }
  const fs::path wide = dir / "wide.nii";
  io::writeTensorVolume(wide.string(), f, io::TensorLayout::Mrtrix);

  app::ViewerScene scene("slice=axial");
  scene.apply(session::LoadFile{wide.string(), "auto"});
  settle(scene);
  ASSERT_TRUE(scene.state().hasData) << errors(scene);
  for (int i = 0; i < 5; ++i)
    scene.render(160, 120);
  const std::string e = errors(scene);
  EXPECT_NE(e.find("while rendering"), std::string::npos) << e;
  EXPECT_NE(e.find(std::to_string(max3d + 1) + "x2x2"), std::string::npos) << e;
  EXPECT_NE(e.find("3D texture size limit (" + std::to_string(max3d) + " voxels per axis)"),
            std::string::npos)
      << e;
  EXPECT_TRUE(scene.glFailed());
  // One error, not one per frame.
  const auto serial = scene.errorSerial();
  scene.apply(session::Rotate{10, 0});
  for (int i = 0; i < 3; ++i)
    scene.render(160, 120);
  EXPECT_EQ(scene.errorSerial(), serial);
  render::takeDebugMessages(); // the refused upload left none, but do not let it leak into the next test

  // The scene is still usable: a good file loads and renders to convergence.
  scene.apply(session::DismissError{});
  scene.apply(session::LoadFile{kSample.string(), "auto"});
  settle(scene);
  // Bounded by time: the frames of the viewer's motion window are interactive, however many fit in it.
  const auto t0 = std::chrono::steady_clock::now();
  while (!scene.converged() && std::chrono::steady_clock::now() - t0 < std::chrono::seconds(60)) {
    scene.update();
    scene.render(160, 120);
  }
  EXPECT_TRUE(scene.converged());
  EXPECT_TRUE(scene.state().errorChain.empty()) << errors(scene);
  EXPECT_EQ(scene.state().data.path, kSample.string());
}
