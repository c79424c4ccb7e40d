// SPDX-License-Identifier: GPL-3.0-or-later
// JSON for every document dtfabric reads or writes (TRX headers, BIDS sidecars and derivative documents,
// the `--json` reports, the pages' embedded data), through nlohmann::json. This header declares only the
// forward types, so it stays cheap to include; a .cpp that builds or reads documents includes
// <nlohmann/json.hpp> itself.
#pragma once

#include <nlohmann/json_fwd.hpp>

#include <string>
#include <string_view>

namespace dtf::io {

// Parses `text` as one JSON document (RFC 8259; nothing but whitespace after it). Throws InputError
// "ORIGIN: not valid JSON (what, at byte N)" naming `origin`, e.g. a file path.
nlohmann::ordered_json parseJson(std::string_view text, const std::string& origin);

// The JSON document in the file at `path`. Throws InputError naming the path when it cannot be read or is
// not valid JSON.
nlohmann::ordered_json readJsonFile(const std::string& path);

// The document as text: `indent` < 0 gives one line with ", " and ": " between members (as Python's
// json.dumps), otherwise one member per line, nested members indented by that many spaces.
// Strings are written as UTF-8; bytes that are not valid UTF-8 (possible in file names) become U+FFFD
// instead of failing. NaN and infinities are written as null.
std::string jsonText(const nlohmann::ordered_json& j, int indent = -1);
std::string jsonText(const nlohmann::json& j, int indent = -1);

// The string member `key` of the object `j`; "" when `j` is not an object or the member is absent or not a
// string.
std::string jsonString(const nlohmann::ordered_json& j, const std::string& key);
// The number member `key` of the object `j`; NaN when `j` is not an object or the member is absent or not a
// number (null included: NaN is written as null).
double jsonNumber(const nlohmann::ordered_json& j, const std::string& key);

} // namespace dtf::io
