// SPDX-License-Identifier: GPL-3.0-or-later
// Every source file of the tree names its licence: an `SPDX-License-Identifier: GPL-3.0-or-later` line in a
// comment within its first 5 lines (line 1, or right after a shebang or a GLSL `#version`). Sources are the
// C++ and GLSL files, Python, CMake (CMakeLists.txt, *.cmake, *.cmake.in), shell scripts (*.sh and the
// scripts in .ci/), the workflow's Snakefile and Containerfile. The files are those git tracks or would track
// (untracked, not ignored), so a new file fails before it is committed; without git, a walk of the tree.
// The LICENSE file at the top holds the GPL version 3 text.
#include "support/test_env.h"

#include <array>
#include <cstdio>
#include <fstream>
#include <sstream>

namespace fs = std::filesystem;

namespace {

const std::string kIdentifier = "SPDX-License-Identifier: GPL-3.0-or-later";

// The comment marker a source file's SPDX line starts with: "//" for C++ and GLSL, "#" for Python, CMake,
// shell and the workflow files; "" for a file that is not a source (data, images, markdown, configuration).
std::string commentOf(const std::string& rel) {
  const fs::path p(rel);
  const std::string name = p.filename().string(), ext = p.extension().string();
  for (const char* e : {".h", ".cpp", ".glsl", ".vert", ".frag", ".geom", ".comp"})
    if (ext == e) return "//";
  if (ext == ".py" || ext == ".cmake" || ext == ".sh" || name == "CMakeLists.txt" || name == "Snakefile" ||
      name == "Containerfile" || (name.size() > 9 && name.compare(name.size() - 9, 9, ".cmake.in") == 0))
    return "#";
  if (rel.rfind(".ci/", 0) == 0 && rel.find('/', 4) == std::string::npos) return "#";
  return "";
}

// "" when `text` (a source with comment marker `comment`) carries the identifier line within its first 5
// lines; otherwise what is wrong.
std::string spdxProblem(const std::string& text, const std::string& comment) {
  std::istringstream in(text);
  std::string line;
  for (int i = 0; i < 5 && std::getline(in, line); ++i) {
    if (line.find("SPDX-License-Identifier") == std::string::npos) continue;
    if (line == comment + " " + kIdentifier) return "";
    return "names another licence or form on line " + std::to_string(i + 1) + ": \"" + line +
           "\" (expected \"" + comment + " " + kIdentifier + "\")";
  }
  return "has no \"" + comment + " " + kIdentifier + "\" line within its first 5 lines";
}

// The files git tracks or would track under `root` (root-relative); empty when git cannot list them.
std::vector<std::string> gitFiles(const fs::path& root) {
  const std::string cmd =
      "git -C '" + root.string() + "' ls-files -z --cached --others --exclude-standard 2>/dev/null";
  std::vector<std::string> files;
  FILE* pipe = popen(cmd.c_str(), "r");
  if (!pipe) return files;
  std::string all;
  std::array<char, 4096> buf;
  for (size_t n; (n = fread(buf.data(), 1, buf.size(), pipe)) > 0;)
    all.append(buf.data(), n);
  if (pclose(pipe) != 0) return {};
  std::istringstream in(all);
  for (std::string f; std::getline(in, f, '\0');)
    if (!f.empty()) files.push_back(f);
  return files;
}

// Without git: every file under `root`, leaving out hidden folders (except .ci) and build folders.
std::vector<std::string> walkedFiles(const fs::path& root) {
  std::vector<std::string> files;
  for (auto it = fs::recursive_directory_iterator(root); it != fs::recursive_directory_iterator(); ++it) {
    const std::string name = it->path().filename().string();
    if (it->is_directory() && ((name[0] == '.' && name != ".ci") || name.rfind("build", 0) == 0)) {
      it.disable_recursion_pending();
      continue;
    }
    if (it->is_regular_file()) files.push_back(fs::relative(it->path(), root).generic_string());
  }
  return files;
}

// One message per source file under `root` that lacks the identifier: "FILE has no ...".
std::vector<std::string> filesWithoutSpdx(const fs::path& root, const std::vector<std::string>& files,
                                          int* checked = nullptr) {
  std::vector<std::string> errors;
  int n = 0;
  for (const auto& rel : files) {
    const std::string comment = commentOf(rel);
    if (comment.empty() || !fs::is_regular_file(root / rel)) continue;
    std::ifstream in(root / rel, std::ios::binary);
    std::string head(1024, '\0');
    in.read(head.data(), static_cast<std::streamsize>(head.size()));
    head.resize(static_cast<size_t>(in.gcount()));
    if (const std::string p = spdxProblem(head, comment); !p.empty()) errors.push_back(rel + " " + p);
    ++n;
  }
  if (checked) *checked = n;
  return errors;
}

void writeFile(const fs::path& root, const std::string& rel, const std::string& text) {
  fs::create_directories((root / rel).parent_path());
  std::ofstream(root / rel) << text;
}

} // namespace

TEST(Licence, EverySourceFileNamesItsLicence) {
  const fs::path root = dtf::test::sourceDir();
  std::vector<std::string> files = gitFiles(root);
  if (files.empty()) files = walkedFiles(root);
  int checked = 0;
  for (const auto& e : filesWithoutSpdx(root, files, &checked))
    ADD_FAILURE() << e;
  EXPECT_GT(checked, 400) << "the scan found almost no sources: is the source tree where expected?";
}

TEST(Licence, TheLicenceFileHoldsTheGplVersion3) {
  std::ifstream in(dtf::test::sourceDir() / "LICENSE");
  ASSERT_TRUE(in) << "no LICENSE file at the top of the source tree";
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_NE(text.str().find("GNU GENERAL PUBLIC LICENSE\n                       Version 3, 29 June 2007"),
            std::string::npos);
  EXPECT_NE(text.str().find("END OF TERMS AND CONDITIONS"), std::string::npos);
}

TEST(Licence, SourceKindsAndCommentMarkers) {
  EXPECT_EQ(commentOf("render/shader_program.cpp"), "//");
  EXPECT_EQ(commentOf("shaders/fabric/phong.frag"), "//");
  EXPECT_EQ(commentOf("shaders/common/eigen.glsl"), "//");
  EXPECT_EQ(commentOf("tests/python/test_load.py"), "#");
  EXPECT_EQ(commentOf("cmake/dtfabricConfig.cmake.in"), "#");
  EXPECT_EQ(commentOf("io/CMakeLists.txt"), "#");
  EXPECT_EQ(commentOf(".ci/setup"), "#");
  EXPECT_EQ(commentOf("app/workflow/Snakefile"), "#");
  EXPECT_EQ(commentOf("README.md"), "");
  EXPECT_EQ(commentOf("cmake/debian/changelog.in"), "");
  EXPECT_EQ(commentOf("sample_data/dwi.bvec"), "");
  EXPECT_EQ(commentOf("tests/baseline/images/x.png"), "");
}

// The checker on a small tree: each way of missing the line is reported with the file's name; the accepted
// forms (line 1, after a shebang, after #version, within 5 lines) are not.
TEST(Licence, TheCheckerNamesEachFileWithoutTheLine) {
  const fs::path root = dtf::test::scratchDir() / "tree";
  const std::string cpp = "// " + kIdentifier + "\n", sh = "# " + kIdentifier + "\n";
  writeFile(root, "io/a.cpp", cpp + "int a;\n");
  writeFile(root, "io/late.h", "// one\n// two\n// three\n// four\n" + cpp);
  writeFile(root, "shaders/x.frag", "#version 450 core\n" + cpp + "void main() {}\n");
  writeFile(root, ".ci/run", "#!/usr/bin/env bash\n" + sh + "true\n");
  writeFile(root, "notes.md", "no licence line needed\n");
  writeFile(root, "io/missing.cpp", "int b;\n");
  writeFile(root, "io/too_late.h", "//\n//\n//\n//\n//\n" + cpp);
  writeFile(root, "tools/x.py", "# SPDX-License-Identifier: MIT\n");
  writeFile(root, "cmake/y.cmake", cpp); // the C++ marker in a CMake file
  const std::vector<std::string> files = {"io/a.cpp",      "io/late.h",       "shaders/x.frag", ".ci/run",
                                          "notes.md",      "io/missing.cpp",  "io/too_late.h",  "tools/x.py",
                                          "cmake/y.cmake", "io/not_there.cpp"};
  int checked = 0;
  const auto errors = filesWithoutSpdx(root, files, &checked);
  EXPECT_EQ(checked, 8);
  ASSERT_EQ(errors.size(), 4u);
  EXPECT_EQ(errors[0].rfind("io/missing.cpp has no \"// SPDX-License-Identifier: GPL-3.0-or-later\"", 0), 0u)
      << errors[0];
  EXPECT_EQ(errors[1].rfind("io/too_late.h has no", 0), 0u) << errors[1];
  EXPECT_EQ(errors[2].rfind("tools/x.py names another licence or form on line 1", 0), 0u) << errors[2];
  EXPECT_EQ(errors[3].rfind("cmake/y.cmake names another licence or form on line 1", 0), 0u) << errors[3];

  // The walk finds the same sources, skipping build folders.
  writeFile(root, "build/gen.cpp", "int c;\n");
  const auto walked = walkedFiles(root);
  EXPECT_EQ(filesWithoutSpdx(root, walked).size(), 4u);
}
