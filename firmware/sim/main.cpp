// marvin-mcu-sim: the portable firmware core (firmware/core) against a simulated body in a
// simulated room, attached to a pseudo-terminal, so the host drives it through a real tty
// exactly as it drives the board.
//
//   marvin-mcu-sim (--room ROOM.json | --world WORLD.json [--seed N]) [--link PATH]
//                  [--state FILE] [--deadman-ms N]
//
// --world puts the body in a simulated home (sim/world.h, examples/worlds/home.json): the
// world's base (acceleration, seeded odometry noise) and its HC-SR04 model (cone, noise,
// dropouts) answer the firmware core's commands and pings; --room keeps the older
// corridor model (firmware/sim/room.h).
// --link makes PATH a symlink to the pty's slave (replaced atomically, so a restarted
// simulator reappears at the same path); the slave's name is also printed on stdout.
// --state writes the body's pose as JSON every 100 ms (for tests and curious users).
// Time is the steady clock's, and the core runs as if on a CPU of its own: when this
// process was not scheduled for a while, the body, the core's deadman and the bytes that
// arrived meanwhile are played through the gap rather than jumping at its end.
// SIGINT / SIGTERM end it cleanly (the link is removed).
#include <fcntl.h>
#include <poll.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <memory>
#include <stdexcept>
#include <string>

#include "core/marvin_core.h"
#include "room.h"
#include "sim/simulator.h"

namespace {

volatile std::sig_atomic_t g_quit = 0;
void on_signal(int) { g_quit = 1; }

struct Sim {
  std::unique_ptr<marvin::sim::Simulator> world;  // with --world; else the room below
  marvin::mcusim::Room room;
  marvin::mcusim::RobotPose pose;
  int master = -1;
  std::uint8_t speed[2] = {0, 0}, backward[2] = {0, 0};
  int head_deg = 0, sonar_deg = 0, leds = 0;
  long collisions = 0;
  bool touching = false;
  std::uint64_t bytes_dropped = 0;
};

void hal_set_motor(void* ctx, std::uint8_t side, std::uint8_t backward, std::uint8_t speed) {
  auto* s = static_cast<Sim*>(ctx);
  s->speed[side & 1] = speed;
  s->backward[side & 1] = backward;
  if (s->world) s->world->set_motor(side & 1, backward != 0, speed);
}
void hal_set_head(void* ctx, std::int8_t degrees) {
  auto* s = static_cast<Sim*>(ctx);
  s->head_deg = degrees;
  if (s->world) s->world->set_head(degrees);
}
void hal_set_sonar_servo(void* ctx, std::uint8_t degrees) {
  static_cast<Sim*>(ctx)->sonar_deg = degrees;
}
void hal_set_leds(void* ctx, std::uint8_t bits) {
  auto* s = static_cast<Sim*>(ctx);
  s->leds = bits;
  if (s->world) s->world->set_leds(bits);
}
void hal_send(void* ctx, const std::uint8_t* bytes, std::size_t n) {
  auto* s = static_cast<Sim*>(ctx);
  // Like a UART nobody listens to: what the pty cannot take is lost.
  ssize_t w = ::write(s->master, bytes, n);
  if (w < 0 || static_cast<std::size_t>(w) < n)
    s->bytes_dropped += n - (w < 0 ? 0 : static_cast<std::size_t>(w));
}

double wheel_m_s(const Sim& s, int side) {
  double v = s.speed[side] / 255.0 * s.room.max_speed_m_s;
  return s.backward[side] ? -v : v;
}

void write_state(const Sim& s, const std::string& path, std::uint32_t now_ms) {
  if (path.empty()) return;
  std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::trunc);
    out << "{\"x\": " << s.pose.x << ", \"y\": " << s.pose.y
        << ", \"heading_deg\": " << s.pose.heading_deg
        << ", \"clearance_m\": "
        << (s.world ? s.world->clearance_m(s.world->pose())
                    : marvin::mcusim::clearance_m(s.room, s.pose))
        << ", \"left\": " << (s.backward[0] ? -1 : 1) * s.speed[0]
        << ", \"right\": " << (s.backward[1] ? -1 : 1) * s.speed[1]
        << ", \"head_deg\": " << s.head_deg << ", \"leds\": " << s.leds
        << ", \"collisions\": " << s.collisions << ", \"time_ms\": " << now_ms << "}\n";
  }
  std::rename(tmp.c_str(), path.c_str());
}

int open_pty(std::string* slave_name, int* slave_fd) {
  int master = ::posix_openpt(O_RDWR | O_NOCTTY);
  if (master < 0 || ::grantpt(master) != 0 || ::unlockpt(master) != 0)
    throw std::runtime_error(std::string("cannot create a pseudo-terminal: ") +
                             std::strerror(errno));
  const char* name = ::ptsname(master);
  if (!name) throw std::runtime_error("ptsname failed");
  *slave_name = name;
  // Keep the slave open ourselves: the master then survives the host closing its side.
  *slave_fd = ::open(name, O_RDWR | O_NOCTTY);
  if (*slave_fd < 0)
    throw std::runtime_error(std::string("cannot open ") + name + ": " + std::strerror(errno));
  termios t{};
  ::tcgetattr(*slave_fd, &t);
  ::cfmakeraw(&t);
  ::cfsetispeed(&t, B115200);
  ::cfsetospeed(&t, B115200);
  ::tcsetattr(*slave_fd, TCSANOW, &t);
  ::fcntl(master, F_SETFL, ::fcntl(master, F_GETFL) | O_NONBLOCK);
  return master;
}

void make_link(const std::string& target, const std::string& link) {
  std::string tmp = link + ".new";
  ::unlink(tmp.c_str());
  if (::symlink(target.c_str(), tmp.c_str()) != 0 || std::rename(tmp.c_str(), link.c_str()) != 0)
    throw std::runtime_error("cannot make the link " + link + ": " + std::strerror(errno));
}

void usage() {
  std::fprintf(
      stderr,
      "usage: marvin-mcu-sim (--room ROOM.json | --world WORLD.json [--seed N]) [--link PATH]\n"
      "                      [--state FILE] [--deadman-ms N]\n");
}

}  // namespace

int main(int argc, char** argv) {
  std::string room_path, world_path, link_path, state_path;
  std::uint64_t seed = 1;
  mv_config cfg;
  mv_config_defaults(&cfg);
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) {
        usage();
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--room") {
      room_path = value();
    } else if (a == "--world") {
      world_path = value();
    } else if (a == "--seed") {
      seed = std::stoull(value());
    } else if (a == "--link") {
      link_path = value();
    } else if (a == "--state") {
      state_path = value();
    } else if (a == "--deadman-ms") {
      cfg.deadman_ms = static_cast<std::uint16_t>(std::stoi(value()));
    } else {
      usage();
      return 2;
    }
  }
  if (room_path.empty() == world_path.empty()) {
    usage();
    return 2;
  }
  try {
    Sim sim;
    if (!world_path.empty()) {
      marvin::sim::SimOptions options;
      options.seed = seed;
      sim.world = std::make_unique<marvin::sim::Simulator>(marvin::sim::load_world(world_path),
                                                           options);
      sim.world->set_sweep(0, 0, 0, 1);  // the firmware core schedules the pings itself
      sim.world->on_collision([&sim](const marvin::navigation::Pose& p) {
        ++sim.collisions;
        std::fprintf(stderr, "marvin-mcu-sim: collision at (%.2f, %.2f)\n", p.x, p.y);
      });
      const auto& p = sim.world->pose();
      sim.pose = {p.x, p.y, p.heading * 180.0 / marvin::navigation::kPi};
    } else {
      sim.room = marvin::mcusim::load_room(room_path);
      sim.pose = sim.room.start;
    }

    std::string slave;
    int slave_fd = -1;
    sim.master = open_pty(&slave, &slave_fd);
    if (!link_path.empty()) make_link(slave, link_path);
    std::printf("%s\n", slave.c_str());
    std::fflush(stdout);
    std::signal(SIGINT, on_signal);
    std::signal(SIGTERM, on_signal);
    std::signal(SIGPIPE, SIG_IGN);

    const mv_hal hal = {&sim,         hal_set_motor, hal_set_head, hal_set_sonar_servo,
                        hal_set_leds, hal_send};
    auto start = std::chrono::steady_clock::now();
    auto now_ms = [&] {
      return static_cast<std::uint32_t>(std::chrono::duration_cast<std::chrono::milliseconds>(
                                            std::chrono::steady_clock::now() - start)
                                            .count());
    };
    mv_core core;
    mv_core_init(&core, &hal, &cfg, now_ms());
    std::uint32_t last_ms = now_ms(), last_state_ms = 0;
    // Moves the body from last_ms to `t` with the wheel speeds the core set, running the core's
    // tick at least every 10 ms on the way (its deadman, its status): what an MCU with a CPU
    // of its own does, even when this process did not run for a while (a busy machine). A wall
    // stops the body (a collision).
    auto advance_to = [&](std::uint32_t t) {
      while (static_cast<std::int32_t>(t - last_ms) > 0) {
        const std::uint32_t next = t - last_ms > 10 ? last_ms + 10 : t;
        const double dt = (next - last_ms) / 1000.0;
        if (sim.world) {
          sim.world->step(dt);
          const auto& truth = sim.world->pose();
          sim.pose = {truth.x, truth.y, truth.heading * 180.0 / marvin::navigation::kPi};
        } else {
          bool moved = marvin::mcusim::step_body(sim.room, sim.pose, wheel_m_s(sim, 0),
                                                 wheel_m_s(sim, 1), dt);
          bool pushing = !moved && (sim.speed[0] || sim.speed[1]);
          if (pushing && !sim.touching) {
            ++sim.collisions;
            std::fprintf(stderr, "marvin-mcu-sim: collision at (%.2f, %.2f)\n", sim.pose.x,
                         sim.pose.y);
          }
          sim.touching = pushing;
        }
        last_ms = next;
        mv_core_tick(&core, next);
      }
    };
    bool rx_active = false;
    while (!g_quit) {
      pollfd p{sim.master, POLLIN, 0};
      int r = ::poll(&p, 1, 1);
      std::uint32_t now = now_ms();
      if (r > 0 && (p.revents & POLLIN)) {
        std::uint8_t buf[4096];  // all a pty holds: what waited is spread over the wait below
        ssize_t n = ::read(sim.master, buf, sizeof buf);
        // The bytes waited in the pty while this process was not running; the host sent them
        // spread over that time, so they are taken spread over it (not all at its start or
        // end: a turn's end would then come too early or too late by the whole wait).
        const std::uint32_t waited_from = last_ms;
        const std::uint64_t waited = now - waited_from;
        for (ssize_t i = 0; i < n; ++i) {
          const std::uint32_t at =
              waited_from + static_cast<std::uint32_t>(waited * static_cast<std::uint64_t>(i + 1) /
                                                       static_cast<std::uint64_t>(n));
          advance_to(at);
          mv_core_rx(&core, buf[i], at);
        }
        rx_active = n > 0;
      } else if (rx_active) {
        mv_core_rx_idle(&core, now);  // the UART's IDLE interrupt
        rx_active = false;
      }
      advance_to(now);
      std::uint8_t angle;
      if (mv_core_ping_due(&core, now, &angle)) {
        if (sim.world) {
          const marvin::sim::SonarSample reading = sim.world->measure(angle);
          mv_core_echo(&core, reading.echo ? marvin::mcusim::echo_us_for(reading.distance_m) : 0,
                       now);
        } else {
          double d = marvin::mcusim::sonar_distance_m(sim.room, sim.pose, angle);
          mv_core_echo(&core, marvin::mcusim::echo_us_for(d), now);
        }
      }
      if (now - last_state_ms >= 100) {
        write_state(sim, state_path, now);
        last_state_ms = now;
      }
    }
    write_state(sim, state_path, now_ms());
    if (!link_path.empty()) ::unlink(link_path.c_str());
    ::close(slave_fd);
    ::close(sim.master);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "marvin-mcu-sim: %s\n", e.what());
    return 1;
  }
  return 0;
}
