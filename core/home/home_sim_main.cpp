// marvin-home-sim --broker HOST:PORT [--world FILE] [--base zigbee2mqtt] [--mute NAME]...
// marvin-home-sim --free-port     prints a free TCP port on 127.0.0.1 (for scripts/sim)
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <boost/asio/io_context.hpp>
#include <boost/asio/signal_set.hpp>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <mutex>

#include "home/config.h"
#include "home/home_sim.h"
#include "home/mqtt_client.h"

namespace {

void print(const std::string& line) {
  std::fwrite(line.data(), 1, line.size(), stdout);
  std::fputc('\n', stdout);
  std::fflush(stdout);
}

int free_port() {
  int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t len = sizeof a;
  if (fd < 0 || ::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0 ||
      ::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len) != 0) {
    std::perror("marvin-home-sim: cannot find a free port");
    return 1;
  }
  ::close(fd);
  print(std::to_string(ntohs(a.sin_port)));
  return 0;
}

int usage() {
  std::fprintf(stderr,
               "usage: marvin-home-sim --broker HOST:PORT [--world FILE] [--base TOPIC] "
               "[--mute NAME]...\n       marvin-home-sim --free-port\n");
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  std::string broker, world = MARVIN_DEFAULT_WORLD, base = "zigbee2mqtt";
  std::set<std::string> mute;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw std::runtime_error(a + " needs a value");
      return argv[++i];
    };
    try {
      if (a == "--free-port") return free_port();
      if (a == "--broker") broker = value();
      else if (a == "--world") world = value();
      else if (a == "--base") base = value();
      else if (a == "--mute") mute.insert(value());
      else return usage();
    } catch (const std::exception& e) {
      std::fprintf(stderr, "marvin-home-sim: %s\n", e.what());
      return usage();
    }
  }
  if (broker.empty()) return usage();
  try {
    marvin::home::MqttOptions options = marvin::home::broker_from_address(broker);
    options.client_id = "marvin-home-sim";
    options.will_topic = base + "/bridge/state";
    options.will_payload = R"({"state":"offline"})";
    marvin::home::HomeSimulator sim(marvin::home::load_world_devices(world), base, mute);
    boost::asio::io_context io;
    std::unique_ptr<marvin::home::MqttClient> client;
    bool announced = false;
    client = std::make_unique<marvin::home::MqttClient>(
        io, options,
        [&](const std::string& topic, std::string_view payload, bool) {
          std::vector<std::string> lines;
          for (auto& [t, p] : sim.handle(topic, payload, &lines)) client->publish(t, p, 0, true);
          for (const std::string& line : lines) print(line);
        },
        [&](bool up) {
          if (!up) {
            print("broker lost; reconnecting");
            return;
          }
          for (auto& [t, p] : sim.announce()) client->publish(t, p, 1, true);
          print(announced ? "ready again" : "ready");
          announced = true;
        });
    client->subscribe(base + "/+/set");
    client->subscribe(base + "/+/+/set");
    client->subscribe(base + "/+/get");
    client->subscribe(base + "/+/+/get");
    boost::asio::signal_set signals(io, SIGINT, SIGTERM);
    signals.async_wait([&](const boost::system::error_code&, int) {
      client->stop();
      io.stop();
    });
    client->start();
    io.run();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "marvin-home-sim: %s\n", e.what());
    return 1;
  }
  return 0;
}
