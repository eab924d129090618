// `marvin run --sim` (the host with simulated devices and a console), `marvin skills list`
// (what the registry loaded, and what it refused) and `marvin skills reload` (asks running
// hosts to pick up changed skills now).
//
// Skills directories: without --skills-dir, the store's installed-skills directory
// (app/installed_skills.h, the same default as `marvin skill install`) when it exists; with
// --skills-dir, exactly the directories named, so `marvin skill install --skills-dir D` and
// `marvin run --sim --skills-dir D` work on the same skills. The running host watches them
// and reloads what changed (Host::watch_skills()).
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <functional>
#include <iostream>
#include <memory>
#include <string>
#include <thread>

#include "app/cli.h"
#include "app/host.h"
#include "app/shutdown_signals.h"
#include "app/voice_run.h"
#include "app/web_run.h"
#include "app/installed_skills.h"
#include "common/log.h"
#include "sim/world.h"
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
  // The simulated home: --world (default examples/worlds/home.json with --sim), --speed,
  // --seed, --show.
  std::string world;
  double speed = 1;
  std::uint64_t seed = 1;
  std::string show;
  std::string camera;
  std::string mqtt;         // --mqtt HOST:PORT
  std::string home_config;  // --home-config FILE
  VoiceRunOptions voice;  // --audio-in/--audio-out, --wake-word; live without --sim
  WebRunOptions web;      // the carer's web page (app/web_run.h)
  bool no_phone = false;   // --no-phone
  double phone_no_answer_s = 30;  // --phone-no-answer
  int phone_port = 0;             // --phone-port (0: a free one)
  std::string phone_config;       // --phone-config FILE
};

// The smart home: --mqtt (a broker without authentication, e.g. scripts/sim's), else
// --home-config, else the default config file when it exists; nullopt: none.
std::optional<home::HomeConfig> home_options(const std::string& mqtt, const std::string& file) {
  try {
    if (!mqtt.empty()) {
      home::HomeConfig c;
      c.broker = home::broker_from_address(mqtt);
      return c;
    }
    std::optional<std::filesystem::path> path;
    if (!file.empty()) {
      path = file;
    } else if (auto fallback = home::default_home_config_path();
               fallback && std::filesystem::exists(*fallback)) {
      path = fallback;
    }
    if (!path) return std::nullopt;
    return home::load_home_config(*path);
  } catch (const home::ConfigError& e) {
    throw CliError(e.what(), 2);
  }
}

HostOptions host_options(const RunOptions& o) {
  HostOptions h;
  for (const auto& dir : o.skills_dirs) h.skills_dirs.emplace_back(dir);
  if (o.skills_dirs.empty()) {
    if (auto installed = default_installed_skills_dir()) h.installed_skills_dir = *installed;
  }
  h.builtin_skills = !o.no_builtin;
  h.in_memory_data = o.in_memory;
  h.data_dir = o.data_dir;
  h.mcu_tty = o.mcu_tty;
  // --sim lives in the default home unless another world is named. With --mcu-tty the base
  // is behind the serial link; a --world then gives it a floor plan to go places on.
  if (!o.mcu_tty.empty()) {
    h.world_file = o.world;
  } else if (o.sim) {
    h.world_file = o.world.empty() ? sim::default_world_file() : std::filesystem::path(o.world);
    h.sim_speed = o.speed;
    h.sim_seed = o.seed;
    h.show = o.show;
  }
  h.camera = o.camera;  // empty with --sim: the simulated home's camera (Host)
  h.home = home_options(o.mqtt, o.home_config);
  // --sim: a phone with a simulated other end (app/host_phone.h), unless --no-phone; the
  // robot's own account from --phone-config (the real robot: its sound card).
  if (!o.no_phone && (o.sim || !o.phone_config.empty())) {
    PhoneOptions phone;
    phone.settings.account_uri = "sip:marvin@127.0.0.1";
    phone.settings.sip_port = o.phone_port;
    if (!o.phone_config.empty()) {
      try {
        phone.settings = load_phone_config(o.phone_config);
      } catch (const std::exception& e) {
        throw CliError(std::string("--phone-config: ") + e.what(), 2);
      }
      if (o.phone_port != 0) phone.settings.sip_port = o.phone_port;
      if (!o.sim) phone.settings.audio = telephony::PhoneSettings::Audio::kAlsa;
    }
    phone.no_answer_timeout =
        std::chrono::milliseconds(static_cast<std::int64_t>(o.phone_no_answer_s * 1000));
    if (o.sim) phone.simulated_people = sim::default_world_file().parent_path() / "phone.json";
    h.phone = std::move(phone);
  }
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
  } catch (const sim::WorldError& e) {
    throw CliError(std::string("cannot load the world: ") + e.what(), 2);
  } catch (const std::exception& e) {
    throw CliError(std::string("cannot open the personal data: ") + e.what() +
                       " (use --data-dir DIR, or --in-memory)",
                   1);
  }
}

void run_sim(const RunOptions& o) {
  // Before any thread starts (see shutdown_signals.h); a signal before the handler is set
  // is kept for it.
  ShutdownSignals signals;
  // Without --sim: the microphone and speaker (a clear error without a sound card).
  std::shared_ptr<LiveAudio> live;
  if (!o.sim) {
    if (!o.voice.audio_in.empty()) {
      throw CliError("--audio-in plays a recording to the simulated robot: add --sim", 2);
    }
    live = open_live_audio(o.voice);
  }
  set_log_level(o.verbose ? LogLevel::kInfo : LogLevel::kWarning);
  // The console's lines also feed the web page's live view.
  auto feed = std::make_shared<web::LiveFeed>();
  std::unique_ptr<Host> host_ptr = open_host(o, [feed](std::string_view line) {
    write_line(line);
    feed->console_line(line);
  });
  Host& host = *host_ptr;
  // Watching starts before loading, so nothing installed meanwhile is missed (a reload
  // that finds no change does nothing).
  try {
    host.watch_skills();
  } catch (const std::exception& e) {
    log(LogLevel::kWarning, "skills", std::string(e.what()) + "; installed skills are "
                                          "picked up at the next start");
  }
  host.load();
  const HostOptions options = host_options(o);
  std::unique_ptr<web::WebServer> page = start_web_for_host(
      host, o.web, *feed, options.installed_skills_dir, options.time_zone);
  if (live || !o.voice.audio_in.empty()) {
    // The voice run owns the host from here on; it stops the page before the host goes.
    return run_voice(std::move(host_ptr), o.voice, live, signals,
                     std::shared_ptr<void>(std::move(page)));
  }
  const bool interactive = isatty(STDIN_FILENO) != 0;
  if (interactive) {  // typed lines are not echoed, but the page shows them as turns
    write_line("Marvin (simulated robot). Type a request; Ctrl-D quits.");
    host.loop().on_heard([feed](std::string_view line) { feed->console_line("You: " + std::string(line)); });
  } else {
    host.loop().on_heard([feed](std::string_view line) {
      write_line("You: " + std::string(line));
      feed->console_line("You: " + std::string(line));
    });
  }
  // The console reader feeds the host loop; the loop runs here until end of input, or
  // until a signal stops it (the reader goes then too, the input still open).
  auto reader = std::make_unique<ConsoleReader>(host);
  signals.on_signal([&host](int signal) {
    host.show(std::string("[") + signal_name(signal) + ": stopping]");
    host.loop().shut_down();
  });
  host.body().set_light(devices::Light::kAwaiting);
  host.manager().say("Hello, I'm Marvin.");
  host.start_scheduler();
  host.loop().run();
  signals.on_signal({});  // the handler uses the host, which goes below
  reader.reset();
  page.reset();  // before the host it serves
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

// Rewrites <dir>/.store/reload-request for each directory: a running host watching the
// directory reloads what changed there (SkillWatcher). Nothing happens without a host.
void request_reload(const std::vector<std::string>& given) {
  std::vector<std::filesystem::path> dirs(given.begin(), given.end());
  if (dirs.empty()) {
    std::optional<std::filesystem::path> installed = default_installed_skills_dir();
    if (!installed) {
      throw CliError("no skills directory: pass --skills-dir or set MARVIN_SKILLS_DIR");
    }
    dirs.push_back(*installed);
  }
  for (const auto& dir : dirs) {
    std::error_code ec;
    if (!std::filesystem::is_directory(dir, ec)) {
      throw CliError("skills directory " + dir.string() + " does not exist", 1);
    }
  }
  for (const auto& dir : dirs) {
    std::filesystem::path request = reload_request_file(dir);
    std::error_code ec;
    std::filesystem::create_directories(request.parent_path(), ec);
    std::ofstream out(request, std::ios::trunc);
    out << "reload requested by process " << ::getpid() << "\n";
    out.close();
    if (!out) throw CliError("cannot write " + request.string(), 1);
    write_line("asked running hosts to reload the skills in " + dir.string() + " (" +
               request.string() + ")");
  }
}

void add_skill_options(CLI::App& app, RunOptions& o) {
  app.add_option("--skills-dir", o.skills_dirs,
                 "Load the skills in this directory instead of the installed skills "
                 "($MARVIN_SKILLS_DIR or ~/.local/share/marvin/skills); repeatable");
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
  run->add_option("--world", options->world,
                  "With --sim: live in this world file (default: examples/worlds/home.json); "
                  "with --mcu-tty: the floor plan to go places on");
  run->add_option("--speed", options->speed,
                  "With --sim: simulated seconds per second (default 1; 10 runs 10x faster)")
      ->check(CLI::Range(0.1, 1000.0));
  run->add_option("--seed", options->seed, "With --sim: the simulation's random seed (default 1)");
  run->add_option("--show", options->show,
                  "With --sim: keep this PNG picture of the floor plan and the robot up to date");
  run->add_option("--camera", options->camera,
                  "The camera skills look through: device:/dev/video0, device:0, folder:DIR or "
                  "video:FILE (--sim default: the simulated home's camera)");
  run->add_option("--mqtt", options->mqtt,
                  "Smart home: the home's MQTT broker HOST:PORT (no authentication)");
  run->add_option("--home-config", options->home_config,
                  "Smart home: the config file (default: $MARVIN_HOME_CONFIG, else "
                  "~/.config/marvin/home.json when it exists)");
  run->add_flag("--no-phone", options->no_phone,
                "With --sim: no phone (by default baresip calls a simulated other end)");
  run->add_option("--phone-no-answer", options->phone_no_answer_s,
                  "Seconds a call may ring before \"not answering\" (default 30)")
      ->check(CLI::Range(0.5, 300.0));
  run->add_option("--phone-config", options->phone_config,
                  "The robot's SIP account: JSON {\"account\", \"registrar\", \"user\", "
                  "\"password\", \"sip_port\", \"audio_device\"} (app/host_phone.h)");
  run->add_option("--phone-port", options->phone_port,
                  "With --sim: Marvin's SIP port on 127.0.0.1 (default: a free one; baresip "
                  "also takes the port above it)")
      ->check(CLI::Range(0, 65534));
  add_skill_options(*run, *options);
  add_voice_run_options(*run, options->voice);
  add_web_run_options(*run, options->web);
  run->callback([options] { run_sim(*options); });

  CLI::App& skills = command_group(root, "skills", "Installed skills");
  CLI::App* list = skills.add_subcommand("list", "Skills, versions, kinds, intents, load errors");
  add_skill_options(*list, *options);
  list->callback([options] { list_skills(*options); });

  auto reload_dirs = std::make_shared<std::vector<std::string>>();
  CLI::App* reload = skills.add_subcommand(
      "reload", "Ask running hosts to reload the skills that changed (installed, edited, removed)");
  reload->add_option("--skills-dir", *reload_dirs,
                     "This directory (default: the installed skills); repeatable");
  reload->callback([reload_dirs] { request_reload(*reload_dirs); });
}

}  // namespace

MARVIN_CLI_COMMANDS(install_skill_platform_commands);

}  // namespace marvin::app
