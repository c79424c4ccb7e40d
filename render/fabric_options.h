// SPDX-License-Identifier: GPL-3.0-or-later
// The fabric's parameters, each declared once: its name (the CLI flag `--NAME` of `dtfabric render`, the
// script's `set NAME VALUE`), older script names, help, value kind, the range the CLI and scripts accept,
// the panel slider's narrower range, its default and the FabricParams field it sets. The CLI's flags, their
// validation and help, the script's `set` keys and the Fabric panel's sliders all read this table.
#pragma once

#include "io/model/range.h"
#include "render/fabric_params.h"

#include <string>
#include <vector>

namespace dtf::render {

struct FabricOption {
  enum class Kind {
    Number,  // a real number in `range`
    Integer, // an integer in `range`
    OnOff,   // on|off in scripts, a checkbox; on by default, the CLI has --no-NAME
    Choice,  // one of `choices` (its index); the CLI and scripts take the name
  };
  const char* name;    // CLI flag without dashes and script key, e.g. "blend-k"
  const char* aliases; // other script keys, space-separated ("" none), e.g. "k"
  const char* metavar; // the value in help, e.g. "K"
  const char* help;    // one line, no default (it is printed from `get` of a default FabricParams)
  Kind kind;
  Range range;              // accepted by the CLI and scripts
  Range slider;             // the panel's slider (lo == hi: none)
  const char* sliderLabel;  // nullptr: not on the panel
  const char* sliderFormat; // printf format of the slider's value
  bool sliderLogarithmic;
  double (*get)(const FabricParams&);
  void (*set)(FabricParams&, double);
  const char* choices = nullptr; // Kind::Choice: the names, space-separated, in index order

  // Kind::Choice: the names in index order.
  std::vector<std::string> choiceNames() const;

  bool matches(const std::string& key) const; // the name or an alias
  // Parses and validates `text`; throws UsageError "NAME must lie in RANGE, got TEXT" and the like.
  double parse(const std::string& text) const;
  // "--blend-k K", "--no-lighting"
  std::string cliSynopsis() const;
};

// Every option, in the order help lists them.
const std::vector<FabricOption>& fabricOptions();
// The option named `key` (name or alias), nullptr when none.
const FabricOption* findFabricOption(const std::string& key);
// The value's text as the CLI and scripts write it: "0.1", "on", "medical".
std::string formatFabricValue(const FabricOption& o, double v);

} // namespace dtf::render
