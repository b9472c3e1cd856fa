// SPDX-License-Identifier: MIT
// The verbs of palletballet-lab: the studies that judge configurations against the reference
// configuration (core/lab), apart from the product's CLI, which links the core only. They share
// palletballet-cli's argument parsing and readers (app/cli/commands.hpp).
#pragma once

#include <vector>

#include "app/cli/commands.hpp"

namespace pb::cli {

/// The lab's tool, as its verbs' usage and errors name it.
inline constexpr const char* kLabProgram = "palletballet-lab";

/// study speed-accuracy | stability | convergence | standing (app/lab/study_command.cpp).
std::vector<Command> study_commands();

/// batch: the batch study of random pallets (app/lab/batch_command.cpp).
Command batch_command();

/// `study standing`: validation's standing rule against the simulation
/// (app/lab/study_standing.cpp).
int run_study_standing(const Args& args);

}  // namespace pb::cli
