// The `marvin` executable: collects the subcommands of every area and runs one.
#include <cstdio>
#include <map>
#include <string>

#include "app/cli.h"

namespace marvin::app {
namespace {

std::multimap<std::string, CommandInstaller>& installers() {
  static std::multimap<std::string, CommandInstaller> all;  // a repeated name must not drop a group
  return all;
}

}  // namespace

CommandRegistration::CommandRegistration(const char* name, CommandInstaller installer) {
  installers().emplace(name, installer);
}

}  // namespace marvin::app

int main(int argc, char** argv) {
  CLI::App app{"Marvin: an offline assistant for a home robot", "marvin"};
  app.set_version_flag("--version", std::string("marvin ") + MARVIN_VERSION);
  app.require_subcommand(1);
  for (auto& [name, install] : marvin::app::installers()) install(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const marvin::app::CliError& e) {
    std::fprintf(stderr, "marvin: %s\n", e.what());
    return e.exit_code();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "marvin: %s\n", e.what());
    return 1;
  }
  return 0;
}
