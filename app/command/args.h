// SPDX-License-Identifier: GPL-3.0-or-later
// Value parsers the option tables (app/command/options.h) share: sizes and index triples.
#pragma once

#include <string>

namespace dtf::app {

// Parses "W x H" such as "1024x768", each side in [minW, 8192] x [minH, 8192] pixels (the one size rule of
// the commands; UsageError "--size must lie between 16x16 and 8192x8192, got ..." otherwise).
void parseSize(const std::string& text, int& w, int& h, int minW = 16, int minH = 16);
// Parses "a,b,c" into three integers.
void parseTriple(const std::string& text, int out[3]);

} // namespace dtf::app
