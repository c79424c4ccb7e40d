#include "app/cli/args.h"

#include "io/model/error.h"

#include <charconv>
#include <cstdlib>
#include <sstream>

namespace dtf::app {

Args::Args(const std::vector<std::string>& argv, const std::set<std::string>& flags) {
  for (std::size_t i = 0; i < argv.size(); ++i) {
    const std::string& a = argv[i];
    if (a.size() > 2 && a.rfind("--", 0) == 0) {
      std::string key = a.substr(2), value;
      auto eq = key.find('=');
      if (eq != std::string::npos) {
        value = key.substr(eq + 1);
        key = key.substr(0, eq);
        if (flags.count(key)) throw UsageError("option --" + key + " takes no value");
        options_.emplace_back(key, value);
      } else if (flags.count(key)) {
        flagsGiven_.insert(key);
      } else {
        if (i + 1 >= argv.size()) throw UsageError("option --" + key + " needs a value");
        options_.emplace_back(key, argv[++i]);
      }
    } else if (a == "-o") {
      if (i + 1 >= argv.size()) throw UsageError("option -o needs a value");
      options_.emplace_back("output", argv[++i]);
    } else {
      positionals_.push_back(a);
    }
  }
}

const std::string& Args::positional(std::size_t n, const std::string& what) const {
  if (n >= positionals_.size()) throw UsageError("missing " + what);
  return positionals_[n];
}

bool Args::flag(const std::string& name) {
  used_.insert(name);
  return flagsGiven_.count(name) > 0;
}

std::optional<std::string> Args::get(const std::string& name) {
  used_.insert(name);
  std::optional<std::string> v;
  for (const auto& [k, val] : options_)
    if (k == name) v = val; // the last occurrence wins
  return v;
}

std::string Args::getOr(const std::string& name, const std::string& def) { return get(name).value_or(def); }

double Args::getDouble(const std::string& name, double def) {
  auto v = get(name);
  if (!v) return def;
  char* end = nullptr;
  double d = std::strtod(v->c_str(), &end);
  if (v->empty() || *end != '\0') throw UsageError("option --" + name + " expects a number, got '" + *v + "'");
  return d;
}

int Args::getInt(const std::string& name, int def) {
  auto v = get(name);
  if (!v) return def;
  int out = 0;
  auto [p, ec] = std::from_chars(v->data(), v->data() + v->size(), out);
  if (ec != std::errc() || p != v->data() + v->size())
    throw UsageError("option --" + name + " expects an integer, got '" + *v + "'");
  return out;
}

void Args::finish() const {
  for (const auto& [k, v] : options_)
    if (!used_.count(k)) throw UsageError("unknown option --" + k);
  for (const auto& f : flagsGiven_)
    if (!used_.count(f)) throw UsageError("unknown option --" + f);
}

void parseSize(const std::string& text, int& w, int& h) {
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
  if (w < 16 || h < 16 || w > 16384 || h > 16384) throw UsageError("size out of range 16..16384: " + text);
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
  if (n != 3 || ss.rdbuf()->in_avail() > 0) throw UsageError("expected three integers I,J,K, got '" + text + "'");
}

std::optional<std::string> surfaceArgument(Args& args) {
  std::vector<std::string> specs;
  if (auto v = args.get("surface")) specs.push_back(*v);
  if (auto v = args.get("fa")) specs.push_back("fa=" + *v);
  if (auto v = args.get("slice")) specs.push_back("slice=" + *v);
  if (auto v = args.get("fibre-surface")) specs.push_back("fibre=" + *v);
  if (auto v = args.get("fibre-surface-voxel")) specs.push_back("fibre-voxel=" + *v);
  if (specs.size() > 1) throw UsageError("give one surface (--surface, --fa, --slice or --fibre-surface)");
  if (specs.empty()) return std::nullopt;
  return specs[0];
}

} // namespace dtf::app
