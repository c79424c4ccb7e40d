// SPDX-License-Identifier: GPL-3.0-or-later
// GLSL programs built from the files embedded in dtf_shaders. Before compiling, `#include "common/x.glsl"`
// lines are expanded recursively (each file once), variant `#define`s are injected after `#version`, and
// `#line N fileIndex` directives are inserted so a compile error names the original file and line: the
// error message carries the table mapping file indices to names.
#pragma once

#include "render/gl_objects.h"

#include <cstddef>
#include <glm/glm.hpp>
#include <initializer_list>
#include <memory>
#include <span>
#include <string>
#include <type_traits>
#include <unordered_map>
#include <utility>
#include <vector>

namespace dtf::render {

struct ShaderSource {
  std::string text;               // expanded source, ready for glShaderSource
  std::vector<std::string> files; // #line file index -> embedded file name
};

// Expands `file` (a name relative to shaders/, e.g. "fabric/advection.frag") with its includes and the
// given defines ("NAME" or "NAME VALUE"). Throws GlError for a missing file or an include cycle.
ShaderSource preprocessShader(const std::string& file, const std::vector<std::string>& defines = {});
// A driver's compile log with its "index:line" (Mesa) and "index(line)" (NVIDIA) locations rewritten to
// "file:line" through `files`, followed by the index table.
std::string mapShaderLog(const std::string& log, const std::vector<std::string>& files);
// Preprocesses and compiles one stage; returns the shader object (the caller links and deletes it).
// Throws GlError with the file/line-mapped log.
GLuint compileShaderStage(GLenum stage, const std::string& file, const std::vector<std::string>& defines = {});

// A texture unit, image unit or atomic-counter binding of a program, named once in C++: its value, the
// GLSL define the shader declares it with (`layout(binding = UNIT_X) uniform sampler2D u_x;`) and the
// uniform it binds (so a check can compare the binding the GL reports with the value).
struct BindingName {
  GLuint value;
  const char* define;
  const char* uniform;
};
// "DEFINE VALUE" for every binding of the tables: injected into a program's GLSL, which does not compile
// without them (an undeclared name in a layout qualifier is an error).
std::vector<std::string> bindingDefines(std::initializer_list<std::span<const BindingName>> tables);
template <class E>
  requires std::is_enum_v<E>
constexpr GLuint unit(E e) {
  return static_cast<GLuint>(e);
}
// Binds `texture` to the texture unit of a program's unit enum.
template <class E>
  requires std::is_enum_v<E>
void bindTexture(E u, GLuint texture) {
  glBindTextureUnit(unit(u), texture);
}
// Binds `texture` to image unit `unit` for reading. The shader declares the image's format, which the texture
// must have (other formats read undefined values): throws GlError otherwise.
void bindReadImage(GLuint unit, const Texture& texture, GLenum format);
template <class E>
  requires std::is_enum_v<E>
void bindReadImage(E u, const Texture& texture, GLenum format) {
  bindReadImage(unit(u), texture, format);
}

// The uniform names of an enum E with enumerators 0 .. E::Count - 1, in order, from uniformName(E) (found
// by argument-dependent lookup; a switch over E, so a missing name is a -Wswitch error).
template <class E>
  requires std::is_enum_v<E>
std::vector<const char*> uniformNames() {
  std::vector<const char*> names;
  for (int i = 0; i < static_cast<int>(E::Count); ++i) names.push_back(uniformName(static_cast<E>(i)));
  return names;
}

class ShaderProgram {
public:
  ShaderProgram() = default;
  // Compiles and links a vertex + fragment program. Throws GlError with the file/line-mapped log. The
  // locations of `uniforms` are looked up once, after linking: set(E, v) with an enum whose values index
  // that list uses them (-1 where the uniform is unused in this program, which the GL ignores).
  ShaderProgram(const std::string& vertexFile, const std::string& fragmentFile,
                const std::vector<std::string>& defines = {}, const std::vector<const char*>& uniforms = {});
  // The same for any list of stages, e.g. {{GL_VERTEX_SHADER, "a.vert"}, {GL_GEOMETRY_SHADER, "a.geom"},
  // ...}.
  ShaderProgram(const std::vector<std::pair<GLenum, std::string>>& stages,
                const std::vector<std::string>& defines = {}, const std::vector<const char*>& uniforms = {});

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

  // The cached location of uniform `u` (its index in the constructor's `uniforms`).
  template <class E>
    requires std::is_enum_v<E>
  GLint location(E u) const {
    return locations_.at(static_cast<std::size_t>(u));
  }
  template <class E, class T>
    requires std::is_enum_v<E>
  void set(E u, const T& v) const {
    setAt(location(u), v);
  }

private:
  void setAt(GLint loc, float v) const { glProgramUniform1f(id(), loc, v); }
  void setAt(GLint loc, int v) const { glProgramUniform1i(id(), loc, v); }
  void setAt(GLint loc, bool v) const { glProgramUniform1i(id(), loc, v ? 1 : 0); }
  void setAt(GLint loc, const glm::ivec2& v) const { glProgramUniform2i(id(), loc, v.x, v.y); }
  void setAt(GLint loc, const glm::vec2& v) const { glProgramUniform2f(id(), loc, v.x, v.y); }
  void setAt(GLint loc, const glm::vec3& v) const { glProgramUniform3f(id(), loc, v.x, v.y, v.z); }
  void setAt(GLint loc, const glm::vec4& v) const { glProgramUniform4f(id(), loc, v.x, v.y, v.z, v.w); }
  void setAt(GLint loc, const glm::mat4& m) const;
  void setAt(GLint loc, const glm::mat3& m) const;

  ProgramHandle program_;
  std::vector<GLint> locations_;
};

// Compile-time variants of one program (vertex + fragment, or any list of stages): bit i of a variant mask defines the i-th name.
// Features are switched by defines rather than uniform branches because a software rasteriser (llvmpipe)
// executes both sides of a branch. A variant is compiled on first use and kept, so frames never compile
// after the first use of a setting.
class ShaderVariants {
public:
  static constexpr int kMaxDefines = 16;
  // `always`: defines of every variant (the program's bindings); `uniforms` as for ShaderProgram.
  ShaderVariants(std::string vertexFile, std::string fragmentFile, std::vector<std::string> defines,
                 std::vector<std::string> always = {}, std::vector<const char*> uniforms = {});
  // The same for any list of stages (e.g. one compute shader: {{GL_COMPUTE_SHADER, "a.comp"}}).
  ShaderVariants(std::vector<std::pair<GLenum, std::string>> stages, std::vector<std::string> defines,
                 std::vector<std::string> always = {}, std::vector<const char*> uniforms = {});
  // The program with the defines of `mask` (bit i = defines[i]). Throws GlError on a compile failure.
  const ShaderProgram& get(unsigned mask);

private:
  std::vector<std::pair<GLenum, std::string>> stages_;
  std::vector<std::string> defines_, always_;
  std::vector<const char*> uniforms_;
  std::unordered_map<unsigned, std::unique_ptr<ShaderProgram>> programs_; // by mask, as compiled
};

} // namespace dtf::render
