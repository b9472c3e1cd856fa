// SPDX-License-Identifier: MIT
#include "app/cli/args.hpp"

#include <charconv>
#include <cmath>

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

}  // namespace

Args::Args(const VerbSpec& spec, const std::vector<std::string>& argv) : spec_(spec) {
  for (std::size_t i = 0; i < argv.size(); ++i) {
    const std::string& a = argv[i];
    if (a == "--help" || a == "-h") {
      help_ = true;
      return;
    }
    if (a.size() > 2 && a.starts_with("--")) {
      std::string name = a.substr(2);
      std::optional<std::string> value;
      if (auto eq = name.find('='); eq != std::string::npos) {
        value = name.substr(eq + 1);
        name = name.substr(0, eq);
      }
      const OptionSpec* option = find_option(spec, name);
      if (option == nullptr) fail(spec, "unknown option --" + name);
      if (option->value_name.empty()) {
        if (value) fail(spec, "--" + name + " takes no value");
        values_[name] = "";
      } else {
        if (!value) {
          if (i + 1 >= argv.size())
            fail(spec, "--" + name + " needs a value " + option->value_name);
          value = argv[++i];
        }
        values_[name] = *value;
      }
    } else if (a.size() > 1 && a[0] == '-' && !(a[1] >= '0' && a[1] <= '9') && a[1] != '.') {
      fail(spec, "unknown option " + a);
    } else {
      positionals_.push_back(a);
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

}  // namespace pb::cli
