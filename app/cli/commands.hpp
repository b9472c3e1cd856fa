// SPDX-License-Identifier: MIT
// The verbs of palletballet-cli. Each prints JSON on stdout and errors on stderr, and returns the
// exit code: 0 done, 2 bad input (usage or validation), 1 a failure of the run itself.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "app/cli/args.hpp"
#include "core/json_io.hpp"

namespace pb::cli {

inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;
inline constexpr int kExitBadInput = 2;

struct Command {
  VerbSpec spec;
  std::function<int(const Args&)> run;
};

/// scenarios, catalog, validate, random, friction.
std::vector<Command> data_commands();

/// Reads a file's text, or stdin for "-"; nullopt (with a message on stderr) if it can't.
std::optional<std::string> read_input(const std::string& path);

/// Prints JSON on stdout, indented by two spaces.
void print_json(const Json& json);

/// Prints each diagnostic as "pointer: message" on stderr.
void print_diagnostics(const Diagnostics& diagnostics);

}  // namespace pb::cli
