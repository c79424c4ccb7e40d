// SPDX-License-Identifier: GPL-3.0-or-later
#include "app/command/args.h"

#include "io/model/error.h"

#include <charconv>
#include <cstdlib>
#include <sstream>

namespace dtf::app {

void parseSize(const std::string& text, int& w, int& h, int minW, int minH) {
  auto x = text.find('x');
  if (x == std::string::npos) throw UsageError("size must look like 1024x768, got '" + text + "'");
  try {
    std::size_t p1 = 0, p2 = 0;
    w = std::stoi(text.substr(0, x), &p1);
    h = std::stoi(text.substr(x + 1), &p2);
    if (p1 != x || p2 != text.size() - x - 1) throw std::invalid_argument("trailing");
  } catch (const std::exception&) {
    throw UsageError("size must look like 1024x768, got '" + text + "'");
  }
  constexpr int kMax = 8192;
  if (w < minW || h < minH || w > kMax || h > kMax)
    throw UsageError("--size must lie between " + std::to_string(minW) + "x" + std::to_string(minH) +
                     " and " + std::to_string(kMax) + "x" + std::to_string(kMax) + ", got " + text);
}

void parseTriple(const std::string& text, int out[3]) {
  std::stringstream ss(text);
  std::string part;
  int n = 0;
  while (std::getline(ss, part, ',')) {
    if (n >= 3) break;
    try {
      std::size_t p = 0;
      out[n] = std::stoi(part, &p);
      if (p != part.size()) throw std::invalid_argument("trailing");
    } catch (const std::exception&) {
      throw UsageError("expected three integers I,J,K, got '" + text + "'");
    }
    ++n;
  }
  if (n != 3 || ss.rdbuf()->in_avail() > 0)
    throw UsageError("expected three integers I,J,K, got '" + text + "'");
}

} // namespace dtf::app
