// The carer's web page in `marvin run` (implemented in cli_web.cpp, used by cli_skills.cpp).
//
// Decision: a running host serves the page by default on 127.0.0.1:8443 (only this
// machine), provided its personal data is the SQLite store and a password was set with
// `marvin web password`; without a password there is nobody who could log in, so it says
// how to set one instead (on the log: `marvin run -v`). --web-listen ADDR:PORT serves it elsewhere (0.0.0.0:8443 for the
// home network), --no-web turns it off. A port already in use is a warning, not a reason
// for the robot not to run.
#pragma once

#include <memory>
#include <string>

#include "app/cli.h"
#include "app/host.h"
#include "web/live.h"
#include "web/web_server.h"

namespace marvin::app {

struct WebRunOptions {
  std::string listen = "127.0.0.1:8443";
  bool off = false;
  std::string cert;  // --web-cert/--web-key: the user's certificate (PEM)
  std::string key;
  std::string root;  // --web-root: the page's files (default: this build's)
};

void add_web_run_options(CLI::App& run, WebRunOptions& options);

// Starts the page for `host` (its data, store and `feed`, the console lines); null when it
// is off or cannot start (the reason is logged). When it starts, the console shows
// "[web page: https://127.0.0.1:8443/]".
std::unique_ptr<web::WebServer> start_web_for_host(Host& host, const WebRunOptions& options,
                                                   web::LiveFeed& feed,
                                                   const std::filesystem::path& skills_dir,
                                                   const std::string& time_zone);

}  // namespace marvin::app
