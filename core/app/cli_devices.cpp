// `marvin mcu ...`: talk to the body's MCU (or marvin-mcu-sim) over its serial link.
//
//   marvin mcu status --tty PATH            wait for one STATUS frame and print it
//   marvin mcu scan --tty PATH [--seconds S] print the filtered sonar scan after S seconds
//   marvin mcu move --tty PATH DIR SPEED MS  drive (forward|backward|left|right), then stop
//   marvin mcu stop --tty PATH
//   marvin mcu tilt --tty PATH DEGREES
//   marvin mcu light --tty PATH off|awaiting|listening|executing
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "app/cli.h"
#include "devices/serial_body.h"

namespace marvin::app {
namespace {

using namespace std::chrono_literals;
using devices::SerialBody;

struct McuOptions {
  std::string tty;
  double seconds = 3;
  std::string direction, light;
  int speed = 0, ms = 0, degrees = 0;
};

// Opens the link and waits (up to 5 s) for the first STATUS, so commands are not dropped.
std::unique_ptr<SerialBody> connect(const std::string& tty,
                                    std::optional<devices::Status>* first = nullptr) {
  auto body = std::make_unique<SerialBody>(tty);
  std::mutex mu;
  std::condition_variable cv;
  std::optional<devices::Status> status;
  int id = body->link().add_telemetry_callback([&](const devices::Telemetry& t) {
    if (auto* s = std::get_if<devices::Status>(&t)) {
      std::lock_guard lock(mu);
      status = *s;
      cv.notify_all();
    }
  });
  {
    std::unique_lock lock(mu);
    cv.wait_for(lock, 5s, [&] { return status.has_value(); });
  }
  body->link().remove_callback(id);
  if (!status)
    throw CliError("mcu: no status from " + tty +
                   " within 5 s (is the board or marvin-mcu-sim running?)");
  if (first) *first = status;
  return body;
}

void print_status(const devices::Status& s) {
  std::printf("left %s%d right %s%d head %d sweeping %s blocked %s rx-errors %d mcu-time %u ms\n",
              s.left_backward ? "-" : "", s.left_speed, s.right_backward ? "-" : "", s.right_speed,
              s.head_deg, s.sweeping ? "yes" : "no", s.blocked ? "yes" : "no", s.rx_errors,
              static_cast<unsigned>(s.mcu_time_ms));
}

void install(CLI::App& root) {
  auto opts = std::make_shared<McuOptions>();
  CLI::App* mcu =
      root.add_subcommand("mcu", "Talk to the body's MCU (or marvin-mcu-sim) over the serial link");
  mcu->require_subcommand(1);
  auto tty = [&](CLI::App* c) {
    c->add_option("--tty", opts->tty, "serial device or pty link")->required();
  };

  CLI::App* status = mcu->add_subcommand("status", "Print the MCU's status");
  tty(status);
  status->callback([opts] {
    std::optional<devices::Status> s;
    connect(opts->tty, &s);
    print_status(*s);
  });

  CLI::App* scan = mcu->add_subcommand("scan", "Print the filtered sonar scan");
  tty(scan);
  scan->add_option("--seconds", opts->seconds, "how long to listen (default 3)");
  scan->callback([opts] {
    auto body = connect(opts->tty);
    std::mutex mu;
    std::condition_variable cv;
    std::unique_lock lock(mu);
    cv.wait_for(lock, std::chrono::duration<double>(opts->seconds));  // listen for a while
    for (const auto& p : body->latest_scan())
      std::printf("%5.0f deg  %.3f m\n", p.angle_deg, p.distance_m);
  });

  CLI::App* move = mcu->add_subcommand("move", "Drive, then stop");
  tty(move);
  move->add_option("direction", opts->direction, "forward|backward|left|right")->required();
  move->add_option("speed", opts->speed, "0..255")->required()->check(CLI::Range(0, 255));
  move->add_option("ms", opts->ms, "duration in ms")->required()->check(CLI::Range(0, 60000));
  move->callback([opts] {
    static const std::map<std::string, devices::Direction> kDirections = {
        {"forward", devices::Direction::kForward},
        {"backward", devices::Direction::kBackward},
        {"left", devices::Direction::kLeft},
        {"right", devices::Direction::kRight}};
    auto it = kDirections.find(opts->direction);
    if (it == kDirections.end())
      throw CliError("mcu move: direction must be forward, backward, left or right, not '" +
                     opts->direction + "'");
    auto body = connect(opts->tty);
    body->move(it->second, static_cast<std::uint8_t>(opts->speed),
               std::chrono::milliseconds(opts->ms));
    std::mutex mu;
    std::condition_variable cv;
    std::unique_lock lock(mu);
    cv.wait_for(lock, std::chrono::milliseconds(opts->ms) + 200ms,
                [&] { return !body->motors().driving(); });
    body->stop();
  });

  CLI::App* stop = mcu->add_subcommand("stop", "Stop every motor");
  tty(stop);
  stop->callback([opts] { connect(opts->tty)->stop(); });

  CLI::App* tilt = mcu->add_subcommand("tilt", "Tilt the head (-60..60 degrees)");
  tty(tilt);
  tilt->add_option("degrees", opts->degrees, "above level")->required()->check(CLI::Range(-60, 60));
  tilt->callback([opts] { connect(opts->tty)->tilt_head(opts->degrees); });

  CLI::App* light = mcu->add_subcommand("light", "Set the status light");
  tty(light);
  light->add_option("state", opts->light, "off|awaiting|listening|executing")->required();
  light->callback([opts] {
    static const std::map<std::string, devices::Light> kLights = {
        {"off", devices::Light::kOff},
        {"awaiting", devices::Light::kAwaiting},
        {"listening", devices::Light::kListening},
        {"executing", devices::Light::kExecuting}};
    auto it = kLights.find(opts->light);
    if (it == kLights.end())
      throw CliError("mcu light: state must be off, awaiting, listening or executing, not '" +
                     opts->light + "'");
    connect(opts->tty)->set_light(it->second);
  });
}

}  // namespace

MARVIN_CLI_COMMANDS(install);

}  // namespace marvin::app
