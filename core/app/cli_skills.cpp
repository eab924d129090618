// `marvin run --sim` (the host with simulated devices and a console) and `marvin skills
// list` (what the registry loaded, and what it refused).
#include <unistd.h>

#include <cstdio>
#include <iostream>
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
  bool verbose = false;
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

void run_sim(const RunOptions& o) {
  if (!o.sim) {
    throw CliError("only the simulated robot is available in this build: use `marvin run --sim`",
                   2);
  }
  set_log_level(o.verbose ? LogLevel::kInfo : LogLevel::kWarning);
  Host host(host_options(o), write_line);
  host.load();
  const bool interactive = isatty(STDIN_FILENO) != 0;
  if (interactive) {
    write_line("Marvin (simulated robot). Type a request; Ctrl-D quits.");
  } else {
    host.loop().on_heard([](std::string_view line) { write_line("You: " + std::string(line)); });
  }
  // The console reader feeds the host loop; the loop runs here until end of input.
  std::thread reader([&host] {
    std::string line;
    while (std::getline(std::cin, line)) {
      while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
      if (!line.empty()) host.loop().post(line);
    }
    host.loop().close();
  });
  host.body().set_light(devices::Light::kAwaiting);
  host.manager().say("Hello, I'm Marvin.");
  host.loop().run();
  reader.join();
}

void list_skills(const RunOptions& o) {
  set_log_level(LogLevel::kError);
  Host host(host_options(o), [](std::string_view) {});
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
}

void install_skill_platform_commands(CLI::App& root) {
  auto options = std::make_shared<RunOptions>();
  CLI::App* run = root.add_subcommand("run", "Run the robot's host");
  run->add_flag("--sim", options->sim, "Simulated devices and a text console (stdin/stdout)");
  run->add_flag("-v,--verbose", options->verbose, "Show the host's informational log on stderr");
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
