// Value parsers the option tables (app/command/options.h) share: sizes and index triples.
#pragma once

#include <string>

namespace dtf::app {

// Parses "W x H" such as "1024x768".
void parseSize(const std::string& text, int& w, int& h);
// Parses "a,b,c" into three integers.
void parseTriple(const std::string& text, int out[3]);

} // namespace dtf::app
