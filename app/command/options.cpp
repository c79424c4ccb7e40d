// SPDX-License-Identifier: GPL-3.0-or-later
#include "app/command/options.h"

#include "app/command/args.h"
#include "io/formats/fibre_io.h"
#include "io/formats/tensor_io.h"
#include "io/model/error.h"
#include "render/fabric_options.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace dtf::app {

namespace {

std::string joined(const std::vector<std::string>& items, const std::string& sep, const std::string& last) {
  std::string out;
  for (std::size_t i = 0; i < items.size(); ++i)
    out += (i == 0 ? "" : i + 1 == items.size() ? last : sep) + items[i];
  return out;
}

// `text` wrapped at `width`, continuation lines indented by `indent` spaces; `used` is the length of the
// line the text continues. Explicit newlines in `text` start a new indented line.
std::string wrapped(const std::string& text, std::size_t used, std::size_t indent, std::size_t width) {
  std::string out;
  std::istringstream paragraphs(text);
  bool firstParagraph = true;
  for (std::string paragraph; std::getline(paragraphs, paragraph); firstParagraph = false) {
    if (!firstParagraph) {
      out += "\n" + std::string(indent, ' ');
      used = indent;
    }
    std::istringstream words(paragraph);
    bool first = true;
    for (std::string w; words >> w; first = false) {
      if (!first && used + 1 + w.size() > width) {
        out += "\n" + std::string(indent, ' ');
        used = indent;
      } else if (!first) {
        out += ' ';
        ++used;
      }
      out += w;
      used += w.size();
    }
  }
  return out;
}

} // namespace

// ---- ranges ----

Range closedRange(double lo, double hi) {
  return Range::closed(lo, hi);
}
Range atLeast(double lo) {
  return Range::atLeast(lo);
}
Range above(double lo) {
  return Range::above(lo);
}
Range aboveUpTo(double lo, double hi) {
  return {lo, hi, true, false};
}
Range anyNumber() {
  return Range{};
}

// ---- rows ----

CliOption CliOption::flag(std::string name, std::string help) {
  CliOption o;
  o.name = std::move(name);
  o.kind = Kind::Flag;
  o.help = std::move(help);
  return o;
}
CliOption CliOption::text(std::string name, std::string metavar, std::string help, std::string def) {
  CliOption o;
  o.name = std::move(name);
  o.metavar = std::move(metavar);
  o.kind = Kind::Text;
  o.help = std::move(help);
  o.defaultValue = std::move(def);
  return o;
}
CliOption CliOption::choice(std::string name, std::string metavar, std::vector<std::string> choices,
                            std::string def, std::string help) {
  CliOption o = text(std::move(name), std::move(metavar), std::move(help), std::move(def));
  o.kind = Kind::Choice;
  o.choices = std::move(choices);
  return o;
}
CliOption CliOption::number(std::string name, std::string metavar, double def, Range range,
                            std::string help) {
  CliOption o = text(std::move(name), std::move(metavar), std::move(help), shortestNumber(def));
  o.kind = Kind::Number;
  o.range = range;
  return o;
}
CliOption CliOption::integer(std::string name, std::string metavar, int def, Range range, std::string help) {
  CliOption o = text(std::move(name), std::move(metavar), std::move(help), std::to_string(def));
  o.kind = Kind::Integer;
  o.range = range;
  return o;
}
CliOption CliOption::list(std::string name, std::string metavar, std::string help) {
  CliOption o = text(std::move(name), std::move(metavar), std::move(help));
  o.kind = Kind::List;
  return o;
}
CliOption CliOption::required() && {
  synopsis = Synopsis::Required;
  return std::move(*this);
}
CliOption CliOption::hidden() && {
  synopsis = Synopsis::Hidden;
  return std::move(*this);
}
CliOption CliOption::under(std::string heading) && {
  group = std::move(heading);
  return std::move(*this);
}
CliOption CliOption::defaultSays(std::string note) && {
  defaultNote = std::move(note);
  return std::move(*this);
}
CliOption CliOption::checkedBy(void (*fn)(const std::string&)) && {
  check = fn;
  return std::move(*this);
}
CliOption CliOption::internalOnly() && {
  internal = true;
  synopsis = Synopsis::Hidden;
  return std::move(*this);
}
CliOption CliOption::noDefault() && {
  defaultValue.clear();
  return std::move(*this);
}
CliOption CliOption::measuredIn(std::string u) && {
  unit = std::move(u);
  return std::move(*this);
}
CliOption CliOption::alsoSays(const std::string& more) && {
  help += more;
  return std::move(*this);
}

CliOption CliOption::repeats() && {
  repeatable = true;
  return std::move(*this);
}

std::string CliOption::rangeText(bool inRange) const {
  const std::string r = range.text();
  if (unit.empty() || r.empty()) return r;
  const bool bounded = std::isfinite(range.lo) && std::isfinite(range.hi);
  return (inRange && bounded ? "in " : "") + r + " " + unit;
}

std::string CliOption::switchName() const {
  return name == "output" ? "-o" : "--" + name;
}

std::string CliOption::written() const {
  if (kind == Kind::Flag) return switchName();
  return switchName() + " " + metavar + (kind == Kind::List ? " ..." : "");
}

void CliOption::validate(const std::string& value) const {
  const std::string sw = "--" + name;
  switch (kind) {
  case Kind::Flag:
  case Kind::Text:
  case Kind::List:
    break;
  case Kind::Choice:
    if (std::find(choices.begin(), choices.end(), value) == choices.end())
      throw UsageError(sw + " must be " + joined(choices, ", ", " or ") + ", got '" + value + "'");
    break;
  case Kind::Number: {
    char* end = nullptr;
    const double v = std::strtod(value.c_str(), &end);
    if (value.empty() || *end != '\0' || !std::isfinite(v))
      throw UsageError("option " + sw + " expects a number, got '" + value + "'");
    if (!range.contains(v)) throw UsageError(sw + " must be " + rangeText(true) + ", got " + value);
    break;
  }
  case Kind::Integer: {
    // As the fabric table reads integers: any number text with an integral value ("3", "3.0", "3e2").
    char* end = nullptr;
    const double v = std::strtod(value.c_str(), &end);
    if (value.empty() || *end != '\0' || !std::isfinite(v) || v != std::floor(v) ||
        std::abs(v) > std::numeric_limits<int>::max())
      throw UsageError("option " + sw + " expects an integer, got '" + value + "'");
    if (!range.contains(v)) throw UsageError(sw + " must be " + rangeText(true) + ", got " + value);
    break;
  }
  }
  if (check) check(value);
}

std::string CliOption::fullHelp() const {
  std::string facts;
  if (!defaultNote.empty())
    facts = "default " + defaultNote;
  else if (!defaultValue.empty())
    facts = "default " + defaultValue;
  if ((kind == Kind::Number || kind == Kind::Integer) && !range.text().empty())
    facts += (facts.empty() ? "" : "; ") + rangeText();
  if (kind == Kind::Choice && help.find(choices.front()) == std::string::npos)
    facts = joined(choices, ", ", " or ") + (facts.empty() ? "" : "; " + facts);
  if (repeatable) facts += std::string(facts.empty() ? "" : "; ") + "may be given several times";
  return facts.empty() ? help : help + " (" + facts + ")";
}

// ---- tables ----

const CliOption* OptionTable::find(const std::string& name) const {
  for (const auto& o : options)
    if (o.name == name) return &o;
  return nullptr;
}

std::string OptionTable::synopsis() const {
  std::string out = positionals;
  bool hiddenOnes = false;
  for (const auto& o : options) {
    if (o.synopsis == CliOption::Synopsis::Hidden) {
      hiddenOnes = hiddenOnes || !o.internal;
      continue;
    }
    const std::string w = o.written();
    out += (out.empty() ? "" : " ") + (o.synopsis == CliOption::Synopsis::Required ? w : "[" + w + "]");
  }
  if (!synopsisTail.empty())
    out += (out.empty() ? "" : " ") + synopsisTail;
  else if (hiddenOnes)
    out += (out.empty() ? "" : " ") + std::string("[OPTIONS]");
  return out;
}

std::string OptionTable::help() const {
  constexpr std::size_t kWidth = 110;
  std::size_t column = 0;
  for (const auto& o : options)
    if (!o.internal) column = std::max(column, o.written().size());
  column = std::min<std::size_t>(column + 4, 28);

  // The usage line breaks between options, never inside "[--name VALUE]".
  std::string usage = synopsis();
  int depth = 0;
  for (char& ch : usage) {
    depth += ch == '[' ? 1 : ch == ']' ? -1 : 0;
    if (ch == ' ' && depth > 0) ch = '\x01';
  }
  const std::string lead = "usage: dtfabric " + command + " ";
  usage = wrapped(usage, lead.size(), lead.size(), kWidth);
  std::replace(usage.begin(), usage.end(), '\x01', ' ');
  std::string out = lead + usage + "\n";
  if (!intro.empty()) out += "\n" + intro + (intro.back() == '\n' ? "" : "\n");
  std::string heading = "\noptions:";
  bool headed = false;
  for (const auto& o : options) {
    if (o.internal) continue;
    if (!o.group.empty()) {
      heading = "\n" + o.group;
      headed = false;
    }
    if (!headed) {
      out += heading + "\n";
      headed = true;
    }
    std::string line = "  " + o.written();
    line.resize(std::max(line.size() + 2, column), ' ');
    out += line + wrapped(o.fullHelp(), line.size(), column, kWidth) + "\n";
  }
  if (!epilogue.empty()) out += "\n" + epilogue + (epilogue.back() == '\n' ? "" : "\n");
  return out;
}

// ---- parsing ----

ParsedOptions::ParsedOptions(const OptionTable& table, const CommandArgs& argv) : table_(&table) {
  for (const auto& a : argv)
    if (a == "--help") help_ = true;
  if (help_) return; // help wins over anything else on the line
  for (std::size_t i = 0; i < argv.size(); ++i) {
    const std::string& a = argv[i];
    std::string key, value;
    bool inlineValue = false;
    if (a.size() > 2 && a.rfind("--", 0) == 0) {
      key = a.substr(2);
      if (auto eq = key.find('='); eq != std::string::npos) {
        value = key.substr(eq + 1);
        key.resize(eq);
        inlineValue = true;
      }
    } else if (a == "-o") {
      key = "output";
    } else {
      positionals_.push_back(a);
      continue;
    }
    const CliOption* o = table.find(key);
    if (!o) throw UsageError("unknown option " + (a == "-o" ? std::string("-o") : "--" + key));
    const std::string sw = o->switchName();
    if (o->kind == CliOption::Kind::Flag) {
      if (inlineValue) throw UsageError("option " + sw + " takes no value");
      values_.emplace_back(key, "");
      continue;
    }
    if (o->kind == CliOption::Kind::List && !inlineValue) {
      // The values up to the next option, at least one.
      bool any = false;
      for (; i + 1 < argv.size() && argv[i + 1].rfind("--", 0) != 0 && argv[i + 1] != "-o"; ++i) {
        values_.emplace_back(key, argv[i + 1]);
        any = true;
      }
      if (!any) throw UsageError(sw + " needs at least one value");
      continue;
    }
    if (!inlineValue) {
      if (i + 1 >= argv.size()) throw UsageError("option " + sw + " needs a value");
      value = argv[++i];
    }
    o->validate(value);
    values_.emplace_back(key, value);
  }
  if (positionals_.size() > table.maxPositionals)
    throw UsageError("unexpected argument '" + positionals_[table.maxPositionals] + "'");
}

bool ParsedOptions::printHelpIfAsked() const {
  if (help_) std::fputs(table_->help().c_str(), stdout);
  return help_;
}

const std::string& ParsedOptions::positional(std::size_t n, const std::string& what) const {
  if (n >= positionals_.size()) throw UsageError("missing " + what);
  return positionals_[n];
}

const CliOption& ParsedOptions::row(const std::string& name) {
  const CliOption* o = table_->find(name);
  if (!o)
    throw std::logic_error("dtfabric " + table_->command + " reads --" + name +
                           ", which its option table lacks");
  read_.insert(name);
  return *o;
}

bool ParsedOptions::given(const std::string& name) {
  row(name);
  for (const auto& [k, v] : values_)
    if (k == name) return true;
  return false;
}

bool ParsedOptions::flag(const std::string& name) {
  if (row(name).kind != CliOption::Kind::Flag) throw std::logic_error("--" + name + " is not a flag");
  return given(name);
}

std::optional<std::string> ParsedOptions::get(const std::string& name) {
  if (row(name).kind == CliOption::Kind::Flag) throw std::logic_error("--" + name + " is a flag");
  std::optional<std::string> v;
  for (const auto& [k, val] : values_)
    if (k == name) v = val; // the last occurrence wins
  return v;
}

std::string ParsedOptions::text(const std::string& name) {
  return get(name).value_or(row(name).defaultValue);
}

std::string ParsedOptions::required(const std::string& name) {
  const std::string written = row(name).written();
  auto v = get(name);
  if (!v || v->empty()) throw UsageError("missing " + written);
  return *v;
}

double ParsedOptions::number(const std::string& name) {
  const CliOption& o = row(name);
  if (o.kind != CliOption::Kind::Number && o.kind != CliOption::Kind::Integer)
    throw std::logic_error("--" + name + " is not a number");
  const std::string v = text(name);
  if (v.empty()) throw std::logic_error("--" + name + " has no default and was not given");
  return std::strtod(v.c_str(), nullptr); // validated when parsed
}

int ParsedOptions::integer(const std::string& name) {
  if (row(name).kind != CliOption::Kind::Integer) throw std::logic_error("--" + name + " is not an integer");
  return static_cast<int>(number(name));
}

std::vector<std::string> ParsedOptions::all(const std::string& name) {
  if (!row(name).repeatable) throw std::logic_error("--" + name + " is not repeatable");
  std::vector<std::string> out;
  for (const auto& [k, v] : values_)
    if (k == name) out.push_back(v);
  return out;
}

std::vector<std::string> ParsedOptions::list(const std::string& name) {
  if (row(name).kind != CliOption::Kind::List) throw std::logic_error("--" + name + " is not a list");
  std::vector<std::string> out;
  for (const auto& [k, v] : values_)
    if (k == name) out.push_back(v);
  return out;
}

void ParsedOptions::finish() const {
  std::string unread;
  for (const auto& o : table_->options)
    if (!read_.count(o.name)) unread += " --" + o.name;
  if (!unread.empty())
    throw std::logic_error("dtfabric " + table_->command + " never reads" + unread + " of its option table");
}

std::optional<std::string> surfaceArgument(ParsedOptions& options) {
  static const std::pair<const char*, const char*> kForms[] = {{"surface", ""},
                                                               {"fa", "fa="},
                                                               {"slice", "slice="},
                                                               {"fibre-surface", "fibre="},
                                                               {"fibre-surface-voxel", "fibre-voxel="}};
  std::vector<std::string> specs;
  for (const auto& [name, prefix] : kForms)
    if (options.has(name))
      if (auto v = options.get(name)) specs.push_back(prefix + *v);
  if (specs.size() > 1) throw UsageError("give one surface (--surface, --fa, --slice or --fibre-surface)");
  if (specs.empty()) return std::nullopt;
  return specs[0];
}

std::vector<CliOption> fabricCliOptions() {
  using K = render::FabricOption::Kind;
  const render::FabricParams defaults;
  std::vector<CliOption> rows;
  for (const auto& f : render::fabricOptions()) {
    const double def = f.get(defaults);
    CliOption o;
    switch (f.kind) {
    case K::OnOff:
      o = CliOption::flag(std::string("no-") + f.name, std::string("no ") + f.help);
      break;
    case K::Choice:
      o = CliOption::text(f.name, f.metavar, f.help, render::formatFabricValue(f, def));
      break;
    case K::Number:
    case K::Integer: {
      o = f.kind == K::Number ? CliOption::number(f.name, f.metavar, def, f.range, f.help)
                              : CliOption::integer(f.name, f.metavar, static_cast<int>(def), f.range, f.help);
      break;
    }
    }
    rows.push_back(std::move(o).hidden());
  }
  return rows;
}

void checkTensorLayout(const std::string& value) {
  io::parseLayout(value); // throws UsageError naming the layouts
}

void checkSize(const std::string& value) {
  int w = 0, h = 0;
  parseSize(value, w, h);
}

void checkTriple(const std::string& value) {
  int ijk[3];
  parseTriple(value, ijk);
}

std::string layoutNamesText(LayoutNames which) {
  std::string s;
  for (auto l : {io::TensorLayout::Fsl, io::TensorLayout::Mrtrix, io::TensorLayout::Symmatrix,
                 io::TensorLayout::Dtitk})
    s += (s.empty() ? "" : ", ") + std::string(io::layoutName(l));
  if (which == LayoutNames::Tensor) return s;
  std::string f;
  for (auto l : {io::FibreLayout::MrtrixPeaks, io::FibreLayout::DipyPeaks, io::FibreLayout::Bedpostx})
    f += (f.empty() ? "" : ", ") + std::string(io::fibreLayoutName(l));
  return "tensor files (" + s + ") or fibre sets (" + f + ")";
}

CliOption layoutOption(LayoutNames which) {
  if (which == LayoutNames::Tensor)
    return CliOption::text("layout", "L", "tensor layout override (" + layoutNamesText(which) + ")", "auto")
        .checkedBy(checkTensorLayout);
  return CliOption::text("layout", "L", "layout override: " + layoutNamesText(which), "auto");
}

CliOption bvalOption() {
  return CliOption::text("bval", "F",
                         "treat INPUT as a DWI and fit tensors (FSL gradient table, with --bvec)");
}

CliOption bvecOption() {
  return CliOption::text("bvec", "F", "the DWI's gradient directions (with --bval)");
}

CliOption fitMaskOption() {
  return CliOption::text("mask", "M", "fit only where M is non-zero (same grid as the DWI)");
}

std::vector<CliOption> furnitureOptions() {
  using O = CliOption;
  return {
      O::flag("no-letters", "no orientation letters (L/R, A/P, S/I) at the image edges").hidden(),
      O::flag("no-legend", "no orientation legend (the world axes in DEC colours, bottom right)").hidden(),
      O::flag("no-scale-bar", "no scale bar in mm (bottom left; orthographic views)").hidden(),
      O::flag("no-colour-bar", "no colour bar of the tract value (right edge; with --tracts-color)").hidden(),
  };
}

render::FigureFurniture furnitureFrom(ParsedOptions& args) {
  render::FigureFurniture f;
  f.letters = !args.flag("no-letters");
  f.legend = !args.flag("no-legend");
  f.scaleBar = !args.flag("no-scale-bar");
  f.colourBar = !args.flag("no-colour-bar");
  return f;
}

CliOption pairedTensorOption(const std::string& forWhat) {
  return CliOption::text("tensor", "F", "fibre sets: a tensor volume on the same grid for " + forWhat);
}

} // namespace dtf::app
