// SPDX-License-Identifier: MIT
// The verbs of palletballet-cli (and the shared parts palletballet-lab's build on). Each prints
// JSON on stdout and errors on stderr, and returns the exit code: 0 done, 2 bad input (usage or
// validation), 1 a failure of the run itself.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "app/cli/args.hpp"
#include "core/analysis/failure_map.hpp"
#include "core/base/diagnostic.hpp"
#include "core/contract/conveyor_profile.hpp"
#include "core/contract/json_io.hpp"
#include "core/contract/pallet_config.hpp"
#include "core/inputs/pallet_source.hpp"

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

/// mjcf, solve, analyze, bench.
std::vector<Command> physics_commands();

/// map FILE: the failure map (app/cli/map_command.cpp).
Command map_command();

/// `bench batch`: the batch engine's scaling table (app/cli/bench_command.cpp).
int run_bench_batch(const Args& args);
/// `bench scale`: unwrapped pallets of growing size, each analysed in a child process.
int run_bench_scale(const Args& args);
/// Whole numbers from a list option, each in [lo, hi] (a UsageError otherwise), or `fallback`.
std::vector<int> int_list(const Args& args, const std::string& name, std::vector<int> fallback,
                          int lo, int hi);

/// The random pallets' wrap from `--wrap none|shrink|stretch|banded|mixed` (mixed: nullopt, drawn
/// per pallet), or `fallback` when the option is absent; a UsageError naming `command` otherwise.
std::optional<WrapType> random_wrap_option(const Args& args, const std::string& command,
                                           std::optional<WrapType> fallback);

/// Reads a file's text, or stdin for "-"; nullopt (with a message on stderr) if it can't.
std::optional<std::string> read_input(const std::string& path);

/// Prints JSON on stdout, indented by two spaces.
void print_json(const Json& json);

/// Prints each diagnostic as "pointer: message" on stderr.
void print_diagnostics(const Diagnostics& diagnostics);

/// A tool's main: runs the verb argv[1] names among `commands` with the rest of argv ("--help",
/// "help" or nothing: the verbs' list, under `program`'s name). Returns the exit code.
int run_verbs(const std::string& program, const std::vector<Command>& commands, int argc,
              char** argv);

}  // namespace pb::cli
