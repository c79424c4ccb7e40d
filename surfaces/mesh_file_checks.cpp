// SPDX-License-Identifier: GPL-3.0-or-later
// The checks of PLY and OBJ files before VTK's readers see them: vtkPLYReader trusts the header's element
// counts and reads past the end of a short binary file, and trusts the faces' vertex indices, their lengths
// and the presence of x, y, z and vertex_indices (heap corruption, a crash); vtkOBJReader reads a vertex
// coordinate it cannot parse ("nan", "inf") as 0.
#include "io/model/error.h"
#include "surfaces/detail/vtk_convert.h"

#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <sstream>
#include <vector>

namespace dtf::surfaces::detail {

namespace {

struct PlyProperty {
  int size = 0;      // bytes of a scalar, or of each list item
  int countSize = 0; // lists: bytes of the count (0: a scalar)
  bool countSigned = false;
  bool itemSigned = false, itemInteger = false; // lists: the items' type
  std::string name;
  bool isFaceIndices() const { return countSize && (name == "vertex_indices" || name == "vertex_index"); }
};

struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::vector<PlyProperty> properties;
};

// Bytes of a PLY scalar type (both the old names and the sized ones); 0 for an unknown name.
int plyTypeSize(const std::string& t, bool* isSigned = nullptr) {
  struct Type {
    const char* name;
    int size;
    bool isSigned;
  };
  static const Type kTypes[] = {
      {"char", 1, true},  {"int8", 1, true},    {"uchar", 1, false},  {"uint8", 1, false},
      {"short", 2, true}, {"int16", 2, true},   {"ushort", 2, false}, {"uint16", 2, false},
      {"int", 4, true},   {"int32", 4, true},   {"uint", 4, false},   {"uint32", 4, false},
      {"float", 4, true}, {"float32", 4, true}, {"double", 8, true},  {"float64", 8, true}};
  for (const Type& k : kTypes)
    if (t == k.name) {
      if (isSigned) *isSigned = k.isSigned;
      return k.size;
    }
  return 0;
}

// A list count of `size` bytes at p, in the file's byte order.
std::int64_t listCount(const unsigned char* p, int size, bool isSigned, bool bigEndian) {
  std::uint64_t u = 0;
  for (int i = 0; i < size; ++i)
    u |= std::uint64_t(p[bigEndian ? i : size - 1 - i]) << (8 * (size - 1 - i));
  if (!isSigned) return static_cast<std::int64_t>(u);
  const std::uint64_t sign = std::uint64_t(1) << (8 * size - 1);
  return static_cast<std::int64_t>((u ^ sign) - sign); // sign-extends
}

class PlyChecker {
public:
  explicit PlyChecker(const std::string& path) : path_(path), in_(path, std::ios::binary) {
    if (!in_) fail("cannot open the file");
  }

  void run() {
    readHeader();
    checkStructure();
    for (const PlyElement& e : elements_)
      binary_ ? checkBinary(e) : checkAscii(e);
  }

private:
  [[noreturn]] void fail(const std::string& why) const { throw InputError(path_ + ": " + why); }

  void readHeader() {
    std::string line;
    if (!std::getline(in_, line) || line.rfind("ply", 0) != 0) fail("not a PLY file (no 'ply' first line)");
    bool formatSeen = false;
    while (std::getline(in_, line)) {
      if (!line.empty() && line.back() == '\r') line.pop_back();
      std::istringstream words(line);
      std::string key;
      words >> key;
      if (key == "end_header") {
        if (!formatSeen) fail("the PLY header has no format line");
        return;
      }
      if (key == "format") {
        std::string f;
        words >> f;
        if (f != "ascii" && f != "binary_little_endian" && f != "binary_big_endian")
          fail("a PLY format '" + f + "' (ascii, binary_little_endian or binary_big_endian)");
        binary_ = f != "ascii";
        bigEndian_ = f == "binary_big_endian";
        formatSeen = true;
      } else if (key == "element") {
        PlyElement e;
        long long count = -1;
        if (!(words >> e.name >> count) || count < 0) fail("a malformed PLY element line '" + line + "'");
        e.count = static_cast<std::uint64_t>(count);
        elements_.push_back(e);
      } else if (key == "property") {
        if (elements_.empty()) fail("a PLY property before any element");
        elements_.back().properties.push_back(property(words, line));
      } else if (key != "comment" && key != "obj_info" && !key.empty()) {
        fail("an unknown PLY header line '" + line + "'");
      }
    }
    fail("the PLY header has no end_header line");
  }

  // What a surface needs: vertices with scalar x, y and z; faces (if any) with an integer list of vertex
  // indices.
  void checkStructure() {
    bool vertexSeen = false;
    for (const PlyElement& e : elements_) {
      if (e.name == "vertex") {
        vertexSeen = true;
        vertices_ = e.count;
        if (e.count == 0) fail("the PLY file has no vertices (element vertex 0)");
        for (const char* axis : {"x", "y", "z"}) {
          bool found = false;
          for (const PlyProperty& p : e.properties)
            found = found || (!p.countSize && p.name == axis);
          if (!found) fail(std::string("the PLY vertices have no scalar property '") + axis + "'");
        }
      } else if (e.name == "face" && e.count > 0) {
        bool found = false;
        for (const PlyProperty& p : e.properties) {
          if (!p.isFaceIndices()) continue;
          if (!p.itemInteger) fail("the PLY faces' " + p.name + " are not integers");
          found = true;
        }
        if (!found) fail("the PLY faces have no vertex_indices list");
      }
    }
    if (!vertexSeen) fail("the PLY file has no vertex element");
  }

  // A face's list of n vertex indices: at least three, each naming a vertex.
  void checkFace(std::uint64_t face, std::int64_t n, const std::vector<std::int64_t>& indices) const {
    if (n < 3)
      fail("face " + std::to_string(face) + " has " + std::to_string(n) + " vertices (a face needs 3)");
    for (std::int64_t i : indices)
      if (i < 0 || static_cast<std::uint64_t>(i) >= vertices_)
        fail("vertex index is out of range in face " + std::to_string(face) + ": " + std::to_string(i) +
             " (the file has " + std::to_string(vertices_) + " vertices)");
  }

  PlyProperty property(std::istringstream& words, const std::string& line) const {
    PlyProperty p;
    std::string type;
    words >> type;
    if (type == "list") {
      std::string countType, itemType;
      words >> countType >> itemType;
      p.countSize = plyTypeSize(countType, &p.countSigned);
      p.size = plyTypeSize(itemType, &p.itemSigned);
      p.itemInteger = itemType.rfind("float", 0) != 0 && itemType != "double";
      if (p.countSize == 0 || p.countSize == 8 || countType.rfind("float", 0) == 0 || countType == "double")
        fail("a PLY list count of type '" + countType + "' (an integer type)");
    } else {
      p.size = plyTypeSize(type);
    }
    if (p.size == 0 || !(words >> p.name)) fail("a malformed PLY property line '" + line + "'");
    return p;
  }

  // Walks every record of the binary body: the file must hold them all, each list count non-negative.
  void checkBinary(const PlyElement& e) {
    if (!bodyRead_) {
      body_.assign(std::istreambuf_iterator<char>(in_), {});
      bodyRead_ = true;
    }
    auto shortBy = [&](std::uint64_t record) {
      fail("the PLY header declares " + std::to_string(e.count) + " " + e.name +
           " records, but the file ends at " + e.name + " " + std::to_string(record) + " (truncated)");
    };
    std::uint64_t fixed = 0;
    bool lists = false;
    for (const PlyProperty& p : e.properties) {
      if (p.countSize)
        lists = true;
      else
        fixed += static_cast<std::uint64_t>(p.size);
    }
    const std::uint64_t left = body_.size() - at_;
    if (!lists) {
      if (fixed > 0 && left / fixed < e.count) shortBy(left / fixed);
      at_ += fixed * e.count;
      return;
    }
    const auto* p0 = reinterpret_cast<const unsigned char*>(body_.data());
    for (std::uint64_t r = 0; r < e.count; ++r)
      for (const PlyProperty& p : e.properties) {
        if (!p.countSize) {
          at_ += static_cast<std::uint64_t>(p.size);
          if (at_ > body_.size()) shortBy(r);
          continue;
        }
        if (at_ + static_cast<std::uint64_t>(p.countSize) > body_.size()) shortBy(r);
        const std::int64_t n = listCount(p0 + at_, p.countSize, p.countSigned, bigEndian_);
        if (n < 0)
          fail("a negative list length " + std::to_string(n) + " in " + e.name + " " + std::to_string(r));
        const std::uint64_t items = at_ + static_cast<std::uint64_t>(p.countSize);
        at_ = items + static_cast<std::uint64_t>(n) * static_cast<std::uint64_t>(p.size);
        if (at_ > body_.size()) shortBy(r);
        if (e.name == "face" && p.isFaceIndices()) {
          indices_.clear();
          for (std::int64_t i = 0; i < n; ++i)
            indices_.push_back(listCount(p0 + items + static_cast<std::uint64_t>(i * p.size), p.size,
                                         p.itemSigned, bigEndian_));
          checkFace(r, n, indices_);
        }
      }
  }

  // One record a line: enough numbers for its scalars and lists.
  void checkAscii(const PlyElement& e) {
    std::string line;
    for (std::uint64_t r = 0; r < e.count; ++r) {
      if (!std::getline(in_, line))
        fail("the PLY header declares " + std::to_string(e.count) + " " + e.name +
             " records, but the file ends at " + e.name + " " + std::to_string(r) + " (truncated)");
      std::istringstream words(line);
      for (const PlyProperty& p : e.properties) {
        double v = 0;
        if (!(words >> v)) fail("line of " + e.name + " " + std::to_string(r) + " is short or not numbers");
        if (!p.countSize) continue;
        if (v < 0 || v != static_cast<double>(static_cast<long long>(v)))
          fail("a list length " + std::to_string(v) + " in " + e.name + " " + std::to_string(r));
        const bool face = e.name == "face" && p.isFaceIndices();
        indices_.clear();
        std::string item;
        for (long long i = 0; i < static_cast<long long>(v); ++i) {
          if (!(words >> item)) fail("line of " + e.name + " " + std::to_string(r) + " ends inside its list");
          if (!face) continue;
          char* end = nullptr;
          errno = 0;
          const long long index = std::strtoll(item.c_str(), &end, 10);
          if (end == item.c_str() || *end != '\0' || errno == ERANGE)
            fail("face " + std::to_string(r) + ": vertex index '" + item + "' is not an integer");
          indices_.push_back(index);
        }
        if (face) checkFace(r, static_cast<std::int64_t>(v), indices_);
      }
    }
  }

  std::string path_;
  std::ifstream in_;
  bool binary_ = false, bigEndian_ = false;
  std::vector<PlyElement> elements_;
  std::string body_; // binary: the bytes after the header
  bool bodyRead_ = false;
  std::uint64_t at_ = 0;              // binary: the next record's offset in body_
  std::uint64_t vertices_ = 0;        // the vertex element's count
  std::vector<std::int64_t> indices_; // the face being checked
};

} // namespace

void checkPly(const std::string& path) {
  PlyChecker(path).run();
}

void checkObj(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open the file");
  std::string line;
  for (std::size_t n = 1; std::getline(in, line); ++n) {
    if (line.rfind("v ", 0) != 0 && line.rfind("v\t", 0) != 0) continue;
    std::istringstream words(line.substr(2));
    std::string word;
    int coordinates = 0;
    while (coordinates < 3 && words >> word) {
      char* end = nullptr;
      const double v = std::strtod(word.c_str(), &end);
      if (end == word.c_str() || *end != '\0' || !std::isfinite(v))
        throw InputError(path + ": line " + std::to_string(n) + ": vertex coordinate '" + word +
                         "' is not a finite number");
      ++coordinates;
    }
    if (coordinates < 3)
      throw InputError(path + ": line " + std::to_string(n) + ": a vertex needs three coordinates");
  }
}

} // namespace dtf::surfaces::detail
