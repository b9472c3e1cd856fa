// SPDX-License-Identifier: MIT
// palletballet-cli: the core from the command line. JSON on stdout, errors on stderr. It links the
// core only; the studies that judge configurations are palletballet-lab's (app/lab).
#include <vector>

#include "app/cli/commands.hpp"

int main(int argc, char** argv) {
  std::vector<pb::cli::Command> commands = pb::cli::data_commands();
  for (auto& command : pb::cli::physics_commands()) commands.push_back(std::move(command));
  commands.push_back(pb::cli::map_command());
  return pb::cli::run_verbs("palletballet-cli", commands, argc, argv);
}
