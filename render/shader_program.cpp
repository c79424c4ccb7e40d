// SPDX-License-Identifier: GPL-3.0-or-later
#include "render/shader_program.h"

#include "io/model/error.h"
#include "shaders/shader_sources.h"

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cstring>
#include <regex>
#include <sstream>

namespace dtf::render {

namespace {

struct Expander {
  ShaderSource out;
  std::vector<std::string> stack;
  std::vector<std::string> defines;
  bool versionSeen = false;

  int fileIndex(const std::string& name) {
    auto it = std::find(out.files.begin(), out.files.end(), name);
    if (it != out.files.end()) return static_cast<int>(it - out.files.begin());
    out.files.push_back(name);
    return static_cast<int>(out.files.size() - 1);
  }

  void expand(const std::string& name) {
    if (std::find(stack.begin(), stack.end(), name) != stack.end())
      throw GlError("shader include cycle through " + name);
    bool alreadyIncluded = std::find(out.files.begin(), out.files.end(), name) != out.files.end();
    if (alreadyIncluded && !stack.empty()) return; // each include once
    const char* src = shaders::find(name);
    if (!src) throw GlError("shader file not embedded: " + name + (stack.empty() ? "" : " (included from " + stack.back() + ")"));
    stack.push_back(name);
    int idx = fileIndex(name);
    static const std::regex includeRe(R"(^\s*#\s*include\s+\"([^\"]+)\")");
    static const std::regex versionRe(R"(^\s*#\s*version\b)");
    std::istringstream in(src);
    std::string line;
    int lineNo = 0;
    if (versionSeen) out.text += "#line 1 " + std::to_string(idx) + "\n";
    while (std::getline(in, line)) {
      ++lineNo;
      std::smatch m;
      if (std::regex_search(line, m, versionRe)) {
        if (!versionSeen) {
          versionSeen = true;
          out.text += line + "\n";
          for (const auto& d : defines) out.text += "#define " + d + "\n";
        }
        out.text += "#line " + std::to_string(lineNo + 1) + " " + std::to_string(idx) + "\n";
        continue;
      }
      if (std::regex_search(line, m, includeRe)) {
        expand(m[1]);
        out.text += "#line " + std::to_string(lineNo + 1) + " " + std::to_string(idx) + "\n";
        continue;
      }
      out.text += line + "\n";
    }
    stack.pop_back();
  }
};

} // namespace

// Mesa writes "0:12(3): error", NVIDIA "0(12) : error": both become "file:12".
std::string mapShaderLog(const std::string& log, const std::vector<std::string>& files) {
  std::string table = "\nfile indices:";
  for (std::size_t i = 0; i < files.size(); ++i) table += "\n  " + std::to_string(i) + " = " + files[i];
  static const std::regex loc(R"((^|\n)(\d+)(?::(\d+)|\((\d+)\)))");
  std::string mapped;
  std::sregex_iterator it(log.begin(), log.end(), loc), end;
  std::size_t last = 0;
  for (; it != end; ++it) {
    const auto& m = *it;
    mapped += log.substr(last, m.position() - last);
    std::size_t idx = std::stoul(m[2]);
    const std::string line = m[3].matched ? m[3].str() : m[4].str();
    mapped += m[1].str() + (idx < files.size() ? files[idx] : m[2].str()) + ":" + line;
    last = m.position() + m.length();
  }
  mapped += log.substr(last);
  return mapped + table;
}

ShaderSource preprocessShader(const std::string& file, const std::vector<std::string>& defines) {
  Expander e;
  e.defines = defines;
  e.expand(file);
  if (!e.versionSeen) throw GlError("shader " + file + " has no #version line");
  return std::move(e.out);
}

void bindReadImage(GLuint unit, const Texture& texture, GLenum format) {
  if (texture.format() != format) {
    std::ostringstream msg;
    msg << "image unit " << unit << ": the texture's format 0x" << std::hex << texture.format()
        << " is not the shader's 0x" << format;
    throw GlError(msg.str());
  }
  glBindImageTexture(unit, texture.id(), 0, GL_FALSE, 0, GL_READ_ONLY, format);
}

std::vector<std::string> bindingDefines(std::initializer_list<std::span<const BindingName>> tables) {
  std::vector<std::string> defines;
  for (const auto& table : tables)
    for (const BindingName& b : table) defines.push_back(std::string(b.define) + " " + std::to_string(b.value));
  return defines;
}

ShaderProgram::ShaderProgram(const std::string& vertexFile, const std::string& fragmentFile,
                             const std::vector<std::string>& defines,
                             const std::vector<const char*>& uniforms)
    : ShaderProgram({{GL_VERTEX_SHADER, vertexFile}, {GL_FRAGMENT_SHADER, fragmentFile}}, defines, uniforms) {
}

ShaderProgram::ShaderProgram(const std::vector<std::pair<GLenum, std::string>>& stages,
                             const std::vector<std::string>& defines,
                             const std::vector<const char*>& uniforms) {
  std::vector<GLuint> compiled;
  std::string files;
  try {
    for (const auto& [stage, file] : stages) {
      compiled.push_back(compileShaderStage(stage, file, defines));
      files += (files.empty() ? "" : " + ") + file;
    }
  } catch (...) {
    for (GLuint s : compiled)
      glDeleteShader(s);
    throw;
  }
  program_ = ProgramHandle(glCreateProgram());
  for (GLuint s : compiled)
    glAttachShader(program_.id(), s);
  glLinkProgram(program_.id());
  for (GLuint s : compiled)
    glDeleteShader(s);
  GLint ok = 0;
  glGetProgramiv(program_.id(), GL_LINK_STATUS, &ok);
  if (!ok) {
    GLint len = 0;
    glGetProgramiv(program_.id(), GL_INFO_LOG_LENGTH, &len);
    std::string log(static_cast<std::size_t>(std::max(len, 1)), '\0');
    glGetProgramInfoLog(program_.id(), len, nullptr, log.data());
    log.resize(std::strlen(log.c_str()));
    throw GlError("linking " + files + " failed:\n" + log);
  }
  locations_.reserve(uniforms.size());
  for (const char* name : uniforms) locations_.push_back(glGetUniformLocation(program_.id(), name));
}

void ShaderProgram::set(const char* name, const glm::mat4& m) const {
  glProgramUniformMatrix4fv(id(), location(name), 1, GL_FALSE, glm::value_ptr(m));
}
void ShaderProgram::set(const char* name, const glm::mat3& m) const {
  glProgramUniformMatrix3fv(id(), location(name), 1, GL_FALSE, glm::value_ptr(m));
}
void ShaderProgram::setAt(GLint loc, const glm::mat4& m) const {
  glProgramUniformMatrix4fv(id(), loc, 1, GL_FALSE, glm::value_ptr(m));
}
void ShaderProgram::setAt(GLint loc, const glm::mat3& m) const {
  glProgramUniformMatrix3fv(id(), loc, 1, GL_FALSE, glm::value_ptr(m));
}

GLuint compileShaderStage(GLenum stage, const std::string& file, const std::vector<std::string>& defines) {
  ShaderSource src = preprocessShader(file, defines);
  GLuint s = glCreateShader(stage);
  const char* text = src.text.c_str();
  glShaderSource(s, 1, &text, nullptr);
  glCompileShader(s);
  GLint ok = 0;
  glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    GLint len = 0;
    glGetShaderiv(s, GL_INFO_LOG_LENGTH, &len);
    std::string log(static_cast<std::size_t>(std::max(len, 1)), '\0');
    glGetShaderInfoLog(s, len, nullptr, log.data());
    log.resize(std::strlen(log.c_str())); // drop the terminating NUL(s)
    glDeleteShader(s);
    throw GlError("compiling " + file + " failed:\n" + mapShaderLog(log, src.files));
  }
  return s;
}

ShaderVariants::ShaderVariants(std::string vertexFile, std::string fragmentFile, std::vector<std::string> defines,
                               std::vector<std::string> always, std::vector<const char*> uniforms)
    : ShaderVariants({{GL_VERTEX_SHADER, std::move(vertexFile)}, {GL_FRAGMENT_SHADER, std::move(fragmentFile)}},
                     std::move(defines), std::move(always), std::move(uniforms)) {}

ShaderVariants::ShaderVariants(std::vector<std::pair<GLenum, std::string>> stages, std::vector<std::string> defines,
                               std::vector<std::string> always, std::vector<const char*> uniforms)
    : stages_(std::move(stages)), defines_(std::move(defines)), always_(std::move(always)),
      uniforms_(std::move(uniforms)) {
  if (defines_.size() > kMaxDefines) throw GlError("ShaderVariants: too many defines for " + stages_.back().second);
}

const ShaderProgram& ShaderVariants::get(unsigned mask) {
  mask &= (1u << defines_.size()) - 1u;
  auto& slot = programs_[mask];
  if (!slot) {
    std::vector<std::string> defines = always_;
    for (std::size_t i = 0; i < defines_.size(); ++i)
      if (mask & (1u << i)) defines.push_back(defines_[i]);
    slot = std::make_unique<ShaderProgram>(stages_, defines, uniforms_);
  }
  return *slot;
}

} // namespace dtf::render
