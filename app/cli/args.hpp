// SPDX-License-Identifier: MIT
// A small, strict command-line parser over CLI11: each verb declares its options; anything else is
// an error that names the verb and the option and points at --help.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace pb::cli {

struct OptionSpec {
  std::string name;        ///< without dashes: "seed"
  std::string value_name;  ///< empty for a flag; "N" for "--seed N"
  std::string help;
};

struct VerbSpec {
  std::string name;
  std::string usage;  ///< "random --seed N [--anomaly-rate R] ..."
  std::string summary;
  std::vector<OptionSpec> options;
  int min_positionals = 0;
  int max_positionals = 0;
  std::string program = "palletballet-cli";  ///< the tool the verb belongs to (usage, errors)
};

/// Thrown by the accessors below for a bad value; main() turns it into a message and exit 2.
struct UsageError {
  std::string message;
};

class Args {
 public:
  /// Parses argv after the verb. "--name value" and "--name=value" both work (the word after an
  /// option is its value, "--offset -0.5"); the last of a repeated option counts; "-" (stdin) and
  /// negative numbers are positionals, and so is everything after "--"; --help or -h anywhere asks
  /// for help. Unknown options, missing values, a value given to a flag and a wrong positional
  /// count throw UsageError (CLI11's own errors included: nothing else is thrown).
  Args(const VerbSpec& spec, const std::vector<std::string>& argv);

  bool help() const { return help_; }
  bool flag(const std::string& name) const { return values_.count(name) > 0; }
  std::optional<std::string> text(const std::string& name) const;
  std::optional<double> number(const std::string& name) const;
  std::optional<std::int64_t> integer(const std::string& name) const;
  /// Comma-separated numbers: "--threads 1,2,4".
  std::optional<std::vector<double>> numbers(const std::string& name) const;
  const std::vector<std::string>& positionals() const { return positionals_; }

 private:
  const VerbSpec& spec_;
  bool help_ = false;
  std::map<std::string, std::string> values_;
  std::vector<std::string> positionals_;
};

/// The value of --name, which must lie in (lo, hi] (`unit` names it in the error); `fallback` when
/// absent. Throws UsageError naming the verb, the option, its range and the value given.
double option_in_range(const Args& args, const std::string& verb, const std::string& name,
                       double fallback, double lo, double hi, const std::string& unit);

/// The --help text of a verb.
std::string help_text(const VerbSpec& spec);

}  // namespace pb::cli
