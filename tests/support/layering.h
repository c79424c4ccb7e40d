// SPDX-License-Identifier: GPL-3.0-or-later
// The include graph of a source tree and the layering rules read from it: modules in an ordered table (each
// may include only itself and the lower modules it names), no include cycle between files, and no cycle
// between the folders of one top-level folder. Functions of a root path, so a test can run them on the real
// tree and on a synthetic one made to break a rule.
#pragma once

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <regex>
#include <set>
#include <string>
#include <vector>

namespace dtf::test::layering {

namespace fs = std::filesystem;

// `from` includes `to`; both root-relative ("io/dwi.cpp" includes "io/model/error.h").
struct Include {
  std::string from, to;
};

// A module and the modules below it whose headers it may include.
struct Layer {
  std::string module; // a folder, root-relative ("io/model", "app/cli")
  std::vector<std::string> may;
};

inline bool isSource(const fs::path& p) {
  return p.extension() == ".h" || p.extension() == ".cpp";
}

// Every `#include "X"` of the .h/.cpp files under root/<top> for each top, where root/X is a file of the
// tree (system and generated headers are not edges).
inline std::vector<Include> scanIncludes(const fs::path& root, const std::vector<std::string>& tops) {
  const std::regex inc(R"(^\s*#\s*include\s*\"([^\"]+)\")");
  std::vector<Include> edges;
  for (const auto& top : tops) {
    if (!fs::exists(root / top)) continue;
    for (const auto& entry : fs::recursive_directory_iterator(root / top)) {
      if (!entry.is_regular_file() || !isSource(entry.path())) continue;
      const std::string from = fs::relative(entry.path(), root).generic_string();
      std::ifstream in(entry.path());
      for (std::string line; std::getline(in, line);) {
        std::smatch m;
        if (std::regex_search(line, m, inc) && fs::is_regular_file(root / m[1].str()))
          edges.push_back({from, m[1].str()});
      }
    }
  }
  return edges;
}

// The module of a file: the longest module of the table that is a folder prefix of it; "" when none.
inline std::string moduleOf(const std::string& file, const std::vector<Layer>& table) {
  std::string best;
  for (const auto& l : table)
    if (file.rfind(l.module + "/", 0) == 0 && l.module.size() > best.size()) best = l.module;
  return best;
}

// The table's own order: every module a layer may include stands earlier in the table (so the permissions
// form no cycle: cli and bench cannot both include each other). One message per misplaced permission.
inline std::vector<std::string> tableOrderErrors(const std::vector<Layer>& table) {
  std::vector<std::string> errors;
  std::set<std::string> below;
  for (const auto& l : table) {
    for (const auto& m : l.may)
      if (!below.count(m)) errors.push_back(l.module + " may include " + m + ", which is not below it");
    below.insert(l.module);
  }
  return errors;
}

// Includes that leave the including file's module for one it may not include (a higher module, or one
// beside it that the table does not name). One message per include: "FILE includes HEADER (A -> B)".
inline std::vector<std::string> forbiddenIncludes(const std::vector<Include>& edges,
                                                  const std::vector<Layer>& table) {
  std::map<std::string, std::set<std::string>> may;
  for (const auto& l : table)
    may[l.module].insert(l.may.begin(), l.may.end());
  std::vector<std::string> errors;
  for (const auto& e : edges) {
    const std::string a = moduleOf(e.from, table), b = moduleOf(e.to, table);
    if (a.empty() || b.empty() || a == b || may[a].count(b)) continue;
    errors.push_back(e.from + " includes " + e.to + " (" + a + " -> " + b + ")");
  }
  return errors;
}

// The cycles of a directed graph: each strongly connected component of more than one node (or a node with
// an edge to itself), its nodes sorted.
inline std::vector<std::vector<std::string>>
cycles(const std::map<std::string, std::set<std::string>>& graph) {
  std::map<std::string, int> index, low;
  std::set<std::string> onStack;
  std::vector<std::string> stack;
  std::vector<std::vector<std::string>> found;
  int next = 0;
  std::function<void(const std::string&)> visit = [&](const std::string& v) {
    index[v] = low[v] = next++;
    stack.push_back(v);
    onStack.insert(v);
    if (auto it = graph.find(v); it != graph.end())
      for (const auto& w : it->second) {
        if (!index.count(w)) {
          visit(w);
          low[v] = std::min(low[v], low[w]);
        } else if (onStack.count(w)) {
          low[v] = std::min(low[v], index[w]);
        }
      }
    if (low[v] != index[v]) return;
    std::vector<std::string> component;
    std::string w;
    do {
      w = stack.back();
      stack.pop_back();
      onStack.erase(w);
      component.push_back(w);
    } while (w != v);
    const auto self = graph.find(v);
    if (component.size() > 1 || (self != graph.end() && self->second.count(v))) {
      std::sort(component.begin(), component.end());
      found.push_back(component);
    }
  };
  for (const auto& [v, _] : graph)
    if (!index.count(v)) visit(v);
  return found;
}

// The include graph between files.
inline std::map<std::string, std::set<std::string>> fileGraph(const std::vector<Include>& edges) {
  std::map<std::string, std::set<std::string>> g;
  for (const auto& e : edges)
    g[e.from].insert(e.to);
  return g;
}

// The include graph between the folders under `top` ("io", "io/model", "io/formats", ...): an edge where a
// file of one folder includes a file of another, both under `top`.
inline std::map<std::string, std::set<std::string>> folderGraph(const std::vector<Include>& edges,
                                                                const std::string& top) {
  std::map<std::string, std::set<std::string>> g;
  auto under = [&](const std::string& f) { return f.rfind(top + "/", 0) == 0; };
  for (const auto& e : edges) {
    if (!under(e.from) || !under(e.to)) continue;
    const std::string a = fs::path(e.from).parent_path().generic_string(),
                      b = fs::path(e.to).parent_path().generic_string();
    if (a != b) g[a].insert(b);
  }
  return g;
}

// The files `from` includes, directly or through other files of the graph (not `from` itself).
inline std::set<std::string> reachable(const std::map<std::string, std::set<std::string>>& graph,
                                       const std::string& from) {
  std::set<std::string> seen;
  std::vector<std::string> todo{from};
  while (!todo.empty()) {
    const std::string v = todo.back();
    todo.pop_back();
    if (auto it = graph.find(v); it != graph.end())
      for (const auto& w : it->second)
        if (seen.insert(w).second) todo.push_back(w);
  }
  return seen;
}

inline std::string joined(const std::vector<std::string>& nodes) {
  std::string s;
  for (const auto& n : nodes)
    s += (s.empty() ? "" : " <-> ") + n;
  return s;
}

} // namespace dtf::test::layering
