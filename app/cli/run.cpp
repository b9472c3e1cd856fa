// SPDX-License-Identifier: MIT
#include <exception>
#include <iostream>
#include <string>
#include <vector>

#include "app/cli/commands.hpp"

namespace pb::cli {

namespace {

void print_usage(const std::string& program, const std::vector<Command>& commands) {
  std::cout << "usage: " << program << " <verb> [options]\n\nverbs:\n";
  for (const auto& c : commands) {
    std::string name = "  " + c.spec.name;
    name.resize(14, ' ');
    std::cout << name << c.spec.summary << "\n";
  }
  std::cout << "\n'" << program << " <verb> --help' describes a verb.\n";
}

}  // namespace

int run_verbs(const std::string& program, const std::vector<Command>& commands, int argc,
              char** argv) {
  if (argc < 2 || std::string(argv[1]) == "--help" || std::string(argv[1]) == "-h" ||
      std::string(argv[1]) == "help") {
    print_usage(program, commands);
    return argc < 2 ? kExitBadInput : kExitOk;
  }
  const std::string verb = argv[1];
  for (const auto& command : commands) {
    if (command.spec.name != verb) continue;
    try {
      Args args(command.spec, std::vector<std::string>(argv + 2, argv + argc));
      if (args.help()) {
        std::cout << help_text(command.spec);
        return kExitOk;
      }
      return command.run(args);
    } catch (const UsageError& e) {
      std::cerr << program << " " << e.message << "\n";
      return kExitBadInput;
    } catch (const std::exception& e) {
      std::cerr << program << " " << verb << ": internal error: " << e.what() << "\n";
      return kExitFailure;
    }
  }
  std::cerr << program << ": unknown verb '" << verb << "'; run '" << program << " --help'\n";
  return kExitBadInput;
}

}  // namespace pb::cli
