// SPDX-License-Identifier: GPL-3.0-or-later
#include "io/formats/json.h"

#include "io/model/error.h"

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

namespace dtf::io {

nlohmann::ordered_json parseJson(std::string_view text, const std::string& origin) {
  try {
    return nlohmann::ordered_json::parse(text.begin(), text.end());
  } catch (const nlohmann::json::exception& e) {
    // Syntax errors and numbers out of double's range; e.what() reads "[json.exception.parse_error.101]
    // parse error at line 1, column 2: syntax error ..." or "[json.exception.out_of_range.406] number
    // overflow parsing '1e999'".
    std::string why = e.what();
    if (const auto p = why.find("] "); p != std::string::npos) why = why.substr(p + 2);
    throw InputError(origin + ": not valid JSON (" + why + ")");
  }
}

nlohmann::ordered_json readJsonFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot be read");
  std::stringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw InputError(path + ": read error");
  return parseJson(ss.str(), path);
}

namespace {

// nlohmann's one-line form with a space after each ':' and ',' outside strings (as Python's json.dumps
// writes it), so one-line reports stay readable. Whitespace only: the document is unchanged.
std::string spaced(const std::string& compact) {
  std::string o;
  o.reserve(compact.size() + compact.size() / 8);
  bool inString = false, escaped = false;
  for (char c : compact) {
    o += c;
    if (inString) {
      if (escaped)
        escaped = false;
      else if (c == '\\')
        escaped = true;
      else if (c == '"')
        inString = false;
    } else if (c == '"') {
      inString = true;
    } else if (c == ':' || c == ',') {
      o += ' ';
    }
  }
  return o;
}

template <typename Json> std::string text(const Json& j, int indent) {
  const std::string t = j.dump(indent, ' ', false, Json::error_handler_t::replace);
  return indent < 0 ? spaced(t) : t;
}

} // namespace

std::string jsonText(const nlohmann::ordered_json& j, int indent) {
  return text(j, indent);
}

std::string jsonText(const nlohmann::json& j, int indent) {
  return text(j, indent);
}

std::string jsonString(const nlohmann::ordered_json& j, const std::string& key) {
  if (!j.is_object()) return "";
  const auto it = j.find(key);
  return it != j.end() && it->is_string() ? it->get<std::string>() : std::string();
}

double jsonNumber(const nlohmann::ordered_json& j, const std::string& key) {
  if (!j.is_object()) return std::nan("");
  const auto it = j.find(key);
  return it != j.end() && it->is_number() ? it->get<double>() : std::nan("");
}

} // namespace dtf::io
