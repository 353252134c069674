// The strict option parser behind every subcommand.
#include "slicecap/cli/args.hpp"

#include <charconv>
#include <cmath>
#include <sstream>

namespace slicecap::cli {

std::optional<std::string> ParsedArgs::value(const std::string& name) const {
  auto it = values_.find(name);
  if (it == values_.end()) return std::nullopt;
  return it->second;
}

std::string ParsedArgs::required(const std::string& name) const {
  auto v = value(name);
  if (!v) throw UsageError("missing required option --" + name);
  return *v;
}

namespace {

// The whole of `text` as a double (none if anything is left over or it is not one at all).
std::optional<double> wholeNumber(const std::string& text) {
  double number = 0.0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), number);
  if (ec != std::errc() || end != text.data() + text.size()) return std::nullopt;
  return number;
}

}  // namespace

std::optional<double> ParsedArgs::optionalNumber(const std::string& name) const {
  auto v = value(name);
  if (!v) return std::nullopt;
  const std::optional<double> number = wholeNumber(*v);
  if (!number || !std::isfinite(*number))
    throw UsageError("--" + name + ": '" + *v + "' is not a number");
  return number;
}

std::optional<double> ParsedArgs::numberIn(const std::string& name, double lowest,
                                           double highest, const std::string& what) const {
  auto v = value(name);
  if (!v) return std::nullopt;
  const std::optional<double> number = wholeNumber(*v);
  // The range's own words for every refusal: a person reads what the option takes, not why.
  if (!number || !(*number >= lowest && *number <= highest))
    throw UsageError("--" + name + ": '" + *v + "' is not " + what);
  return number;
}

double ParsedArgs::number(const std::string& name, double fallback) const {
  return optionalNumber(name).value_or(fallback);
}

ParsedArgs parseArgs(const CommandSpec& spec, std::span<const std::string> args) {
  ParsedArgs parsed;
  auto find = [&](const std::string& arg) -> const OptionSpec* {
    for (const OptionSpec& o : spec.options) {
      if (arg == "--" + o.name || (o.shortName && arg == std::string("-") + o.shortName)) return &o;
    }
    return nullptr;
  };
  bool onlyPositional = false;
  for (std::size_t i = 0; i < args.size(); ++i) {
    std::string arg = args[i];
    if (onlyPositional || arg.empty() || arg[0] != '-' || arg == "-") {
      parsed.positional.push_back(arg);
      continue;
    }
    if (arg == "--") {
      onlyPositional = true;
      continue;
    }
    if (arg == "--help" || arg == "-h") {
      parsed.helpRequested = true;
      continue;
    }
    std::optional<std::string> inlineValue;
    if (const auto eq = arg.find('='); arg.rfind("--", 0) == 0 && eq != std::string::npos) {
      inlineValue = arg.substr(eq + 1);
      arg = arg.substr(0, eq);
    }
    const OptionSpec* option = find(arg);
    if (!option)
      throw UsageError(spec.name + ": unknown option " + arg + " (see slicecap " + spec.name +
                       " --help)");
    if (option->valueName.empty()) {
      if (inlineValue)
        throw UsageError(spec.name + ": option --" + option->name + " takes no value");
      parsed.setFlag(option->name);
      continue;
    }
    if (!inlineValue) {
      if (i + 1 >= args.size())
        throw UsageError(spec.name + ": option --" + option->name + " needs " + option->valueName);
      inlineValue = args[++i];
    }
    // Given twice, one of the two would be dropped without a word (a second -o, a second
    // --gltf never written): the user meant something the command would not do.
    if (parsed.value(option->name))
      throw UsageError(spec.name + ": option --" + option->name + " given twice");
    parsed.setValue(option->name, *inlineValue);
  }
  if (!parsed.helpRequested) {
    const int count = static_cast<int>(parsed.positional.size());
    if (count < spec.minPositional || count > spec.maxPositional) {
      throw UsageError(
          spec.name + ": expected " +
          (spec.minPositional == spec.maxPositional
               ? std::to_string(spec.minPositional)
               : std::to_string(spec.minPositional) + " to " + std::to_string(spec.maxPositional)) +
          " argument(s), got " + std::to_string(count) + "; usage: slicecap " + spec.name + " " +
          spec.synopsis);
    }
  }
  return parsed;
}

std::string usageText(const CommandSpec& spec) {
  std::ostringstream out;
  out << "usage: slicecap " << spec.name << " " << spec.synopsis << "\n\n"
      << spec.description << "\n";
  if (!spec.options.empty()) out << "\noptions:\n";
  for (const OptionSpec& o : spec.options) {
    std::string left = "  ";
    left += o.shortName ? std::string("-") + o.shortName + ", " : "    ";
    left += "--" + o.name + (o.valueName.empty() ? "" : " " + o.valueName);
    out << left;
    out << std::string(left.size() < 30 ? 30 - left.size() : 1, ' ') << o.help << "\n";
  }
  out << "  -h, --help                  this text\n";
  return out.str();
}

}  // namespace slicecap::cli
