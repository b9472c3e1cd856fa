// SPDX-License-Identifier: MIT
// palletballet-lab: the numerical studies (speed-accuracy, stability, convergence, standing) and
// the batch study, which measure configurations against the reference configuration. Not part of
// what the product answers: palletballet-cli links the core only.
#include <vector>

#include "app/lab/lab_commands.hpp"

int main(int argc, char** argv) {
  std::vector<pb::cli::Command> commands = pb::cli::study_commands();
  commands.push_back(pb::cli::batch_command());
  return pb::cli::run_verbs(pb::cli::kLabProgram, commands, argc, argv);
}
