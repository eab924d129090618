// What the smart-home tests share: a real broker, the simulator as a child process, a raw
// MQTT peer (to publish discovery, garbage, or play a Home Assistant device) and a capture
// of the log.
#pragma once

#include <doctest/doctest.h>

#include <boost/asio/io_context.hpp>
#include <boost/asio/executor_work_guard.hpp>

#include <condition_variable>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "common/log.h"
#include "home/home_service.h"
#include "home/mqtt_client.h"
#include "support/child_process.h"
#include "support/mosquitto_broker.h"

namespace marvin::home::testing {

using namespace std::chrono_literals;
using test_support::ChildProcess;
using test_support::MosquittoBroker;

inline constexpr auto kWait = std::chrono::milliseconds(test_support::kGenerousTimeout);

// A plain MQTT client on its own thread: publishes, and records what it receives.
class Peer {
 public:
  explicit Peer(const MosquittoBroker& broker, std::string id = "test-peer")
      : work_(io_.get_executor()) {
    MqttOptions o = broker_from_address(broker.address());
    o.client_id = std::move(id);
    client_ = std::make_unique<MqttClient>(
        io_, o,
        [this](const std::string& t, std::string_view p, bool) {
          std::function<void(const std::string&, const std::string&)> h;
          {
            std::lock_guard lock(mutex_);
            received_.emplace_back(t, std::string(p));
            h = handler_;
          }
          changed_.notify_all();
          if (h) h(t, std::string(p));
        },
        [this](bool) { changed_.notify_all(); });
    client_->start();
    thread_ = std::thread([this] { io_.run(); });
  }
  ~Peer() {
    client_->stop();
    work_.reset();
    io_.stop();
    thread_.join();
  }
  void subscribe(const std::string& t) { client_->subscribe(t); }
  void on_message(std::function<void(const std::string&, const std::string&)> h) {
    std::lock_guard lock(mutex_);
    handler_ = std::move(h);
  }
  bool wait_connected() {
    std::unique_lock lock(mutex_);
    return changed_.wait_for(lock, kWait, [&] { return client_->connected(); });
  }
  bool publish(const std::string& t, const std::string& p, bool retain = false) {
    // QoS 1 so a publish is on the broker before the next one.
    return client_->publish(t, p, 1, retain);
  }
  MqttClient& client() { return *client_; }
  // Waits for a message on `topic` whose payload contains `part`; its payload.
  std::optional<std::string> wait_message(const std::string& topic, const std::string& part = "") {
    std::unique_lock lock(mutex_);
    std::optional<std::string> found;
    changed_.wait_for(lock, kWait, [&] {
      for (const auto& [t, p] : received_) {
        if (t == topic && p.find(part) != std::string::npos) {
          found = p;
          return true;
        }
      }
      return false;
    });
    return found;
  }

 private:
  boost::asio::io_context io_;
  boost::asio::executor_work_guard<boost::asio::io_context::executor_type> work_;
  std::unique_ptr<MqttClient> client_;
  std::thread thread_;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::vector<std::pair<std::string, std::string>> received_;
  std::function<void(const std::string&, const std::string&)> handler_;
};

// Records warnings and errors of marvin::log while it lives.
class LogCapture {
 public:
  LogCapture() {
    previous_ = set_log_sink([this](LogLevel level, std::string_view component,
                                    std::string_view message) {
      if (level < LogLevel::kWarning) return;
      {
        std::lock_guard lock(mutex_);
        lines_.push_back(std::string(component) + ": " + std::string(message));
      }
      changed_.notify_all();
    });
  }
  ~LogCapture() { set_log_sink(previous_); }
  // Waits for a line containing every part.
  bool wait_for(const std::vector<std::string>& parts) {
    std::unique_lock lock(mutex_);
    return changed_.wait_for(lock, kWait, [&] {
      for (const std::string& line : lines_) {
        bool all = true;
        for (const std::string& p : parts) all = all && line.find(p) != std::string::npos;
        if (all) return true;
      }
      return false;
    });
  }
  std::vector<std::string> lines() {
    std::lock_guard lock(mutex_);
    return lines_;
  }

 private:
  LogSink previous_;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::vector<std::string> lines_;
};

inline HomeConfig config_for(const MosquittoBroker& broker) {
  HomeConfig c;
  c.broker = broker_from_address(broker.address());
  c.site = "test";
  c.answer_timeout = 5s;  // generous for a loaded machine; a mute device is asked with less
  return c;
}

// marvin-home-sim on the default world, ready when it returns.
inline ChildProcess start_sim(const MosquittoBroker& broker, std::vector<std::string> extra = {}) {
  std::vector<std::string> argv{MARVIN_HOME_SIM, "--broker", broker.address(), "--world",
                                MARVIN_HOME_WORLD};
  argv.insert(argv.end(), extra.begin(), extra.end());
  test_support::ChildOptions o;
  o.err = test_support::ChildStream::kNull;
  ChildProcess sim(argv, o);
  sim.wait_for_line("ready");
  return sim;
}

inline bool has_device(const std::vector<Device>& devices, const std::string& name) {
  for (const Device& d : devices) {
    if (d.name == name) return true;
  }
  return false;
}

inline std::string id_of(HomeService& home, const std::string& name) {
  for (const Device& d : home.devices()) {
    if (d.name == name) return d.id;
  }
  FAIL("no device named " << name);
  return "";
}

}  // namespace marvin::home::testing
