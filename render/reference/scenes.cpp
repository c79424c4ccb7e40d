// SPDX-License-Identifier: GPL-3.0-or-later
#include "render/reference/scenes.h"

#include "io/model/implicit_functions.h"

#include <array>
#include <cmath>
#include <map>

namespace dtf::render::reference {

Grid centredGrid(int n, double spacing) {
  glm::dmat4 a(1.0);
  for (int c = 0; c < 3; ++c) {
    a[c][c] = spacing;
    a[3][c] = -0.5 * (n - 1) * spacing;
  }
  return Grid::fromAffine(glm::ivec3(n), a);
}

namespace {
glm::dmat3 linearTensor(const glm::dvec3& d, double l1, double l2) {
  glm::dvec3 u = glm::normalize(d);
  glm::dmat3 dd = glm::outerProduct(u, u);
  return l1 * dd + l2 * (glm::dmat3(1.0) - dd);
}
void fill(TensorField& f, const std::function<glm::dmat3(const glm::dvec3&)>& t) {
  for (int k = 0; k < f.grid.dims.z; ++k)
    for (int j = 0; j < f.grid.dims.y; ++j)
      for (int i = 0; i < f.grid.dims.x; ++i) {
        std::size_t idx = f.grid.index(i, j, k);
        f.tensors[idx] = SymTensor::fromMat(t(f.grid.toWorld(glm::dvec3(i, j, k))));
        f.valid[idx] = 1;
      }
}
} // namespace

TensorField constantField(const Grid& grid, const glm::dvec3& d, double l1, double l2) {
  TensorField f = makeTensorField(grid);
  glm::dmat3 t = linearTensor(d, l1, l2);
  fill(f, [&](const glm::dvec3&) { return t; });
  return f;
}

TensorField crossingField(const Grid& grid, const glm::dvec3& da, const glm::dvec3& db, double a) {
  TensorField f = makeTensorField(grid);
  glm::dmat3 t = a * linearTensor(da, 1.7e-3, 0.3e-3) + (1 - a) * linearTensor(db, 1.7e-3, 0.3e-3);
  fill(f, [&](const glm::dvec3&) { return t; });
  return f;
}

TensorField hessianField(const Grid& grid, const std::function<double(const glm::dvec3&)>& fn, double h) {
  TensorField f = makeTensorField(grid);
  fill(f, [&](const glm::dvec3& p) {
    glm::dmat3 m(0.0);
    for (int a = 0; a < 3; ++a)
      for (int b = a; b < 3; ++b) {
        glm::dvec3 ea(0.0), eb(0.0);
        ea[a] = h;
        eb[b] = h;
        double v = (fn(p + ea + eb) - fn(p + ea - eb) - fn(p - ea + eb) + fn(p - ea - eb)) / (4 * h * h);
        m[a][b] = m[b][a] = v;
      }
    return m;
  });
  return f;
}

double sphereFunction(const glm::dvec3& p, double radius) {
  return glm::dot(p, p) + 1.5 / radius * p.x * p.y * p.z;
}

double bretzel5Function(const glm::dvec3& p, double scale) { return bretzel5(p / scale).f; }

ScalarVolume sampleFunction(const Grid& grid, const std::function<double(const glm::dvec3&)>& fn) {
  ScalarVolume v(grid, 1);
  for (int k = 0; k < grid.dims.z; ++k)
    for (int j = 0; j < grid.dims.y; ++j)
      for (int i = 0; i < grid.dims.x; ++i)
        v.at(i, j, k) = static_cast<float>(fn(grid.toWorld(glm::dvec3(i, j, k))));
  return v;
}

Mesh planeMesh(const glm::dvec3& c, const glm::dvec3& u, const glm::dvec3& v, double su, double sv, int n) {
  Mesh m;
  glm::dvec3 normal = glm::normalize(glm::cross(u, v));
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      glm::dvec3 p = c + u * (su * (double(i) / n - 0.5)) + v * (sv * (double(j) / n - 0.5));
      m.positions.emplace_back(p);
      m.normals.emplace_back(normal);
    }
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      std::uint32_t a = j * (n + 1) + i, b = a + 1, d = a + (n + 1), e = d + 1;
      m.indices.insert(m.indices.end(), {a, b, e, a, e, d});
    }
  return m;
}

Mesh uvSphere(const glm::dvec3& c, double r, int rings, int segments) {
  Mesh m;
  for (int i = 0; i <= rings; ++i) {
    double theta = M_PI * i / rings;
    for (int j = 0; j <= segments; ++j) {
      double phi = 2 * M_PI * j / segments;
      glm::dvec3 n(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
      m.positions.emplace_back(c + r * n);
      m.normals.emplace_back(n);
    }
  }
  const std::uint32_t row = segments + 1;
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      std::uint32_t a = i * row + j, b = a + 1, d = a + row, e = d + 1;
      if (i > 0) m.indices.insert(m.indices.end(), {a, d, b});
      if (i < rings - 1) m.indices.insert(m.indices.end(), {b, d, e});
    }
  return m;
}

Mesh marchingTetrahedra(const ScalarVolume& vol, double iso) {
  Mesh m;
  const Grid& g = vol.grid;
  // Vertices on grid edges are shared through a map keyed by the two voxel indices.
  std::map<std::pair<std::size_t, std::size_t>, std::uint32_t> edgeVertex;
  auto value = [&](const glm::ivec3& p) { return double(vol.at(p.x, p.y, p.z)); };
  auto gradient = [&](const glm::ivec3& p) {
    glm::dvec3 gr;
    for (int a = 0; a < 3; ++a) {
      glm::ivec3 lo = p, hi = p;
      lo[a] = std::max(p[a] - 1, 0);
      hi[a] = std::min(p[a] + 1, g.dims[a] - 1);
      gr[a] = (value(hi) - value(lo)) / std::max(hi[a] - lo[a], 1);
    }
    return gr;
  };
  glm::dmat3 lin(g.voxelToWorld);
  glm::dmat3 normalMat = glm::transpose(glm::inverse(lin));
  auto vertexOn = [&](const glm::ivec3& a, const glm::ivec3& b) {
    std::size_t ia = g.index(a.x, a.y, a.z), ib = g.index(b.x, b.y, b.z);
    auto key = ia < ib ? std::make_pair(ia, ib) : std::make_pair(ib, ia);
    if (auto it = edgeVertex.find(key); it != edgeVertex.end()) return it->second;
    double va = value(a), vb = value(b);
    double t = std::clamp((iso - va) / (vb - va), 0.0, 1.0);
    glm::dvec3 p = glm::mix(glm::dvec3(a), glm::dvec3(b), t);
    glm::dvec3 n = glm::mix(gradient(a), gradient(b), t);
    n = normalMat * n;
    double len = glm::length(n);
    m.positions.emplace_back(g.toWorld(p));
    m.normals.emplace_back(len > 0 ? n / len : glm::dvec3(0, 0, 1));
    auto idx = static_cast<std::uint32_t>(m.positions.size() - 1);
    edgeVertex.emplace(key, idx);
    return idx;
  };
  // Six tetrahedra around the cube diagonal 0-7.
  static const int tets[6][4] = {{0, 1, 3, 7}, {0, 3, 2, 7}, {0, 2, 6, 7}, {0, 6, 4, 7}, {0, 4, 5, 7}, {0, 5, 1, 7}};
  for (int k = 0; k + 1 < g.dims.z; ++k)
    for (int j = 0; j + 1 < g.dims.y; ++j)
      for (int i = 0; i + 1 < g.dims.x; ++i) {
        std::array<glm::ivec3, 8> c;
        for (int n = 0; n < 8; ++n) c[n] = glm::ivec3(i + (n & 1), j + ((n >> 1) & 1), k + ((n >> 2) & 1));
        for (const auto& t : tets) {
          std::array<glm::ivec3, 4> p = {c[t[0]], c[t[1]], c[t[2]], c[t[3]]};
          int inside[4], nIn = 0, outside[4], nOut = 0;
          for (int n = 0; n < 4; ++n) (value(p[n]) < iso ? inside[nIn++] : outside[nOut++]) = n;
          auto emit = [&](std::uint32_t a, std::uint32_t b, std::uint32_t d) {
            // Orient so the face normal agrees with the gradient normal (outward = increasing values).
            glm::vec3 fn = glm::cross(m.positions[b] - m.positions[a], m.positions[d] - m.positions[a]);
            if (glm::dot(fn, m.normals[a] + m.normals[b] + m.normals[d]) < 0) std::swap(b, d);
            m.indices.insert(m.indices.end(), {a, b, d});
          };
          if (nIn == 1 || nIn == 3) {
            int apex = nIn == 1 ? inside[0] : outside[0];
            const int* others = nIn == 1 ? outside : inside;
            emit(vertexOn(p[apex], p[others[0]]), vertexOn(p[apex], p[others[1]]), vertexOn(p[apex], p[others[2]]));
          } else if (nIn == 2) {
            std::uint32_t a = vertexOn(p[inside[0]], p[outside[0]]), b = vertexOn(p[inside[0]], p[outside[1]]);
            std::uint32_t d = vertexOn(p[inside[1]], p[outside[0]]), e = vertexOn(p[inside[1]], p[outside[1]]);
            emit(a, b, e);
            emit(a, e, d);
          }
        }
      }
  return m;
}

} // namespace dtf::render::reference
