// SPDX-License-Identifier: MIT
// palletballet-cli: the core from the command line. JSON on stdout, errors on stderr.
#include <exception>
#include <iostream>
#include <string>
#include <vector>

#include "app/cli/commands.hpp"

namespace {

void print_usage(const std::vector<pb::cli::Command>& commands) {
  std::cout << "usage: palletballet-cli <verb> [options]\n\nverbs:\n";
  for (const auto& c : commands) {
    std::string name = "  " + c.spec.name;
    name.resize(14, ' ');
    std::cout << name << c.spec.summary << "\n";
  }
  std::cout << "\n'palletballet-cli <verb> --help' describes a verb.\n";
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<pb::cli::Command> commands = pb::cli::data_commands();
  for (auto& command : pb::cli::physics_commands()) commands.push_back(std::move(command));
  for (auto& command : pb::cli::study_commands()) commands.push_back(std::move(command));
  commands.push_back(pb::cli::map_command());
  commands.push_back(pb::cli::batch_command());
  if (argc < 2 || std::string(argv[1]) == "--help" || std::string(argv[1]) == "-h" ||
      std::string(argv[1]) == "help") {
    print_usage(commands);
    return argc < 2 ? pb::cli::kExitBadInput : pb::cli::kExitOk;
  }
  const std::string verb = argv[1];
  for (const auto& command : commands) {
    if (command.spec.name != verb) continue;
    try {
      pb::cli::Args args(command.spec, std::vector<std::string>(argv + 2, argv + argc));
      if (args.help()) {
        std::cout << pb::cli::help_text(command.spec);
        return pb::cli::kExitOk;
      }
      return command.run(args);
    } catch (const pb::cli::UsageError& e) {
      std::cerr << "palletballet-cli " << e.message << "\n";
      return pb::cli::kExitBadInput;
    } catch (const std::exception& e) {
      std::cerr << "palletballet-cli " << verb << ": internal error: " << e.what() << "\n";
      return pb::cli::kExitFailure;
    }
  }
  std::cerr << "palletballet-cli: unknown verb '" << verb << "'; run 'palletballet-cli --help'\n";
  return pb::cli::kExitBadInput;
}
