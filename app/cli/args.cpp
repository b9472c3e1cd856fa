// SPDX-License-Identifier: MIT
#include "app/cli/args.hpp"

#include <CLI/CLI.hpp>
#include <charconv>
#include <cmath>
#include <exception>

#include "core/base/text.hpp"

namespace pb::cli {

namespace {

const OptionSpec* find_option(const VerbSpec& spec, const std::string& name) {
  for (const auto& o : spec.options) {
    if (o.name == name) return &o;
  }
  return nullptr;
}

[[noreturn]] void fail(const VerbSpec& spec, const std::string& what) {
  throw UsageError{spec.name + ": " + what + " (see '" + spec.program + " " + spec.name +
                   " --help')"};
}

// The name of a long option as typed: "--seed=3" -> "seed".
std::string long_name(const std::string& arg) {
  const auto eq = arg.find('=');
  return arg.substr(2, eq == std::string::npos ? std::string::npos : eq - 2);
}

// What CLI11 leaves over that is still an argument: a plain word, "-" (stdin), or a negative
// number ("-5", "-.5"); anything else that starts with '-' is an option the verb does not have.
bool is_positional(const std::string& arg) {
  return arg.size() < 2 || arg[0] != '-' || (arg[1] >= '0' && arg[1] <= '9') || arg[1] == '.';
}

}  // namespace

Args::Args(const VerbSpec& spec, const std::vector<std::string>& argv) : spec_(spec) {
  // The verb's options as a CLI::App: "--name value" and "--name=value" for an option with a
  // value (the word after it is its value whatever it looks like: "--offset -0.5"), a flag for an
  // option without; the last of a repeated option counts. No positionals are declared: CLI11 leaves
  // them, in order, with whatever it did not recognise (remaining()), and they are sorted below.
  CLI::App app{spec.summary, spec.name};
  app.set_help_flag();
  app.allow_extras();
  CLI::Option* help = nullptr;
  std::vector<std::pair<const OptionSpec*, CLI::Option*>> options;
  try {
    help = app.add_flag("-h,--help");
    for (const auto& o : spec.options) {
      CLI::Option* option = o.value_name.empty() ? app.add_flag("--" + o.name)
                                                 : app.add_option("--" + o.name)->expected(1);
      option->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
      options.emplace_back(&o, option);
    }
  } catch (const CLI::Error& e) {  // a malformed VerbSpec: a name CLI11 refuses or one twice
    fail(spec, std::string("cannot take options: ") + e.what());
  }
  std::vector<std::string> reversed(argv.rbegin(), argv.rend());  // CLI11 parses from the back
  try {
    app.parse(reversed);
  } catch (const CLI::ArgumentMismatch&) {
    if (help->count() > 0) {
      help_ = true;
      return;
    }
    // CLI11 takes the word after an option as its value whatever it is, so a value is missing
    // only when the option is the last word.
    const std::string last = argv.empty() ? std::string() : argv.back();
    const OptionSpec* option =
        last.starts_with("--") ? find_option(spec, long_name(last)) : nullptr;
    if (option == nullptr) fail(spec, "cannot read the arguments");
    fail(spec, "--" + option->name + " needs a value " + option->value_name);
  } catch (const std::exception& e) {  // CLI::Error is one
    fail(spec, std::string("cannot read the arguments: ") + e.what());
  }
  if (help->count() > 0) {
    help_ = true;
    return;
  }
  for (const auto& [o, option] : options) {
    if (option->count() == 0) continue;
    if (o->value_name.empty()) {
      // CLI11 records a flag as "true", and "--flag=value" as the value.
      for (const auto& result : option->results()) {
        if (result != "true") fail(spec, "--" + o->name + " takes no value");
      }
      values_[o->name] = "";
    } else {
      values_[o->name] = option->results().back();
    }
  }
  bool only_positionals = false;  // after "--"
  for (const std::string& a : app.remaining()) {
    if (!only_positionals && a == "--") {
      only_positionals = true;
    } else if (only_positionals || is_positional(a)) {
      positionals_.push_back(a);
    } else {
      fail(spec, "unknown option " + (a.starts_with("--") ? "--" + long_name(a) : a));
    }
  }
  const int n = static_cast<int>(positionals_.size());
  if (n < spec.min_positionals) fail(spec, "missing argument; usage: " + spec.usage);
  if (n > spec.max_positionals) fail(spec, "unexpected argument '" + positionals_.back() + "'");
}

std::optional<std::string> Args::text(const std::string& name) const {
  auto it = values_.find(name);
  if (it == values_.end()) return std::nullopt;
  return it->second;
}

static bool parse_double(const std::string& s, double& out) {
  auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
  return ec == std::errc() && ptr == s.data() + s.size() && std::isfinite(out);
}

std::optional<double> Args::number(const std::string& name) const {
  auto t = text(name);
  if (!t) return std::nullopt;
  double v = 0.0;
  if (!parse_double(*t, v)) fail(spec_, "--" + name + " expects a number, got '" + *t + "'");
  return v;
}

std::optional<std::int64_t> Args::integer(const std::string& name) const {
  auto t = text(name);
  if (!t) return std::nullopt;
  std::int64_t v = 0;
  auto [ptr, ec] = std::from_chars(t->data(), t->data() + t->size(), v);
  if (ec != std::errc() || ptr != t->data() + t->size()) {
    fail(spec_, "--" + name + " expects a whole number, got '" + *t + "'");
  }
  return v;
}

std::optional<std::vector<double>> Args::numbers(const std::string& name) const {
  auto t = text(name);
  if (!t) return std::nullopt;
  std::vector<double> out;
  std::size_t start = 0;
  while (start <= t->size()) {
    std::size_t end = t->find(',', start);
    if (end == std::string::npos) end = t->size();
    double v = 0.0;
    if (!parse_double(t->substr(start, end - start), v)) {
      fail(spec_, "--" + name + " expects comma-separated numbers, got '" + *t + "'");
    }
    out.push_back(v);
    start = end + 1;
  }
  return out;
}

std::string help_text(const VerbSpec& spec) {
  std::string out = "usage: " + spec.program + " " + spec.usage + "\n\n" + spec.summary + "\n";
  if (!spec.options.empty()) out += "\noptions:\n";
  for (const auto& o : spec.options) {
    std::string left = "  --" + o.name + (o.value_name.empty() ? "" : " " + o.value_name);
    if (left.size() < 26) left.resize(26, ' ');
    out += left + " " + o.help + "\n";
  }
  out += "  --help                   this text\n";
  return out;
}

double option_in_range(const Args& args, const std::string& verb, const std::string& name,
                       double fallback, double lo, double hi, const std::string& unit) {
  const double v = args.number(name).value_or(fallback);
  if (!(v > lo && v <= hi)) {
    throw UsageError{verb + ": --" + name + " must be above " + short_number(lo) + " and at most " +
                     short_number(hi) + " " + unit + ", got " + short_number(v)};
  }
  return v;
}

}  // namespace pb::cli
