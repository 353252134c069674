// A small, strict command-line parser: declared options only, errors as UsageError (exit code 2).
#pragma once

#include <map>
#include <optional>
#include <set>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "slicecap/core/error.hpp"

namespace slicecap::cli {

/// \brief Bad usage (slicecap::UsageError, lib/core): exit code 2.
using slicecap::UsageError;

/// \brief One option: `--name VALUE` (valueName set) or a flag `--name`; `shortName` e.g. 'o'.
struct OptionSpec {
  std::string name;
  char shortName = 0;
  std::string valueName;  ///< empty for a flag
  std::string help;
};

/// \brief A subcommand's interface: what `--help` prints and what the parser accepts.
struct CommandSpec {
  std::string name;
  std::string synopsis;     ///< e.g. "SLICES.csv -o OUT.exr [--method b]"
  std::string description;  ///< a paragraph for --help
  std::vector<OptionSpec> options;
  int minPositional = 0;
  int maxPositional = 0;
};

/// \brief The parsed arguments of one command.
class ParsedArgs {
 public:
  std::vector<std::string> positional;
  bool helpRequested = false;

  bool flag(const std::string& name) const { return flags_.count(name) > 0; }
  std::optional<std::string> value(const std::string& name) const;
  /// \brief The value of a required option; UsageError if absent.
  std::string required(const std::string& name) const;
  /// \brief A numeric option, or `fallback` if absent; UsageError if not a finite number.
  double number(const std::string& name, double fallback) const;
  std::optional<double> optionalNumber(const std::string& name) const;
  /// \brief A numeric option within [lowest, highest], or none if absent; UsageError
  /// "--NAME: 'VALUE' is not <what>" for anything else (text, NaN, out of range).
  std::optional<double> numberIn(const std::string& name, double lowest, double highest,
                                 const std::string& what) const;

  void setValue(const std::string& name, std::string v) { values_[name] = std::move(v); }
  void setFlag(const std::string& name) { flags_.insert(name); }

 private:
  std::map<std::string, std::string> values_;
  std::set<std::string> flags_;
};

/// \brief Parses `args` (without the command name). `--help`/`-h` sets helpRequested and skips the
/// positional count check. Throws UsageError naming the offending argument.
ParsedArgs parseArgs(const CommandSpec& spec, std::span<const std::string> args);

/// \brief The --help text of a command.
std::string usageText(const CommandSpec& spec);

}  // namespace slicecap::cli
