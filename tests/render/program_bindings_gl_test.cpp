// SPDX-License-Identifier: GPL-3.0-or-later
// The texture units, atomic-counter bindings and uniforms of the pass programs are named once in C++
// (render/program_bindings.h) and injected into the GLSL as defines. These tests compile every program in
// variants that together use all of its bindings and uniforms, and check that the binding the GL reports for
// each sampler / atomic counter equals the C++ value, that every named uniform exists, and that a program
// compiled without its injected bindings fails with an error naming a missing define.
#include "render/program_bindings.h"
#include "render/shader_program.h"
#include "support/gl_test.h"

#include <set>
#include <string>
#include <vector>

using namespace dtf;
using namespace dtf::render;

namespace {

class ProgramBindings : public GlTest {};

struct ProgramCase {
  std::string name, vertex, fragment;
  std::span<const BindingName> bindings;
  std::vector<const char*> uniforms;
  std::vector<std::vector<std::string>> variants; // each compiled with the bindings' defines added
  std::string geometry = {};                      // a geometry stage between them ("" none)
  std::string compute = {};                       // a compute program's one stage (vertex, fragment unused)
};

// The program's stages as ShaderProgram takes them.
std::vector<std::pair<GLenum, std::string>> stagesOf(const ProgramCase& c) {
  if (!c.compute.empty()) return {{GL_COMPUTE_SHADER, c.compute}};
  std::vector<std::pair<GLenum, std::string>> stages = {{GL_VERTEX_SHADER, c.vertex}};
  if (!c.geometry.empty()) stages.emplace_back(GL_GEOMETRY_SHADER, c.geometry);
  stages.emplace_back(GL_FRAGMENT_SHADER, c.fragment);
  return stages;
}

ProgramCase withGeometry(ProgramCase c, std::string geometry) {
  c.geometry = std::move(geometry);
  return c;
}

template <class Program>
ProgramCase makeCase(std::string name, std::string vertex, std::string fragment,
                     std::vector<std::vector<std::string>> variants, std::vector<const char*> uniforms = {}) {
  return {std::move(name), std::move(vertex), std::move(fragment), std::span<const BindingName>(Program::kBindings),
          std::move(uniforms), std::move(variants)};
}

template <class Program>
ProgramCase computeCase(std::string name, std::string file, std::vector<std::vector<std::string>> variants,
                        std::vector<const char*> uniforms) {
  ProgramCase c = makeCase<Program>(std::move(name), "", "", std::move(variants), std::move(uniforms));
  c.compute = std::move(file);
  return c;
}

std::vector<ProgramCase> allPrograms() {
  return {
      makeCase<AdvectionProgram>("advection", "fabric/advection.vert", "fabric/advection.frag",
                                 {{}, {"FAR_PLANE", "COUNT", "THIRD"}, {"RESET"}, {"RESET", "THIRD"},
                                  {"RESET", "REPROJECT"}, {"RESET", "SILHOUETTES"}, {"RESET", "THIRD", "SILHOUETTES"}},
                                 uniformNames<AdvectionProgram::Uniform>()),
      computeCase<AdvectionComputeProgram>(
          "advection (compute)", "fabric/advection.comp",
          {{}, {"COUNT", "THIRD"}, {"RESET"}, {"RESET", "THIRD", "SILHOUETTES"}},
          {"u_k", "u_step", "u_complementSecond", "u_epsilon", "u_threshold", "u_background"}),
      makeCase<CompositeProgram>(
          "composite", "fabric/composite.vert", "fabric/composite.frag",
          {{},
           {"MEDICAL", "SILHOUETTES", "BACKGROUND", "DEPTH_COLOUR", "SHARPEN", "WINDOW_DEPTH", "FADE"},
           {"SILHOUETTES", "DEPTH_COLOUR", "SHARPEN", "FIBRES", "WINDOW_DEPTH", "ANATOMY"},
           {"MEDICAL", "DEC_FA", "FAR_PLANE"},
           {"MEDICAL", "SILHOUETTES", "FIBRES", "ADVECT", "THIRD", "COUNT", "FAR_PLANE"},
           {"DEPTH_COLOUR", "ANATOMY", "BACKGROUND", "ADVECT", "FAR_PLANE"}},
          uniformNames<CompositeProgram::Uniform>()),
      makeCase<CompositeDepthProgram>("composite depth", "fabric/composite.vert",
                                      "fabric/composite_depth.frag", {{}, {"BACKGROUND"}},
                                      uniformNames<CompositeDepthProgram::Uniform>()),
      makeCase<SilhouetteProgram>("silhouette", "fabric/silhouette.vert", "fabric/silhouette.frag",
                                  {{}, {"FAR_PLANE"}}, uniformNames<SilhouetteProgram::Uniform>()),
      makeCase<ProjectionProgram>("projection", "fabric/projection.vert", "fabric/projection.frag",
                                  {{"WITH_PRINCIPAL", "NOISE_BLEND", "BACKGROUND", "UNCERTAINTY"},
                                   {"NOISE_BLEND", "BACKGROUND", "FIBRES", "UNCERTAINTY"},
                                   {"WITH_PRINCIPAL", "BACKGROUND", "ALONG"},
                                   {"NOISE_BLEND", "BACKGROUND", "FIBRES", "UNCERTAINTY", "ALONG"}},
                                  uniformNames<ProjectionProgram::Uniform>()),
      computeCase<ProjectionComputeProgram>("projection (compute)", "fabric/projection.comp",
                                            {{"WITH_PRINCIPAL", "NOISE_BLEND", "BACKGROUND", "UNCERTAINTY"},
                                             {"NOISE_BLEND", "BACKGROUND", "FIBRES", "UNCERTAINTY"},
                                             {"WITH_PRINCIPAL", "BACKGROUND", "ALONG"},
                                             {"NOISE_BLEND", "BACKGROUND", "FIBRES", "UNCERTAINTY", "ALONG"}},
                                            uniformNames<ProjectionProgram::Uniform>()),
      makeCase<GeometryProgram>("geometry", "fabric/geometry.vert", "fabric/geometry.frag", {{}},
                                uniformNames<GeometryProgram::Uniform>()),
      makeCase<HostImportProgram>("host import", "fabric/host_import.vert", "fabric/host_import.frag", {{}},
                                  uniformNames<HostImportProgram::Uniform>()),
      makeCase<PhongProgram>("phong", "fabric/phong.vert", "fabric/phong.frag", {{}},
                             uniformNames<PhongProgram::Uniform>()),
      makeCase<TractLayerProgram>("tract layer", "common/fullscreen.vert", "tracts/layer.frag", {{}}),
      withGeometry(makeCase<TractLinesProgram>("tract lines", "tracts/lines.vert", "tracts/lines.frag", {{}},
                                               uniformNames<TractLinesProgram::Uniform>()),
                   "tracts/lines.geom"),
  };
}

// The binding the GL reports for an active sampler, image or atomic-counter uniform or a shader storage block,
// or -1 when it is not active.
GLint reportedBinding(GLuint program, const char* uniform) {
  const GLuint index = glGetProgramResourceIndex(program, GL_UNIFORM, uniform);
  if (index == GL_INVALID_INDEX) { // a shader storage block, named by its block name
    const GLuint block = glGetProgramResourceIndex(program, GL_SHADER_STORAGE_BLOCK, uniform);
    if (block == GL_INVALID_INDEX) return -1;
    const GLenum bindingProp = GL_BUFFER_BINDING;
    GLint binding = -1;
    glGetProgramResourceiv(program, GL_SHADER_STORAGE_BLOCK, block, 1, &bindingProp, 1, nullptr, &binding);
    return binding;
  }
  const GLenum typeProp = GL_TYPE;
  GLint type = 0;
  glGetProgramResourceiv(program, GL_UNIFORM, index, 1, &typeProp, 1, nullptr, &type);
  if (type == GL_UNSIGNED_INT_ATOMIC_COUNTER) {
    const GLenum bufferProp = GL_ATOMIC_COUNTER_BUFFER_INDEX;
    GLint buffer = -1;
    glGetProgramResourceiv(program, GL_UNIFORM, index, 1, &bufferProp, 1, nullptr, &buffer);
    const GLenum bindingProp = GL_BUFFER_BINDING;
    GLint binding = -1;
    glGetProgramResourceiv(program, GL_ATOMIC_COUNTER_BUFFER, static_cast<GLuint>(buffer), 1, &bindingProp, 1,
                           nullptr, &binding);
    return binding;
  }
  GLint unit = -1;
  glGetUniformiv(program, glGetUniformLocation(program, uniform), &unit);
  return unit;
}

} // namespace

TEST_F(ProgramBindings, TheGlReportsTheNamedBindingsAndEveryNamedUniformExists) {
  for (const ProgramCase& c : allPrograms()) {
    std::set<std::string> boundSeen, uniformSeen;
    for (const auto& variant : c.variants) {
      std::vector<std::string> defines = bindingDefines({c.bindings});
      defines.insert(defines.end(), variant.begin(), variant.end());
      ShaderProgram p(stagesOf(c), defines, c.uniforms);
      for (const BindingName& b : c.bindings) {
        const GLint reported = reportedBinding(p.id(), b.uniform);
        if (reported < 0) continue; // not used by this variant
        boundSeen.insert(b.define);
        EXPECT_EQ(reported, static_cast<GLint>(b.value)) << c.name << ": " << b.uniform << " (" << b.define << ")";
        // GL 4.5 guarantees 8 image units (GL_MAX_IMAGE_UNITS); llvmpipe has more, a GPU may not.
        if (std::string(b.define).rfind("IMAGE_", 0) == 0) {
          EXPECT_LT(reported, 8) << c.name << ": " << b.define;
        }
      }
      for (const char* u : c.uniforms)
        if (glGetUniformLocation(p.id(), u) >= 0) uniformSeen.insert(u);
    }
    for (const BindingName& b : c.bindings)
      EXPECT_TRUE(boundSeen.count(b.define)) << c.name << ": " << b.uniform << " is used by none of the variants";
    for (const char* u : c.uniforms)
      EXPECT_TRUE(uniformSeen.count(u)) << c.name << ": uniform " << u << " is active in none of the variants";
  }
}

TEST_F(ProgramBindings, DefineNamesAreUniqueWithinAProgram) {
  for (const ProgramCase& c : allPrograms()) {
    std::set<std::string> names;
    for (const BindingName& b : c.bindings) EXPECT_TRUE(names.insert(b.define).second) << c.name << ": " << b.define;
  }
}

TEST_F(ProgramBindings, AProgramWithoutItsBindingsDoesNotCompile) {
  int checked = 0;
  for (const ProgramCase& c : allPrograms()) {
    if (c.bindings.empty()) continue;
    try {
      ShaderProgram p(stagesOf(c), c.variants.front());
      ADD_FAILURE() << c.name << " compiled without its binding defines";
    } catch (const GlError& e) {
      const std::string msg = e.what();
      bool named = false;
      for (const BindingName& b : c.bindings) named = named || msg.find(b.define) != std::string::npos;
      EXPECT_TRUE(named) << c.name << ": the error names none of the binding defines:\n" << msg;
      ++checked;
    }
  }
  EXPECT_EQ(checked, 9); // advection and projection (both), composite and its depth, silhouette, host import,
                         // tract layer
  takeDebugMessages(); // the compiler's own debug messages about the failures are expected here
}

// A software rasteriser pays for each read of a uniform component in a fragment shader on every block of
// pixels (about four times a flat input's read), so the fullscreen passes hand their parameters on from
// their vertex shaders (three invocations a draw). A plain uniform read by one of their fragment shaders
// would bring that cost back; samplers, images and atomic counters are bindings, not values.
TEST_F(ProgramBindings, TheFullscreenPassesFragmentShadersReadNoPlainUniforms) {
  const std::set<std::string> fullscreen = {"advection", "composite", "composite depth", "projection",
                                            "host import", "silhouette"};
  const std::set<GLint> opaque = {GL_SAMPLER_2D,      GL_SAMPLER_3D,   GL_UNSIGNED_INT_SAMPLER_2D,
                                  GL_INT_SAMPLER_2D,  GL_IMAGE_2D,     GL_UNSIGNED_INT_IMAGE_2D,
                                  GL_INT_IMAGE_2D,    GL_UNSIGNED_INT_ATOMIC_COUNTER};
  std::set<std::string> checked;
  for (const ProgramCase& c : allPrograms()) {
    if (!fullscreen.count(c.name)) continue;
    for (const auto& variant : c.variants) {
      std::vector<std::string> defines = bindingDefines({c.bindings});
      defines.insert(defines.end(), variant.begin(), variant.end());
      ShaderProgram p(stagesOf(c), defines, c.uniforms);
      GLint count = 0;
      glGetProgramInterfaceiv(p.id(), GL_UNIFORM, GL_ACTIVE_RESOURCES, &count);
      ASSERT_GT(count, 0) << c.name; // its vertex shader's uniforms at least
      for (GLint i = 0; i < count; ++i) {
        const GLenum props[2] = {GL_TYPE, GL_REFERENCED_BY_FRAGMENT_SHADER};
        GLint v[2] = {0, 0};
        glGetProgramResourceiv(p.id(), GL_UNIFORM, static_cast<GLuint>(i), 2, props, 2, nullptr, v);
        if (!v[1] || opaque.count(v[0])) continue;
        char name[256] = {};
        glGetProgramResourceName(p.id(), GL_UNIFORM, static_cast<GLuint>(i), sizeof name, nullptr, name);
        std::string defs;
        for (const std::string& d : variant) defs += " " + d;
        ADD_FAILURE() << c.name << " [" << defs << " ]: the fragment shader reads the uniform " << name;
      }
      checked.insert(c.name);
    }
  }
  EXPECT_EQ(checked, fullscreen);
}
