// SPDX-License-Identifier: GPL-3.0-or-later
#include "app/cli/manual.h"

#include "app/bench/bench.h"
#include "app/cli/commands.h"
#include "app/command/options.h"
#include "io/model/error.h"

#include <cstdint>
#include <cstdio>
#include <map>
#include <sstream>

#ifndef DTF_VERSION
#define DTF_VERSION "unknown"
#endif

namespace dtf::app {

namespace {

const char* kExitStatus = "0 ok, 1 usage, 2 bad input, 3 GL/render failure.";

// The option tables behind a command, with a subsection title ("" for the command's own): `info` hands a
// tractogram to the tract table, `bench` hands each benchmark to its own.
std::vector<std::pair<std::string, const OptionTable*>> tablesOf(const Command& c) {
  std::vector<std::pair<std::string, const OptionTable*>> out;
  if (c.options) out.emplace_back("", &c.options());
  if (std::string(c.name) == "info") out.emplace_back("for a tractogram", &tractInfoOptions());
  if (std::string(c.name) == "bench")
    for (const auto& b : benchmarks())
      if (b.options) out.emplace_back(b.name, &b.options());
  return out;
}

const Command& commandNamed(const std::string& name) {
  for (const auto& c : commands())
    if (name == c.name) return c;
  throw UsageError("no man page named 'dtfabric-" + name + "'");
}

// ---- roff ----

// One UTF-8 sequence at text[i] as a code point; advances i past it (a stray byte stands for itself).
std::uint32_t nextCodePoint(const std::string& text, std::size_t& i) {
  const auto b = static_cast<unsigned char>(text[i]);
  int extra = b >= 0xF0 ? 3 : b >= 0xE0 ? 2 : b >= 0xC0 ? 1 : 0;
  std::uint32_t cp = extra == 3 ? b & 0x07 : extra == 2 ? b & 0x0F : extra == 1 ? b & 0x1F : b;
  ++i;
  for (; extra > 0 && i < text.size() && (static_cast<unsigned char>(text[i]) & 0xC0) == 0x80; --extra, ++i)
    cp = (cp << 6) | (static_cast<unsigned char>(text[i]) & 0x3F);
  return cp;
}

// Plain text as roff: backslashes escaped, non-ASCII as \[uXXXX], and in `code` (option names, file
// names, commands) '-' as the minus sign \- so that it can be copied from the page.
std::string escaped(const std::string& text, bool code) {
  std::string out;
  for (std::size_t i = 0; i < text.size();) {
    const char ch = text[i];
    if (static_cast<unsigned char>(ch) >= 0x80) {
      char buf[16];
      std::snprintf(buf, sizeof buf, "\\[u%04X]", static_cast<unsigned>(nextCodePoint(text, i)));
      out += buf;
      continue;
    }
    ++i;
    if (ch == '\\')
      out += "\\e";
    else if (ch == '-' && code)
      out += "\\-";
    else
      out += ch;
  }
  return out;
}

// The README's markdown (`code`, [text](link)) on one line as roff: code in bold.
std::string inlineText(const std::string& text) {
  std::string out;
  for (std::size_t i = 0; i < text.size();) {
    if (text[i] == '`') {
      const std::size_t end = text.find('`', i + 1);
      if (end != std::string::npos) {
        out += "\\fB" + escaped(text.substr(i + 1, end - i - 1), true) + "\\fR";
        i = end + 1;
        continue;
      }
    }
    if (text[i] == '[') {
      const std::size_t close = text.find("](", i);
      const std::size_t end = close == std::string::npos ? close : text.find(')', close);
      if (end != std::string::npos && text.find('\n', i) > end) {
        out += inlineText(text.substr(i + 1, close - i - 1));
        i = end + 1;
        continue;
      }
    }
    const std::size_t next = text.find_first_of("`[", i + 1);
    out += escaped(text.substr(i, next == std::string::npos ? std::string::npos : next - i), false);
    i = next == std::string::npos ? text.size() : next;
  }
  return out;
}

// A text line that roff does not take for a request.
std::string textLine(const std::string& roff) {
  std::size_t start = roff.find_first_not_of(' ');
  if (start == std::string::npos) return "";
  std::string line = roff.substr(start);
  if (line[0] == '.' || line[0] == '\'') line = "\\&" + line;
  return line + "\n";
}

// Help prose (a table's intro or epilogue): lines starting with spaces are kept as they are (the tables
// inside the prose), other lines are filled, blank lines separate paragraphs.
std::string prose(const std::string& text) {
  std::string out;
  bool verbatim = false;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) {
    const bool indented = line.rfind("  ", 0) == 0;
    if (indented != verbatim) {
      out += indented ? ".nf\n" : ".fi\n";
      verbatim = indented;
    }
    if (line.find_first_not_of(' ') == std::string::npos) {
      out += verbatim ? "\n" : ".PP\n";
    } else if (verbatim) {
      std::string roffLine = escaped(line, false);
      if (roffLine[0] == '.' || roffLine[0] == '\'') roffLine = "\\&" + roffLine;
      out += roffLine + "\n";
    } else {
      out += textLine(inlineText(line));
    }
  }
  if (verbatim) out += ".fi\n";
  return out;
}

std::string header(const std::string& name, const std::string& summary) {
  std::string upper;
  for (char ch : name) upper += static_cast<char>(ch >= 'a' && ch <= 'z' ? ch - 'a' + 'A' : ch);
  return ".\\\" Generated from dtfabric's option tables by `dtfabric help --man " + name + "`. Do not edit.\n" +
         ".TH " + escaped(upper, true) + " 1 \"\" \"dtfabric " DTF_VERSION "\" \"dtfabric manual\"\n" +
         ".nh\n.ad l\n.SH NAME\n" + escaped(name, true) + " \\- " + inlineText(summary) + "\n";
}

// "--near MM" as bold switch and italic metavariable.
std::string optionTerm(const CliOption& o) {
  const std::string w = o.written();
  const std::size_t space = w.find(' ');
  std::string term = "\\fB" + escaped(w.substr(0, space), true) + "\\fR";
  if (space != std::string::npos) term += " \\fI" + escaped(w.substr(space + 1), true) + "\\fR";
  return term;
}

std::string optionList(const OptionTable& t, const std::string& heading) {
  std::string out;
  bool headed = false;
  for (const auto& o : t.options) {
    if (o.internal) continue;
    if (!o.group.empty() || !headed) {
      std::string title = o.group.empty() ? heading : o.group;
      if (!title.empty() && title.back() == ':') title.pop_back();
      out += ".SS \"" + escaped(title, false) + "\"\n";
      headed = true;
    }
    // Lines of the help (a list of forms) stay lines.
    out += ".TP\n" + optionTerm(o) + "\n";
    std::istringstream lines(o.fullHelp());
    bool first = true;
    for (std::string line; std::getline(lines, line); first = false)
      out += (first ? "" : ".br\n") + textLine(inlineText(line));
  }
  out += ".TP\n\\fB\\-\\-help\\fR\nprint this help and exit\n";
  return out;
}

std::string seeAlso(const std::string& self) {
  std::string out = ".SH \"SEE ALSO\"\n";
  bool first = true;
  for (const auto& name : manPageNames()) {
    if (name == self) continue;
    out += (first ? "" : ",\n") + std::string("\\fB") + escaped(name, true) + "\\fR(1)";
    first = false;
  }
  return out + "\n";
}

std::string overviewPage() {
  std::string out = header("dtfabric", "fabric-like tensor LIC for diffusion MRI, headless and in a viewer");
  out += ".SH SYNOPSIS\n.B dtfabric\n\\fICOMMAND\\fR [\\fIARGS\\fR]\n.br\n.B dtfabric \\-\\-help\n.br\n"
         ".B dtfabric \\-\\-version\n";
  out += ".SH DESCRIPTION\n"
         "dtfabric shows diffusion-tensor MRI as a woven texture on a surface whose threads follow the tensor's "
         "two in-surface directions, coloured in the medical RGB code (red left\\[u2013]right, green "
         "anterior\\[u2013]posterior, blue superior\\[u2013]inferior): the image-space tensor LIC of Eichelbaum, "
         "Hlawitschka, Hamann and Scheuermann.\n"
         "It reads tensors, DWIs with their gradient tables, fibre sets and tractograms, renders headless "
         "through EGL, and opens a viewer.\n"
         ".PP\nEvery command has \\fB\\-\\-help\\fR and its own page, \\fBdtfabric\\-\\fR\\fICOMMAND\\fR(1).\n";
  out += ".SH COMMANDS\n";
  for (const auto& c : commands())
    out += ".TP\n\\fBdtfabric " + escaped(c.name, true) + "\\fR\n" + textLine(inlineText(summaryOf(c)));
  out += ".SH OPTIONS\n.TP\n\\fB\\-\\-help\\fR, \\fB\\-h\\fR\nlist the commands and exit\n"
         ".TP\n\\fB\\-\\-version\\fR\nprint the version and exit\n";
  out += ".SH \"EXIT STATUS\"\n" + textLine(kExitStatus);
  out += ".SH FILES\n.TP\n.I /usr/share/dtfabric/dwi.nii.gz\n"
         "a real whole-brain DWI with \\fIdwi.bval\\fR and \\fIdwi.bvec\\fR beside it (the bundled sample, "
         "under the installation prefix's \\fIshare/dtfabric\\fR; its provenance and license in "
         "\\fIREADME.md\\fR there)\n";
  out += ".SH EXAMPLES\n.nf\n"
         "dtfabric info /usr/share/dtfabric/dwi.nii.gz\n"
         "dtfabric render /usr/share/dtfabric/dwi.nii.gz \\-o axial.png \\-\\-surface slice=axial:22\n"
         "dtfabric view /usr/share/dtfabric/dwi.nii.gz\n.fi\n";
  return out + seeAlso("dtfabric");
}

std::string commandPage(const Command& c) {
  const std::string name = "dtfabric-" + std::string(c.name);
  std::string out = header(name, summaryOf(c));
  out += ".SH SYNOPSIS\n.B dtfabric " + escaped(c.name, true) + "\n" + textLine(escaped(synopsisOf(c), true));
  out += ".SH DESCRIPTION\n" + textLine(inlineText(descriptionOf(c)));
  const auto tables = tablesOf(c);
  if (tables.empty()) {
    out += ".SH OPTIONS\n.TP\n\\fB\\-\\-help\\fR\nprint this help and exit\n";
  }
  for (const auto& [title, table] : tables) {
    if (title.empty()) {
      if (!table->intro.empty()) out += ".PP\n" + prose(table->intro);
      out += ".SH OPTIONS\n" + optionList(*table, "Options");
      if (!table->epilogue.empty()) out += ".SH NOTES\n" + prose(table->epilogue);
      continue;
    }
    // A sub-table: its own section with its usage line.
    const bool bench = std::string(c.name) == "bench";
    out += ".SH \"" + escaped(bench ? "dtfabric bench " + title : "Options " + title, false) + "\"\n";
    out += ".B dtfabric " + escaped(table->command, true) + "\n" + textLine(escaped(table->synopsis(), true));
    if (!table->intro.empty()) out += ".PP\n" + prose(table->intro);
    out += optionList(*table, "Options");
    if (!table->epilogue.empty()) out += ".PP\n" + prose(table->epilogue);
  }
  out += ".SH \"EXIT STATUS\"\n" + textLine(kExitStatus);
  return out + seeAlso(name);
}

// ---- bash ----

std::string shellQuoted(const std::string& word) {
  std::string out = "'";
  for (char ch : word) out += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
  return out + "'";
}

std::string words(const std::vector<std::string>& list) {
  std::string joined;
  for (const auto& w : list) joined += (joined.empty() ? "" : " ") + w;
  return shellQuoted(joined);
}

// What completes after each option and which flags a command line takes, keyed by "render" or "bench io".
struct CompletionTable {
  std::vector<std::string> flags;
  std::map<std::string, std::vector<std::string>> choices; // option -> its values
  std::vector<std::string> fileValued;                       // options whose value is a path or text
  std::vector<std::string> numeric;                          // options whose value is a number: nothing
};

void addRows(CompletionTable& t, const OptionTable& table) {
  for (const auto& o : table.options) {
    if (o.internal) continue;
    const std::string sw = o.switchName();
    bool known = false;
    for (const auto& f : t.flags) known = known || f == sw;
    if (known) continue;
    t.flags.push_back(sw);
    switch (o.kind) {
    case CliOption::Kind::Flag:
      break;
    case CliOption::Kind::Choice:
      t.choices[sw] = o.choices;
      break;
    case CliOption::Kind::Number:
    case CliOption::Kind::Integer:
      t.numeric.push_back(sw);
      break;
    case CliOption::Kind::Text:
    case CliOption::Kind::List:
      t.fileValued.push_back(sw);
      break;
    }
  }
}

} // namespace

std::vector<std::string> manPageNames() {
  std::vector<std::string> names = {"dtfabric"};
  for (const auto& c : commands()) names.push_back("dtfabric-" + std::string(c.name));
  return names;
}

std::string manPage(const std::string& name) {
  if (name == "dtfabric") return overviewPage();
  if (name.rfind("dtfabric-", 0) != 0) throw UsageError("no man page named '" + name + "'");
  return commandPage(commandNamed(name.substr(9)));
}

std::string bashCompletion() {
  std::vector<std::pair<std::string, CompletionTable>> lines; // in the order of commands()
  std::vector<std::string> commandNames, benchNames;
  for (const auto& c : commands()) {
    commandNames.push_back(c.name);
    if (std::string(c.name) == "bench") {
      for (const auto& b : benchmarks()) {
        benchNames.push_back(b.name);
        CompletionTable t;
        if (b.options) addRows(t, b.options());
        t.flags.push_back("--help");
        lines.emplace_back("bench " + std::string(b.name), t);
      }
      continue;
    }
    CompletionTable t;
    for (const auto& [title, table] : tablesOf(c)) addRows(t, *table);
    t.flags.push_back("--help");
    lines.emplace_back(c.name, t);
  }
  commandNames.insert(commandNames.end(), {"--help", "--version"});
  benchNames.push_back("--help");

  std::string valueCases, flagCases;
  for (const auto& [key, t] : lines) {
    for (const auto& [sw, values] : t.choices)
      valueCases += "    " + shellQuoted(key + " " + sw) + ") COMPREPLY=($(compgen -W " + words(values) +
                    " -- \"$cur\")); return 0 ;;\n";
    if (!t.fileValued.empty()) {
      std::string pattern;
      for (const auto& sw : t.fileValued) pattern += (pattern.empty() ? "" : "|") + shellQuoted(key + " " + sw);
      valueCases += "    " + pattern + ") _dtfabric_files \"$cur\"; return 0 ;;\n";
    }
    if (!t.numeric.empty()) {
      std::string pattern;
      for (const auto& sw : t.numeric) pattern += (pattern.empty() ? "" : "|") + shellQuoted(key + " " + sw);
      valueCases += "    " + pattern + ") return 0 ;;\n";
    }
    flagCases += "    " + shellQuoted(key) + ") flags=" + words(t.flags) + " ;;\n";
  }

  return "# bash completion for dtfabric " DTF_VERSION ", generated from its option tables by\n"
         "# `dtfabric help --bash-completion`. Do not edit.\n"
         "\n"
         "_dtfabric_files() {\n"
         "  compopt -o filenames 2>/dev/null\n"
         "  local IFS=$'\\n'\n"
         "  COMPREPLY=($(compgen -f -- \"$1\"))\n"
         "}\n"
         "\n"
         "_dtfabric() {\n"
         "  local cur=${COMP_WORDS[COMP_CWORD]} prev=\"\" cmd flags=\"\"\n"
         "  (( COMP_CWORD > 0 )) && prev=${COMP_WORDS[COMP_CWORD-1]}\n"
         "  COMPREPLY=()\n"
         "  if (( COMP_CWORD == 1 )); then\n"
         "    COMPREPLY=($(compgen -W " + words(commandNames) + " -- \"$cur\"))\n"
         "    return 0\n"
         "  fi\n"
         "  cmd=${COMP_WORDS[1]}\n"
         "  if [[ $cmd == bench ]]; then\n"
         "    if (( COMP_CWORD == 2 )); then\n"
         "      COMPREPLY=($(compgen -W " + words(benchNames) + " -- \"$cur\"))\n"
         "      return 0\n"
         "    fi\n"
         "    cmd=\"bench ${COMP_WORDS[2]}\"\n"
         "  fi\n"
         "  # The value of the option before the cursor: its choices, a file name, or nothing for a number.\n"
         "  case \"$cmd $prev\" in\n" + valueCases +
         "  esac\n"
         "  case \"$cmd\" in\n" + flagCases +
         "    *) return 0 ;;\n"
         "  esac\n"
         "  if [[ $cur == -* ]]; then\n"
         "    COMPREPLY=($(compgen -W \"$flags\" -- \"$cur\"))\n"
         "  else\n"
         "    _dtfabric_files \"$cur\"\n"
         "  fi\n"
         "  return 0\n"
         "}\n"
         "complete -F _dtfabric dtfabric\n";
}

} // namespace dtf::app
