// `marvin web password` (the carer's password for the web page) and `marvin web serve` (the
// page without a running robot, on the personal data and installed skills); the page in
// `marvin run` (web_run.h). See core/web/README.md.
#include <signal.h>
#include <termios.h>
#include <unistd.h>

#include <cstdio>
#include <iostream>
#include <memory>
#include <string>

#include "app/cli.h"
#include "app/host.h"
#include "app/installed_skills.h"
#include "app/web_run.h"
#include "common/log.h"
#include "data/sqlite_store.h"
#include "navigation/navigator.h"
#include "web/auth.h"

namespace marvin::app {

namespace fs = std::filesystem;

namespace {

fs::path data_dir_or_default(const std::string& dir) {
  return dir.empty() ? data::default_data_dir() : fs::path(dir);
}

// One line of standard input; on a terminal without echo.
std::string read_secret(const char* prompt) {
  const bool tty = ::isatty(STDIN_FILENO) != 0;
  termios saved{};
  if (tty) {
    std::fputs(prompt, stderr);
    std::fflush(stderr);
    ::tcgetattr(STDIN_FILENO, &saved);
    termios quiet = saved;
    quiet.c_lflag &= ~static_cast<tcflag_t>(ECHO);
    ::tcsetattr(STDIN_FILENO, TCSANOW, &quiet);
  }
  std::string line;
  const bool got = static_cast<bool>(std::getline(std::cin, line));
  if (tty) {
    ::tcsetattr(STDIN_FILENO, TCSANOW, &saved);
    std::fputc('\n', stderr);
  }
  if (!got) throw CliError("no password given on standard input", 2);
  if (!line.empty() && line.back() == '\r') line.pop_back();
  return line;
}

web::WebOptions web_options(const WebRunOptions& o, const fs::path& data_dir,
                            const fs::path& skills_dir, const std::string& time_zone) {
  web::WebOptions w;
  w.listen = o.listen;
  w.state_dir = web::web_state_dir(data_dir);
  w.cert_file = o.cert;
  w.key_file = o.key;
  if (!o.root.empty()) w.static_dir = o.root;
  w.skills_dir = skills_dir;
  w.validate_skill = validate_skill_for_host;
  w.trusted_keys = [skills_dir] { return repository_keys(skills_dir); };
  w.time_zone = time_zone;
  return w;
}

fs::path default_skills_dir() { return default_installed_skills_dir().value_or(fs::path()); }

void install_web(CLI::App& root) {
  CLI::App& group = command_group(root, "web", "The carer's web page");
  {
    auto* cmd = group.add_subcommand(
        "password",
        "Set the web page's password (read from standard input; asked twice on a terminal)");
    auto dir = std::make_shared<std::string>();
    cmd->add_option("--data-dir", *dir, "Personal data directory (default: $MARVIN_DATA_DIR, ...)");
    cmd->callback([dir] {
      const fs::path file = web::password_file(web::web_state_dir(data_dir_or_default(*dir)));
      const std::string password = read_secret("New password for the web page: ");
      if (::isatty(STDIN_FILENO) && read_secret("Again: ") != password)
        throw CliError("the two passwords differ; nothing was changed", 2);
      try {
        web::set_password(file, password);
      } catch (const std::exception& e) {
        throw CliError(std::string(e.what()) + "; nothing was changed", 2);
      }
      write_line("password set in " + file.string() +
                 " (open sessions stay logged in until they expire)");
    });
  }
  {
    auto* cmd = group.add_subcommand(
        "serve",
        "Serve the web page on the personal data and installed skills, without the robot "
        "(until SIGINT/SIGTERM)");
    struct Args {
      std::string data_dir, skills_dir, time_zone;
      WebRunOptions web;
    };
    auto a = std::make_shared<Args>();
    cmd->add_option("--data-dir", a->data_dir,
                    "Personal data directory (default: $MARVIN_DATA_DIR, ...)");
    cmd->add_option("--skills-dir", a->skills_dir,
                    "Installed skills (default: $MARVIN_SKILLS_DIR, ...)");
    cmd->add_option("--tz", a->time_zone,
                    "IANA time zone for times shown and entered (default: the system's)");
    add_web_run_options(*cmd, a->web);
    cmd->callback([a] {
      const fs::path data_dir = data_dir_or_default(a->data_dir);
      data::StoreOptions so;
      so.path = data::database_path(data_dir);
      data::SqliteStore store(so);
      const fs::path skills =
          a->skills_dir.empty() ? default_skills_dir() : fs::path(a->skills_dir);
      web::WebServer server(web_options(a->web, data_dir, skills,
                                        a->time_zone.empty() ? system_time_zone() : a->time_zone),
                            store, store, nullptr);
      // Signals are taken by sigwait below, not by a handler.
      sigset_t signals;
      sigemptyset(&signals);
      sigaddset(&signals, SIGINT);
      sigaddset(&signals, SIGTERM);
      pthread_sigmask(SIG_BLOCK, &signals, nullptr);
      try {
        server.start();
      } catch (const std::exception& e) {
        throw CliError(e.what());
      }
      write_line("Marvin's page: " + server.url());
      if (!web::password_is_set(web::password_file(web::web_state_dir(data_dir))))
        write_line("no password yet: set one with `marvin web password`");
      int signal = 0;
      sigwait(&signals, &signal);
      server.stop();
    });
  }
}

}  // namespace

void add_web_run_options(CLI::App& run, WebRunOptions& options) {
  run.add_option("--web-listen", options.listen,
                 "Serve the carer's web page on ADDR:PORT (default 127.0.0.1:8443; "
                 "0.0.0.0:8443 for the home network)");
  run.add_flag("--no-web", options.off, "Do not serve the web page");
  run.add_option("--web-cert", options.cert,
                 "The page's certificate (PEM; default: made on first start)");
  run.add_option("--web-key", options.key, "The certificate's private key (PEM)");
  run.add_option("--web-root", options.root,
                 "The page's HTML/CSS/JS folder (default: this build's)");
}

std::unique_ptr<web::WebServer> start_web_for_host(Host& host, const WebRunOptions& options,
                                                   web::LiveFeed& feed, const fs::path& skills_dir,
                                                   const std::string& time_zone) {
  if (options.off || !host.store()) return nullptr;
  const fs::path data_dir = host.data_path().parent_path();
  if (!web::password_is_set(web::password_file(web::web_state_dir(data_dir)))) {
    // On the log, not the console: the transcript stays what the robot says and does.
    log(LogLevel::kInfo, "web", "the web page is off until a password is set with `marvin web password`");
    return nullptr;
  }
  web::WebOptions w = web_options(
      options, data_dir, skills_dir.empty() ? default_skills_dir() : skills_dir, time_zone);
  // The devices and home pages: the same smart home and navigator voice and skills use.
  w.smart_home = host.smart_home();
  if (navigation::Navigator* navigator = host.navigator()) {
    w.floor_map = &navigator->map();
    w.robot_pose = [navigator]() -> std::optional<navigation::Pose> { return navigator->pose(); };
  }
  auto server = std::make_unique<web::WebServer>(std::move(w), host.data(), *host.store(), &feed);
  try {
    server->start();
  } catch (const std::exception& e) {
    log(LogLevel::kWarning, "web", std::string("the web page is not served: ") + e.what());
    return nullptr;
  }
  host.show("[web page: " + server->url() + "]");
  return server;
}

MARVIN_CLI_COMMANDS(install_web);

}  // namespace marvin::app
