// `marvin run --sim` (the host with simulated devices and a console) and `marvin skills
// list` (what the registry loaded, and what it refused).
#include <unistd.h>

#include <cstdio>
#include <functional>
#include <iostream>
#include <memory>
#include <string>
#include <thread>

#include "app/cli.h"
#include "app/host.h"
#include "common/log.h"
#include "skills/api_json.h"

namespace marvin::app {
namespace {

struct RunOptions {
  bool sim = false;
  std::vector<std::string> skills_dirs;
  bool no_builtin = false;
  std::string time_zone;
  std::string clock;
  std::string data_dir;
  bool in_memory = false;
  bool verbose = false;
  std::string mcu_tty;
};

void write_line(std::string_view text) {
  std::fwrite(text.data(), 1, text.size(), stdout);
  std::fputc('\n', stdout);
  std::fflush(stdout);
}

HostOptions host_options(const RunOptions& o) {
  HostOptions h;
  for (const auto& dir : o.skills_dirs) h.skills_dirs.emplace_back(dir);
  h.builtin_skills = !o.no_builtin;
  h.in_memory_data = o.in_memory;
  h.data_dir = o.data_dir;
  h.mcu_tty = o.mcu_tty;
  h.time_zone = o.time_zone.empty() ? system_time_zone() : o.time_zone;
  if (!o.clock.empty()) {
    try {
      h.fixed_now_ms = skills::local_to_utc_ms(o.clock, h.time_zone);
    } catch (const std::exception& e) {
      throw CliError(std::string("--clock: ") + e.what(), 2);
    }
  }
  return h;
}

// The host, or a CliError (exit 1) when the personal data cannot be opened.
std::unique_ptr<Host> open_host(const RunOptions& o,
                                std::function<void(std::string_view)> write) {
  HostOptions h = host_options(o);
  try {
    return std::make_unique<Host>(std::move(h), std::move(write));
  } catch (const std::exception& e) {
    throw CliError(std::string("cannot open the personal data: ") + e.what() +
                       " (use --data-dir DIR, or --in-memory)",
                   1);
  }
}

void run_sim(const RunOptions& o) {
  if (!o.sim) {
    throw CliError("only the simulated robot is available in this build: use `marvin run --sim`",
                   2);
  }
  set_log_level(o.verbose ? LogLevel::kInfo : LogLevel::kWarning);
  std::unique_ptr<Host> host_ptr = open_host(o, write_line);
  Host& host = *host_ptr;
  host.load();
  const bool interactive = isatty(STDIN_FILENO) != 0;
  if (interactive) {
    write_line("Marvin (simulated robot). Type a request; Ctrl-D quits.");
  } else {
    host.loop().on_heard([](std::string_view line) { write_line("You: " + std::string(line)); });
  }
  // The console reader feeds the host loop; the loop runs here until end of input.
  std::thread reader = start_console_reader(host);
  host.body().set_light(devices::Light::kAwaiting);
  host.manager().say("Hello, I'm Marvin.");
  host.start_scheduler();
  host.loop().run();
  reader.join();
}

void list_skills(const RunOptions& o) {
  set_log_level(LogLevel::kError);
  std::unique_ptr<Host> host_ptr = open_host(o, [](std::string_view) {});
  Host& host = *host_ptr;
  host.load();
  const auto& skills = host.registry().skills();
  if (skills.empty()) write_line("no skills loaded");
  for (const auto& skill : skills) {
    const skills::Manifest& m = skill->manifest;
    std::string intents;
    for (const auto& intent : m.intents) intents += (intents.empty() ? "" : ", ") + intent.name;
    std::string permissions;
    for (const auto& p : m.permissions) permissions += (permissions.empty() ? "" : ", ") + p;
    write_line(m.id + " " + m.version.text + " (" + m.kind + ") \"" + m.name + "\" in " +
               skill->dir.string());
    write_line("    intents: " + intents);
    write_line("    permissions: " +
               (permissions.empty() ? std::string("speech only") : permissions));
  }
  const auto& errors = host.registry().errors();
  if (!errors.empty()) {
    write_line("load errors:");
    for (const auto& e : errors) write_line("  " + e.message);
  }
  std::vector<std::string> conflicts = host.registry().conflicts();
  if (!conflicts.empty()) {
    write_line("template conflicts:");
    for (const auto& c : conflicts) write_line("  " + c);
  }
}

void add_skill_options(CLI::App& app, RunOptions& o) {
  app.add_option("--skills-dir", o.skills_dirs,
                 "Also load the skills in this directory (repeatable)");
  app.add_flag("--no-builtin-skills", o.no_builtin, "Do not load the build's built-in skills");
  app.add_option("--time-zone", o.time_zone, "The owner's IANA time zone (default: the system's)");
  app.add_option("--clock", o.clock,
                 "Stop the clock at this local time, YYYY-MM-DDTHH:MM (demos, tests)");
  CLI::Option* data_dir = app.add_option("--data-dir", o.data_dir,
                 "Personal data directory (default: $MARVIN_DATA_DIR, else "
                 "$XDG_DATA_HOME/marvin, else ~/.local/share/marvin)");
  app.add_flag("--in-memory", o.in_memory,
               "Keep personal data in memory only (nothing is stored)")
      ->excludes(data_dir);
}

void install_skill_platform_commands(CLI::App& root) {
  auto options = std::make_shared<RunOptions>();
  CLI::App* run = root.add_subcommand("run", "Run the robot's host");
  run->add_flag("--sim", options->sim, "Simulated devices and a text console (stdin/stdout)");
  run->add_flag("-v,--verbose", options->verbose, "Show the host's informational log on stderr");
  run->add_option("--mcu-tty", options->mcu_tty,
                  "Also drive the base through this serial tty: the MCU, or the --link path "
                  "of a running marvin-mcu-sim");
  add_skill_options(*run, *options);
  run->callback([options] { run_sim(*options); });

  CLI::App& skills = command_group(root, "skills", "Installed skills");
  CLI::App* list = skills.add_subcommand("list", "Skills, versions, kinds, intents, load errors");
  add_skill_options(*list, *options);
  list->callback([options] { list_skills(*options); });
}

}  // namespace

MARVIN_CLI_COMMANDS(install_skill_platform_commands);

}  // namespace marvin::app
