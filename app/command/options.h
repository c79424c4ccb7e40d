// SPDX-License-Identifier: GPL-3.0-or-later
// Each command's options declared once: name, value kind, default, range or choices, help. One table per
// command (and per benchmark) drives the parser (unknown options, missing values, kinds, ranges and choices
// are usage errors, exit code 1), `dtfabric CMD --help`, the synopsis of `dtfabric help --markdown` (the
// command tables of README.md and sample_data/guide/reference.md) and the help test.
//
// A command reads its options through ParsedOptions: reading a name its table lacks is a programming error
// (std::logic_error), and so is a table row the command never reads (finish()), so the code, the help and
// the parser cannot disagree.
#pragma once

#include "app/command/command.h"
#include "io/model/range.h"
#include "render/figure_furniture.h"

#include <limits>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace dtf::app {

struct CliOption {
  enum class Kind {
    Flag,    // --NAME, no value
    Text,    // --NAME VALUE, any text (a `check` may validate it)
    Choice,  // one of `choices`
    Number,  // a real number in `range`
    Integer, // an integer in `range`
    List,    // --NAME V1 V2 ... (the values up to the next option; --NAME=V gives one)
  };
  enum class Synopsis { Optional, Required, Hidden }; // how the usage line shows it

  std::string name;    // without dashes; "output" is written -o
  std::string metavar; // "FILE", "N"; empty for flags
  Kind kind = Kind::Text;
  std::string help;                 // without the default and the range (they are appended)
  std::string defaultValue;         // the value when not given, as text ("" none)
  std::string defaultNote;          // said instead of defaultValue when the default is computed ("all cores")
  Range range;                      // Number, Integer
  std::string unit;                 // of the range ("mm", "pixels"), said in --help and range errors
  std::vector<std::string> choices; // Choice
  Synopsis synopsis = Synopsis::Optional;
  std::string group;     // a heading printed before this option in --help (empty: none)
  bool internal = false; // accepted but not listed (a worker process's option)
  bool repeatable = false; // Text: may be given several times, read with ParsedOptions::all
  void (*check)(const std::string& value) = nullptr; // extra validation; throws UsageError

  // Builders for the rows of a table.
  static CliOption flag(std::string name, std::string help);
  static CliOption text(std::string name, std::string metavar, std::string help, std::string def = "");
  static CliOption choice(std::string name, std::string metavar, std::vector<std::string> choices,
                          std::string def, std::string help);
  static CliOption number(std::string name, std::string metavar, double def, Range range, std::string help);
  static CliOption integer(std::string name, std::string metavar, int def, Range range, std::string help);
  static CliOption list(std::string name, std::string metavar, std::string help);
  // Modifiers.
  CliOption required() &&;
  CliOption hidden() &&; // not in the usage line (still in --help's list)
  CliOption under(std::string heading) &&;
  CliOption defaultSays(std::string note) &&;
  CliOption checkedBy(void (*fn)(const std::string&)) &&;
  CliOption internalOnly() &&;
  CliOption noDefault() &&;
  CliOption measuredIn(std::string unit) &&;
  CliOption alsoSays(const std::string& more) &&; // appended to the help: what a command adds to a shared row
  CliOption repeats() &&;                         // a Text row that may be given several times

  std::string written() const;    // "--near MM", "-o FILE", "--json"
  std::string switchName() const; // "--near", "-o"
  // The value checked against kind, range, choices and `check`; throws UsageError.
  void validate(const std::string& value) const;
  // "[0, 1000] mm", "in [0, 1000] mm" (inRange: as the range error says it), ">= 0".
  std::string rangeText(bool inRange = false) const;
  // The help with the default, range and choices appended, as --help and the man pages print it.
  std::string fullHelp() const;
};

// Ranges for the builders.
Range closedRange(double lo, double hi);
Range atLeast(double lo);
Range above(double lo);
Range aboveUpTo(double lo, double hi); // (lo, hi]
Range anyNumber();

struct OptionTable {
  std::string command;            // "compare", "bench view"
  std::string positionals;        // the usage line's positional part, "INPUT", "IN OUT" ("" none)
  std::size_t maxPositionals = 0; // more are an "unexpected argument"
  static constexpr std::size_t kAnyNumber =
      std::numeric_limits<std::size_t>::max(); // maxPositionals: no limit
  std::string intro;                           // prose after the usage line
  std::vector<CliOption> options;
  std::string epilogue;     // prose after the options ("" none)
  std::string synopsisTail; // appended to the synopsis ("[OPTIONS]" is added when options are hidden)

  const CliOption* find(const std::string& name) const;
  // "INPUT --tracts FILE --surface SPEC [--near MM] [--json]" (the reference's command table and the usage
  // line).
  std::string synopsis() const;
  // The text of `dtfabric CMD --help`.
  std::string help() const;
};

// The arguments of one command parsed against its table.
class ParsedOptions {
public:
  // Throws UsageError for an option not in the table, a flag given a value, a missing value, a value of
  // the wrong kind or outside its range, too many positionals.
  ParsedOptions(const OptionTable& table, const CommandArgs& argv);

  bool helpRequested() const { return help_; }
  // With --help: prints the table's help on stdout and returns true.
  bool printHelpIfAsked() const;
  const std::vector<std::string>& positionals() const { return positionals_; }
  const std::string& positional(std::size_t n, const std::string& what) const;

  bool has(const std::string& name) const { return table_->find(name) != nullptr; }
  bool given(const std::string& name);
  bool flag(const std::string& name);
  std::optional<std::string> get(const std::string& name); // as given; nullopt when not given
  std::string text(const std::string& name);               // as given, else the table's default
  std::string required(const std::string& name);           // as given; UsageError "missing --NAME META"
  double number(const std::string& name);
  int integer(const std::string& name);
  std::vector<std::string> list(const std::string& name);
  // Every value of a repeatable Text row, in the order given (empty when not given).
  std::vector<std::string> all(const std::string& name);
  // Throws std::logic_error when a table row was never read: the table would offer an option the
  // command ignores.
  void finish() const;

private:
  const CliOption& row(const std::string& name); // std::logic_error when the table lacks it
  const OptionTable* table_;
  bool help_ = false;
  std::vector<std::string> positionals_;
  std::vector<std::pair<std::string, std::string>> values_; // option name, value (flags: "")
  std::set<std::string> read_;
};

// --surface SPEC or one of its shorthands (--fa T, --slice AXIS[:I], --fibre-surface, --fibre-surface-voxel)
// as a surface spec, for the rows the table has; nullopt when none is given; UsageError for more than one.
std::optional<std::string> surfaceArgument(ParsedOptions& options);

// The fabric options (render/fabric_options.h, one declaration each) as rows of a command's table: --NAME V
// with the fabric table's kind, range and default (colour: text, validated by FabricOption::parse when read),
// and --no-NAME for the on/off ones. For `render` and anything else that takes fabric options.
std::vector<CliOption> fabricCliOptions();

// Validators for `checkedBy`.
void checkTensorLayout(const std::string& value); // io::parseLayout's names
void checkSize(const std::string& value);         // "1024x768"
void checkTriple(const std::string& value);       // "I,J,K"

// The input rows the commands share, each declared once; a command adds what is particular to it with
// `.alsoSays(...)`. The layout names come from io (io::layoutName, io::fibreLayoutName).
enum class LayoutNames { Tensor, TensorOrFibre };
std::string layoutNamesText(LayoutNames which); // "fsl, mrtrix, symmatrix, dtitk" (+ the fibre-set ones)
CliOption layoutOption(LayoutNames which); // --layout L, default auto (Tensor: checked by io::parseLayout)
CliOption bvalOption();                    // --bval F: INPUT is a DWI, its tensors are fitted
CliOption bvecOption();                    // --bvec F
CliOption fitMaskOption();                 // --mask M: where the DWI fit runs
CliOption pairedTensorOption(const std::string& forWhat); // --tensor F beside a fibre set
// --no-letters, --no-legend, --no-scale-bar, --no-colour-bar (hidden): the figure furniture of render and
// movie.
std::vector<CliOption> furnitureOptions();
render::FigureFurniture furnitureFrom(ParsedOptions& args);

} // namespace dtf::app
