// bench_home [ROUNDS]: figures for issue 19's goals, measured in one run against a real
// mosquitto on 127.0.0.1 and marvin-home-sim:
//   1. request -> device state change confirmed (HomeService::set: publish to
//      zigbee2mqtt/<name>/set, the simulator applies it and reports, the report matches),
//      p50 and p99, against a plain publish/subscribe round trip (a client publishes and
//      receives its own message through the same broker; goal: <= 2x), and against a plain
//      request/reply through a second client (as many broker trips as the device path).
//      The test broker runs with set_tcp_nodelay (without it, Nagle's algorithm and delayed
//      ACKs add ~40 ms to each command: see core/home/README.md).
//   2. reconnect after a broker restart: from the broker listening again to the client
//      connected and subscribed, and to the first confirmed command. Goal: within 5 s.
// Prints figures; never fails on time.
#include <algorithm>
#include <boost/asio/executor_work_guard.hpp>
#include <boost/asio/io_context.hpp>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "common/log.h"
#include "home/home_service.h"
#include "support/child_process.h"
#include "support/mosquitto_broker.h"

namespace {

using Clock = std::chrono::steady_clock;
using marvin::home::DeviceCommand;
using marvin::home::HomeService;

double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

double percentile(std::vector<double> v, double p) {
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(p * static_cast<double>(v.size())))];
}

// A client on its own thread. As a requester: publishes to `out` and waits for the payload
// to come back on `in`. As a responder (`reply`): publishes every message of `in` to `out`.
class Echo {
 public:
  Echo(const std::string& address, const std::string& id, std::string in, std::string out,
       bool reply = false)
      : work_(io_.get_executor()), out_(std::move(out)) {
    marvin::home::MqttOptions o = marvin::home::broker_from_address(address);
    o.client_id = id;
    client_ = std::make_unique<marvin::home::MqttClient>(
        io_, o,
        [this, reply](const std::string&, std::string_view payload, bool) {
          if (reply) {
            client_->publish(out_, std::string(payload), 0, false);
            return;
          }
          std::lock_guard lock(mutex_);
          last_ = std::string(payload);
          changed_.notify_all();
        },
        [this](bool) { changed_.notify_all(); });
    client_->subscribe(in);
    client_->start();
    thread_ = std::thread([this] { io_.run(); });
    std::unique_lock lock(mutex_);
    changed_.wait_for(lock, std::chrono::seconds(30), [&] { return client_->connected(); });
  }
  ~Echo() {
    client_->stop();
    work_.reset();
    io_.stop();
    thread_.join();
  }
  bool round_trip(const std::string& payload) {
    client_->publish(out_, payload, 0, false);
    std::unique_lock lock(mutex_);
    return changed_.wait_for(lock, std::chrono::seconds(10), [&] { return last_ == payload; });
  }

 private:
  boost::asio::io_context io_;
  boost::asio::executor_work_guard<boost::asio::io_context::executor_type> work_;
  std::unique_ptr<marvin::home::MqttClient> client_;
  std::thread thread_;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::string out_;
  std::string last_;
};

}  // namespace

int main(int argc, char** argv) {
  const int rounds = argc > 1 ? std::max(10, std::atoi(argv[1])) : 400;
  marvin::set_log_level(marvin::LogLevel::kError);
  marvin::test_support::MosquittoBroker broker;
  marvin::test_support::ChildOptions quiet;
  quiet.err = marvin::test_support::ChildStream::kNull;
  marvin::test_support::ChildProcess sim(
      {MARVIN_HOME_SIM, "--broker", broker.address(), "--world", MARVIN_HOME_WORLD}, quiet);
  sim.wait_for_line("ready");

  marvin::home::HomeConfig config;
  config.broker = marvin::home::broker_from_address(broker.address());
  config.site = "bench";
  HomeService home(config);
  home.start();
  if (!home.settle(std::chrono::seconds(30))) {
    std::fprintf(stderr, "bench_home: no broker\n");
    return 1;
  }
  std::string kitchen;
  for (const auto& d : home.devices()) {
    if (d.name == "kitchen light") kitchen = d.id;
  }
  // Baselines: (a) one client publishing and receiving its own message (broker there and
  // back); (b) request/reply through a second client (two trips, as the device path has).
  Echo self(broker.address(), "bench-self", "bench/self", "bench/self");
  Echo responder(broker.address(), "bench-responder", "bench/req", "bench/rep", true);
  Echo requester(broker.address(), "bench-requester", "bench/rep", "bench/req");

  // Interleaved, so all see the same machine load.
  std::vector<double> command_ms, plain_ms, reply_ms;
  int failed = 0;
  for (int i = 0; i < rounds + 20; ++i) {
    auto t0 = Clock::now();
    bool ok = home.set(kitchen, DeviceCommand{i % 2 == 0, {}, {}, {}}).outcome ==
              HomeService::Outcome::kConfirmed;
    double c = ms_since(t0);
    t0 = Clock::now();
    bool pong = self.round_trip(std::to_string(i));
    double p = ms_since(t0);
    t0 = Clock::now();
    bool answered = requester.round_trip(std::to_string(i));
    double q = ms_since(t0);
    if (i < 20) continue;  // warm-up
    if (!ok || !pong || !answered) ++failed;
    command_ms.push_back(c);
    plain_ms.push_back(p);
    reply_ms.push_back(q);
    // The simulator's stdout pipe must not fill up.
    if (i % 50 == 0)
      sim.read_until([](const std::string&) { return false; }, std::chrono::milliseconds(0));
  }
  const double c50 = percentile(command_ms, 0.50), c99 = percentile(command_ms, 0.99);
  const double p50 = percentile(plain_ms, 0.50), p99 = percentile(plain_ms, 0.99);
  std::printf("device command confirmed through the broker (%d rounds, %d failed)\n", rounds,
              failed);
  std::printf("  command -> reported state: p50 %.3f ms  p99 %.3f ms\n", c50, c99);
  const double r50 = percentile(reply_ms, 0.50), r99 = percentile(reply_ms, 0.99);
  std::printf(
      "  plain publish/subscribe round trip (own message back):  p50 %.3f ms  p99 %.3f ms\n", p50,
      p99);
  std::printf(
      "  plain request/reply via a second client (two trips):    p50 %.3f ms  p99 %.3f ms\n", r50,
      r99);
  std::printf("  ratio to the pub/sub round trip (goal <= 2x):  p50 %.2fx  p99 %.2fx\n", c50 / p50,
              c99 / p99);
  std::printf("  ratio to request/reply (same number of trips): p50 %.2fx  p99 %.2fx\n", c50 / r50,
              c99 / r99);

  // Reconnect after a broker restart.
  std::vector<double> connected_ms, working_ms;
  for (int i = 0; i < 5; ++i) {
    broker.kill();
    home.wait_devices([&](const auto&) { return !home.connected(); }, std::chrono::seconds(30));
    broker.restart();  // returns once the broker listens again
    auto t0 = Clock::now();
    home.wait_connected(std::chrono::seconds(30));
    connected_ms.push_back(ms_since(t0));
    // The simulator reconnects too; the first command that is confirmed again.
    while (home.set(kitchen, DeviceCommand{i % 2 == 0, {}, {}, {}}, std::chrono::milliseconds(200))
                   .outcome != HomeService::Outcome::kConfirmed &&
           ms_since(t0) < 30000) {
    }
    working_ms.push_back(ms_since(t0));
  }
  std::printf("reconnect after a broker restart (5 restarts; goal within 5000 ms)\n");
  std::printf("  connected again:          max %.0f ms  median %.0f ms\n",
              *std::max_element(connected_ms.begin(), connected_ms.end()),
              percentile(connected_ms, 0.5));
  std::printf("  first confirmed command:  max %.0f ms  median %.0f ms\n",
              *std::max_element(working_ms.begin(), working_ms.end()), percentile(working_ms, 0.5));
  home.stop();
  return 0;
}
