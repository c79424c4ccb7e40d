// GLSL programs built from the files embedded in dtf_shaders. Before compiling, `#include "common/x.glsl"`
// lines are expanded recursively (each file once), variant `#define`s are injected after `#version`, and
// `#line N fileIndex` directives are inserted so a compile error names the original file and line: the
// error message carries the table mapping file indices to names.
#pragma once

#include "render/gl_objects.h"

#include <glm/glm.hpp>

#include <array>
#include <memory>
#include <string>
#include <vector>

namespace dtf::render {

struct ShaderSource {
  std::string text;               // expanded source, ready for glShaderSource
  std::vector<std::string> files; // #line file index -> embedded file name
};

// Expands `file` (a name relative to shaders/, e.g. "fabric/advection.frag") with its includes and the
// given defines ("NAME" or "NAME VALUE"). Throws GlError for a missing file or an include cycle.
ShaderSource preprocessShader(const std::string& file, const std::vector<std::string>& defines = {});
// Preprocesses and compiles one stage; returns the shader object (the caller links and deletes it).
// Throws GlError with the file/line-mapped log.
GLuint compileShaderStage(GLenum stage, const std::string& file, const std::vector<std::string>& defines = {});

class ShaderProgram {
public:
  ShaderProgram() = default;
  // Compiles and links a vertex + fragment program. Throws GlError with the file/line-mapped log.
  ShaderProgram(const std::string& vertexFile, const std::string& fragmentFile,
                const std::vector<std::string>& defines = {});

  GLuint id() const { return program_.id(); }
  explicit operator bool() const { return bool(program_); }
  void use() const { glUseProgram(program_.id()); }
  // Uniform location by name (cached lookup is left to the GL); -1 when the uniform is unused.
  GLint location(const char* name) const { return glGetUniformLocation(program_.id(), name); }

  void set(const char* name, float v) const { glProgramUniform1f(id(), location(name), v); }
  void set(const char* name, int v) const { glProgramUniform1i(id(), location(name), v); }
  void set(const char* name, const glm::vec2& v) const { glProgramUniform2f(id(), location(name), v.x, v.y); }
  void set(const char* name, const glm::vec3& v) const {
    glProgramUniform3f(id(), location(name), v.x, v.y, v.z);
  }
  void set(const char* name, const glm::vec4& v) const {
    glProgramUniform4f(id(), location(name), v.x, v.y, v.z, v.w);
  }
  void set(const char* name, const glm::mat4& m) const;
  void set(const char* name, const glm::mat3& m) const;

private:
  ProgramHandle program_;
};

// Compile-time variants of one vertex + fragment program: bit i of a variant mask defines the i-th name.
// Features are switched by defines rather than uniform branches because a software rasteriser (llvmpipe)
// executes both sides of a branch. A variant is compiled on first use and kept, so frames never compile
// after the first use of a setting.
class ShaderVariants {
public:
  static constexpr int kMaxDefines = 7;
  ShaderVariants(std::string vertexFile, std::string fragmentFile, std::vector<std::string> defines,
                 std::vector<std::string> always = {});
  // The program with the defines of `mask` (bit i = defines[i]). Throws GlError on a compile failure.
  const ShaderProgram& get(unsigned mask);

private:
  std::string vertex_, fragment_;
  std::vector<std::string> defines_, always_;
  std::array<std::unique_ptr<ShaderProgram>, 1u << kMaxDefines> programs_;
};

} // namespace dtf::render
