// How an area of the host adds its subcommands to the `marvin` executable.
//
// Each area writes one file core/app/cli_<area>.cpp that defines an installer and
// registers it with MARVIN_CLI_COMMANDS. main() calls every installer on the root CLI11
// app before parsing. A subcommand reports failure by throwing marvin::app::CliError
// (printed as "marvin: <message>", exit code as given); any other std::exception is
// printed the same way with exit code 1.
#pragma once

#include <CLI/CLI.hpp>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <string_view>

namespace marvin::app {

class CliError : public std::runtime_error {
 public:
  explicit CliError(const std::string& message, int exit_code = 1)
      : std::runtime_error(message), exit_code_(exit_code) {}
  int exit_code() const { return exit_code_; }

 private:
  int exit_code_;
};

using CommandInstaller = void (*)(CLI::App& root);

// Writes one line of a subcommand's output and flushes it, so a pipe or a test reading the
// output sees each line as soon as it is written.
inline void write_line(std::string_view text) {
  std::fwrite(text.data(), 1, text.size(), stdout);
  std::fputc('\n', stdout);
  std::fflush(stdout);
}

// The subcommand `name` of `parent`, created (requiring a subcommand of its own) if no
// installer made it yet. Several areas add to one group: `marvin skill new` (Lua) and
// `marvin skill install` (store) both live under `skill`.
inline CLI::App& command_group(CLI::App& parent, const std::string& name,
                               const std::string& description) {
  for (CLI::App* existing : parent.get_subcommands([](CLI::App*) { return true; })) {
    if (existing->get_name() == name) return *existing;
  }
  CLI::App* group = parent.add_subcommand(name, description);
  group->require_subcommand(1);
  return *group;
}

// Registers `installer` to run at start-up; `name` orders the installers (alphabetically)
// so `marvin --help` is stable.
struct CommandRegistration {
  CommandRegistration(const char* name, CommandInstaller installer);
};

#define MARVIN_CLI_COMMANDS(installer) \
  static const ::marvin::app::CommandRegistration marvin_cli_registration_##installer(#installer, installer)

}  // namespace marvin::app
