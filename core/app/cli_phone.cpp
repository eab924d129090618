// `marvin phone call URI`: places one call through Marvin's supervised baresip and prints
// its progress, one line per event ("ringing", "answered", "ended: busy"). A line "hangup"
// on stdin (or its end) hangs up. For trying a SIP account or a peer by hand, and for
// tests; the phone skill uses the same core/telephony Phone.
#include <poll.h>
#include <unistd.h>

#include <filesystem>
#include <iostream>
#include <memory>
#include <string>

#include "app/cli.h"
#include "telephony/phone.h"

namespace marvin::app {
namespace {

struct PhoneCallOptions {
  std::string uri;
  telephony::PhoneSettings settings;
  std::string audio_in;
  std::string record_dir;
  std::string config_dir;
  int no_answer_seconds = 30;
};

int run_phone_call(const PhoneCallOptions& o) {
  telephony::PhoneSettings settings = o.settings;
  settings.audio_in = o.audio_in;
  const std::filesystem::path config_dir =
      o.config_dir.empty() ? std::filesystem::temp_directory_path() /
                                 ("marvin-phone-" + std::to_string(::getpid()))
                           : std::filesystem::path(o.config_dir);
  settings.record_dir =
      o.record_dir.empty() ? config_dir / "recordings" : std::filesystem::path(o.record_dir);
  int pipe_fds[2];
  if (::pipe(pipe_fds) != 0) throw CliError("phone: cannot create a pipe");
  bool answered = false;
  std::string ended;
  telephony::Phone phone(
      settings, config_dir,
      [&](const telephony::PhoneEvent& e) {
        using Kind = telephony::PhoneEvent::Kind;
        switch (e.kind) {
          case Kind::kRinging: write_line("ringing " + e.peer_uri); break;
          case Kind::kAnswered:
            answered = true;
            write_line("answered " + e.peer_uri);
            break;
          case Kind::kEnded: {
            ended = telephony::to_string(e.end);
            write_line("ended: " + ended + (e.reason.empty() ? "" : " (" + e.reason + ")"));
            [[maybe_unused]] auto n = ::write(pipe_fds[1], "x", 1);
            break;
          }
          case Kind::kRegistrationFailed: write_line("registration failed: " + e.reason); break;
          case Kind::kServiceRestarted: write_line("phone service restarted"); break;
          case Kind::kIncoming: write_line("incoming call from " + e.peer_uri); break;
          case Kind::kRegistered: write_line("registered"); break;
        }
      },
      std::chrono::seconds(o.no_answer_seconds));
  phone.start();
  if (!phone.wait_ready(std::chrono::seconds(10))) {
    throw CliError("phone: baresip did not start (see its configuration in " +
                   config_dir.string() + ")");
  }
  const std::string uri = phone.uri_for(o.uri);
  if (uri.empty()) {
    throw CliError("phone: '" + o.uri + "' is neither a SIP address (sip:user@host) nor a "
                   "phone number");
  }
  if (const std::string refused = phone.dial(uri); !refused.empty()) throw CliError(refused);
  bool stdin_open = true;
  for (;;) {
    pollfd fds[2] = {{pipe_fds[0], POLLIN, 0}, {stdin_open ? 0 : -1, POLLIN, 0}};
    ::poll(fds, 2, -1);
    if (fds[0].revents) break;
    if (fds[1].revents) {
      std::string line;
      if (!std::getline(std::cin, line)) stdin_open = false;
      if (!stdin_open || line == "hangup") phone.hang_up();
    }
  }
  ::close(pipe_fds[0]);
  ::close(pipe_fds[1]);
  return answered ? 0 : 2;
}

void install_phone_commands(CLI::App& root) {
  CLI::App& phone = command_group(root, "phone", "Phone calls through Marvin's SIP user agent");
  auto* cmd = phone.add_subcommand("call", "Call a SIP address or number and print the progress");
  auto o = std::make_shared<PhoneCallOptions>();
  cmd->add_option("URI", o->uri, "sip:user@host, or a number (dialled at the account's domain)")
      ->required();
  cmd->add_option("--account", o->settings.account_uri, "Marvin's SIP address")->required();
  cmd->add_option("--registrar", o->settings.registrar, "Registrar URI (none: peer to peer)");
  cmd->add_option("--user", o->settings.auth_user, "Registration user name");
  cmd->add_option("--password", o->settings.auth_password, "Registration password");
  cmd->add_option("--sip-port", o->settings.sip_port, "SIP port on 127.0.0.1 (0: a free one)");
  cmd->add_option("--audio-in", o->audio_in, "WAV file sent as the call's audio");
  cmd->add_option("--record-dir", o->record_dir, "Where the other side's audio is recorded");
  cmd->add_option("--config-dir", o->config_dir, "Where baresip's configuration is written");
  cmd->add_option("--no-answer", o->no_answer_seconds, "Seconds before giving up (default 30)");
  cmd->callback([o] {
    const int code = run_phone_call(*o);
    if (code != 0) throw CliError("phone: the call was not answered", code);
  });
}

}  // namespace

MARVIN_CLI_COMMANDS(install_phone_commands);

}  // namespace marvin::app
