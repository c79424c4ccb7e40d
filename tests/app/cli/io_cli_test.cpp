// SPDX-License-Identifier: GPL-3.0-or-later
// `dtfabric info` and `dtfabric phantom` as a user runs them: exit codes, messages naming the file, text
// and JSON output (parsed back), on the real brain tensors and on malformed files made here.
#include "io/model/tensor_field.h"
#include "io/formats/tensor_io.h"
#include "support/test_env.h"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <gtest/gtest.h>
#include <map>
#include <memory>
#include <sys/wait.h>
#include <variant>

namespace fs = std::filesystem;
using namespace dtf;

namespace {

struct Result {
  int code = -1;
  std::string out; // stdout and stderr together
};

Result run(const std::string& args) {
  std::string cmd = std::string("\"") + DTF_EXE + "\" " + args + " 2>&1";
  Result r;
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return r;
  char buf[4096];
  std::size_t n;
  while ((n = std::fread(buf, 1, sizeof(buf), p)) > 0)
    r.out.append(buf, n);
  int status = pclose(p);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

// Just enough JSON to read dtfabric's output back: objects, arrays, strings, numbers, true/false/null.
struct JValue {
  std::variant<std::nullptr_t, bool, double, std::string, std::vector<JValue>, std::map<std::string, JValue>>
      v;
  const JValue& operator[](const std::string& k) const {
    return std::get<std::map<std::string, JValue>>(v).at(k);
  }
  const JValue& operator[](std::size_t i) const { return std::get<std::vector<JValue>>(v).at(i); }
  double num() const { return std::get<double>(v); }
  const std::string& str() const { return std::get<std::string>(v); }
  std::size_t size() const { return std::get<std::vector<JValue>>(v).size(); }
  bool has(const std::string& k) const { return std::get<std::map<std::string, JValue>>(v).count(k) > 0; }
};

class JParser {
public:
  explicit JParser(const std::string& s) : s_(s) {}
  JValue parseAll() {
    JValue v = value();
    ws();
    if (i_ != s_.size()) throw std::runtime_error("trailing characters at " + std::to_string(i_));
    return v;
  }

private:
  void ws() {
    while (i_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[i_])))
      ++i_;
  }
  char peek() {
    ws();
    if (i_ >= s_.size()) throw std::runtime_error("unexpected end");
    return s_[i_];
  }
  void expect(char c) {
    if (peek() != c) throw std::runtime_error(std::string("expected ") + c + " at " + std::to_string(i_));
    ++i_;
  }
  bool literal(const char* w) {
    if (s_.compare(i_, std::strlen(w), w) != 0) return false;
    i_ += std::strlen(w);
    return true;
  }
  std::string string() {
    expect('"');
    std::string out;
    while (i_ < s_.size() && s_[i_] != '"') {
      char c = s_[i_++];
      if (c == '\\') {
        char e = s_.at(i_++);
        if (e == 'u') {
          out += static_cast<char>(std::stoi(s_.substr(i_, 4), nullptr, 16));
          i_ += 4;
        } else {
          out += e == 'n' ? '\n' : e == 't' ? '\t' : e == 'r' ? '\r' : e;
        }
      } else {
        out += c;
      }
    }
    expect('"');
    return out;
  }
  JValue value() {
    char c = peek();
    JValue v;
    if (c == '{') {
      ++i_;
      std::map<std::string, JValue> m;
      if (peek() != '}') do {
          std::string k = string();
          expect(':');
          m[k] = value();
        } while (peek() == ',' && ++i_);
      expect('}');
      v.v = std::move(m);
    } else if (c == '[') {
      ++i_;
      std::vector<JValue> a;
      if (peek() != ']') do
          a.push_back(value());
        while (peek() == ',' && ++i_);
      expect(']');
      v.v = std::move(a);
    } else if (c == '"') {
      v.v = string();
    } else if (literal("true")) {
      v.v = true;
    } else if (literal("false")) {
      v.v = false;
    } else if (literal("null")) {
      v.v = nullptr;
    } else {
      std::size_t used = 0;
      v.v = std::stod(s_.substr(i_), &used);
      i_ += used;
    }
    return v;
  }
  const std::string& s_;
  std::size_t i_ = 0;
};

JValue parseJson(const std::string& text) {
  return JParser(text).parseAll();
}

std::vector<char> readBytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}
void writeBytes(const fs::path& p, const std::vector<char>& b) {
  std::ofstream(p, std::ios::binary | std::ios::trunc)
      .write(b.data(), static_cast<std::streamsize>(b.size()));
}

std::string q(const fs::path& p) {
  return "\"" + p.string() + "\"";
}

// Exit code 2 and a message that names the file.
void expectBadInput(const std::string& args, const fs::path& file, const std::string& fragment) {
  Result r = run(args);
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find(file.filename().string()), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(fragment), std::string::npos) << "expected '" << fragment << "' in: " << r.out;
}

const char* kTensor = "iu_prisma_dwi/derived/dti_tensor.nii.gz";

} // namespace

TEST(IoCli, InfoTextOnRealTensors) {
  DTF_SHARED_FILE(f, kTensor);
  Result r = run("info " + q(f));
  ASSERT_EQ(r.code, 0) << r.out;
  for (const char* s : {"NIfTI-1", "FLOAT32", "72 x 72 x 39 x 6", "sform", "LAS", "tensor layout: fsl",
                        "mm^2/s", "49040 valid", "FA:"})
    EXPECT_NE(r.out.find(s), std::string::npos) << "missing '" << s << "' in:\n" << r.out;
}

TEST(IoCli, InfoJsonOnRealTensors) {
  DTF_SHARED_FILE(f, kTensor);
  Result r = run("info --json " + q(f));
  ASSERT_EQ(r.code, 0) << r.out;
  JValue j = parseJson(r.out);
  EXPECT_EQ(j["layout"].str(), "fsl");
  EXPECT_FALSE(j["layout_reason"].str().empty());
  EXPECT_EQ(j["orientation"].str(), "LAS");
  EXPECT_EQ(j["affine_source"].str(), "sform");
  EXPECT_EQ(j["units"].str(), "mm^2/s");
  EXPECT_EQ(j["dims"].size(), 4u);
  EXPECT_EQ(j["dims"][3].num(), 6);
  EXPECT_EQ(j["affine"][0][0].num(), -3);
  EXPECT_NEAR(j["affine"][1][3].num(), -98.279, 1e-3);
  EXPECT_EQ(j["valid_voxels"].num(), 49040);
  EXPECT_EQ(j["nan_voxels"].num(), 0);
  EXPECT_NEAR(j["fa"]["mean"].num(), 0.2585, 0.002); // README: mean FA in the mask
  EXPECT_LT(j["component_ranges"]["xy"][0].num(), 0);
}

TEST(IoCli, InfoVoxelEigenvectorOnRealTensors) {
  DTF_SHARED_FILE(f, kTensor);
  Result r = run("info " + q(f) + " --voxel 33,42,22 --json");
  ASSERT_EQ(r.code, 0) << r.out;
  JValue j = parseJson(r.out);
  EXPECT_GT(std::abs(j["eigenvectors"][0][0].num()), 0.9); // corpus callosum: left-right
  EXPECT_NEAR(j["fa"].num(), 0.8463, 0.01);
  EXPECT_NEAR(j["md"].num(), 6.760e-4, 1e-6);
  EXPECT_GT(j["eigenvalues"][0].num(), j["eigenvalues"][1].num());
  EXPECT_NEAR(j["tensor_world"][0][1].num(), -1.1027e-4, 1e-8); // world xy: bvec xy negated (LAS)
  EXPECT_NEAR(j["ad"].num(), j["eigenvalues"][0].num(), 1e-12);
  for (const char* k : {"world", "rd"})
    EXPECT_TRUE(j.has(k)) << k;
  EXPECT_NEAR(j["world"][0].num(), 108 - 3 * 33, 1e-4);
  Result t = run("info " + q(f) + " --voxel 30,34,15");
  ASSERT_EQ(t.code, 0) << t.out;
  EXPECT_NE(t.out.find("FA 0.82"), std::string::npos) << t.out;
}

TEST(IoCli, InfoMrtrixNanVoxelIsCounted) {
  DTF_SHARED_FILE(f, "iu_prisma_dwi/derived/dti_tensor_mrtrix.nii.gz");
  Result r = run("info --json " + q(f));
  ASSERT_EQ(r.code, 0) << r.out;
  JValue j = parseJson(r.out);
  EXPECT_EQ(j["layout"].str(), "mrtrix");
  EXPECT_EQ(j["nan_voxels"].num(), 1);
  EXPECT_GE(j["warnings"].size(), 1u);
}

TEST(IoCli, InfoScalarAndVectorVolumes) {
  DTF_SHARED_FILE(fa, "niivue_fsl_dtifit/FA.nii.gz");
  DTF_SHARED_FILE(v1, "niivue_fsl_dtifit/V1.nii.gz");
  Result r = run("info " + q(fa));
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("not a tensor volume"), std::string::npos) << r.out;
  JValue j = parseJson(run("info --json " + q(fa)).out);
  EXPECT_FALSE(std::get<bool>(j["is_tensor"].v));
  EXPECT_NEAR(j["value_range"][1].num(), 1.2247, 1e-3);
  // V1 beside FA without L1-L3 is an FSL dtifit set's principal direction: a one-population fibre set.
  JValue v = parseJson(run("info --json " + q(v1)).out);
  EXPECT_TRUE(std::get<bool>(v["is_fibres"].v));
  EXPECT_EQ(v["fibre_layout"].str(), "dtifit-v1");
  EXPECT_EQ(v["max_fibres"].num(), 1);
  // Asked as tensors, a 3-volume file is bad input.
  expectBadInput("info --layout fsl " + q(v1), v1, "not a tensor volume");
}

TEST(IoCli, BadInputExitsTwoNamingTheFile) {
  auto dir = test::scratchDir();
  expectBadInput("info " + q(dir / "missing.nii.gz"), dir / "missing.nii.gz", "does not exist");

  TensorField f = makeTensorField(Grid::fromAffine({16, 16, 16}, glm::dmat4(1.0)));
  for (std::size_t i = 0; i < f.tensors.size(); ++i) {
    float s = 1e-4f * static_cast<float>(1 + (i * 7919) % 97);
    f.tensors[i] = {s, 0, 0, 2 * s, 0, 3 * s};
    f.valid[i] = 1;
  }
  auto good = dir / "good.nii.gz";
  io::writeTensorVolume(good.string(), f, io::TensorLayout::Fsl);
  auto bytes = readBytes(good);

  auto truncated = dir / "truncated.nii.gz";
  writeBytes(truncated,
             std::vector<char>(bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(bytes.size() / 2)));
  expectBadInput("info " + q(truncated), truncated, "truncated");

  auto corrupt = dir / "corrupt.nii.gz";
  auto c = bytes;
  for (std::size_t i = 12; i < c.size() - 8; i += 5)
    c[i] = static_cast<char>(c[i] ^ 0x5a);
  writeBytes(corrupt, c);
  expectBadInput("info " + q(corrupt), corrupt, corrupt.filename().string());

  // 7-D file asked as tensors.
  auto seven = dir / "seven.nii";
  io::writeScalarVolume(seven.string(), ScalarVolume(f.grid, 6, 1.0f));
  auto s = readBytes(seven);
  const int16_t dims7[8] = {7, 16, 16, 16, 1, 2, 3, 1};
  std::memcpy(s.data() + 40, dims7, sizeof(dims7));
  writeBytes(seven, s);
  expectBadInput("info --layout fsl " + q(seven), seven, "not a tensor volume");

  // COMPLEX64.
  auto cplx = dir / "complex.nii";
  io::writeScalarVolume(cplx.string(), ScalarVolume(f.grid, 2, 1.0f));
  s = readBytes(cplx);
  int16_t dt = 32, bitpix = 64;
  std::memcpy(s.data() + 70, &dt, 2);
  std::memcpy(s.data() + 72, &bitpix, 2);
  const int16_t dims3[8] = {3, 16, 16, 16, 1, 1, 1, 1};
  std::memcpy(s.data() + 40, dims3, sizeof(dims3));
  writeBytes(cplx, s);
  expectBadInput("info " + q(cplx), cplx, "unsupported datatype");

  // NIfTI-2 header claiming 100000^3 voxels.
  auto huge = dir / "huge.nii";
  io::writeScalarVolume(huge.string(), ScalarVolume(f.grid, 1, 1.0f), 2);
  s = readBytes(huge);
  for (int d = 1; d <= 3; ++d) {
    int64_t n = 100000;
    std::memcpy(s.data() + 16 + 8 * d, &n, 8);
  }
  writeBytes(huge, s);
  expectBadInput("info " + q(huge), huge, "absurd");

  // Every voxel NaN.
  auto nan = dir / "nan.nii";
  io::writeScalarVolume(nan.string(), ScalarVolume(f.grid, 6, NAN));
  expectBadInput("info " + q(nan), nan, "NaN");
}

TEST(IoCli, UsageErrorsExitOne) {
  DTF_SHARED_FILE(f, kTensor);
  Result r = run("info --layout bogus " + q(f));
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_NE(r.out.find("bogus"), std::string::npos) << r.out;
  EXPECT_EQ(run("info " + q(f) + " --voxel 1,2").code, 1);
  EXPECT_EQ(run("info " + q(f) + " --voxel 100,0,0").code, 1);
  EXPECT_EQ(run("info " + q(f) + " --frobnicate 3").code, 1);
  EXPECT_EQ(run("info").code, 1);
  EXPECT_EQ(run("phantom torus -o x.nii.gz").code, 1);
  EXPECT_EQ(run("phantom brain").code, 1);
}

TEST(IoCli, HelpDescribesOptions) {
  Result i = run("info --help");
  EXPECT_EQ(i.code, 0);
  EXPECT_NE(i.out.find("--voxel"), std::string::npos) << i.out;
  Result p = run("phantom --help");
  EXPECT_EQ(p.code, 0);
  EXPECT_NE(p.out.find("bretzel5"), std::string::npos) << p.out;
}

TEST(IoCli, PhantomBrainThenInfo) {
  auto dir = test::scratchDir();
  auto out = dir / "x.nii.gz", scalar = dir / "fa.nii.gz";
  Result r = run("phantom brain -o " + q(out) + " --size 32 --scalar " + q(scalar));
  ASSERT_EQ(r.code, 0) << r.out;
  ASSERT_TRUE(fs::exists(out));
  ASSERT_TRUE(fs::exists(scalar));
  JValue j = parseJson(run("info --json " + q(out)).out);
  EXPECT_EQ(j["layout"].str(), "fsl");
  EXPECT_EQ(j["orientation"].str(), "RAS");
  EXPECT_GT(j["valid_voxels"].num(), 1000);
  EXPECT_GT(j["fa"]["max"].num(), 0.75);
  // Every layout and NIfTI-2 read back as what was written.
  for (const char* layout : {"mrtrix", "symmatrix", "dtitk"}) {
    auto p = dir / (std::string(layout) + ".nii");
    ASSERT_EQ(
        run(std::string("phantom constant --size 8 --angle 60 --nifti2 --layout ") + layout + " -o " + q(p))
            .code,
        0);
    JValue k = parseJson(run("info --json " + q(p) + " --voxel 4,4,4").out);
    EXPECT_EQ(k["layout"].str(), layout);
    EXPECT_NEAR(k["eigenvectors"][0][0].num() * k["eigenvectors"][0][1].num(), 0.5 * std::sqrt(3.0) / 2,
                1e-5);
  }
}
