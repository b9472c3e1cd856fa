// SPDX-License-Identifier: MIT
// Fuzz target: palletballet-cli's and palletballet-lab's command lines. The input is argv after the
// program name, its arguments separated by NUL bytes; the first names the verb (an unknown one is
// matched to a verb by its first byte, so every verb's options are reached). Parses them against
// the verb's real specification and reads every option as each accessor would (text, number,
// integer, list): anything may be a UsageError, nothing may crash or throw anything else. Commands
// are not run.
#include <string>
#include <vector>

#include "app/lab/lab_commands.hpp"
#include "tests/fuzz/fuzz_target.hpp"

namespace {

const std::vector<pb::cli::Command>& commands() {
  static const std::vector<pb::cli::Command> all = [] {
    std::vector<pb::cli::Command> c = pb::cli::data_commands();
    for (auto& command : pb::cli::physics_commands()) c.push_back(std::move(command));
    for (auto& command : pb::cli::study_commands()) c.push_back(std::move(command));
    c.push_back(pb::cli::map_command());
    c.push_back(pb::cli::batch_command());
    return c;
  }();
  return all;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::vector<std::string> argv(1);
  for (char c : pb::fuzz::as_text(data, size)) {
    if (c == '\0')
      argv.emplace_back();
    else
      argv.back() += c;
  }
  const auto& all = commands();
  const pb::cli::Command* command = nullptr;
  for (const auto& c : all)
    if (c.spec.name == argv.front()) command = &c;
  if (command == nullptr)
    command =
        &all[argv.front().empty() ? 0 : static_cast<unsigned char>(argv.front()[0]) % all.size()];
  try {
    const pb::cli::Args args(command->spec, std::vector<std::string>(argv.begin() + 1, argv.end()));
    (void)pb::cli::help_text(command->spec);
    for (const auto& option : command->spec.options) {
      for (int accessor = 0; accessor < 4; ++accessor) {
        try {
          switch (accessor) {
            case 0:
              (void)args.text(option.name);
              break;
            case 1:
              (void)args.number(option.name);
              break;
            case 2:
              (void)args.integer(option.name);
              break;
            default:
              (void)args.numbers(option.name);
              break;
          }
        } catch (const pb::cli::UsageError&) {
        }
      }
    }
  } catch (const pb::cli::UsageError&) {
  }
  return 0;
}
