// The smart-home service: one MQTT connection to the home's broker (MqttClient on the
// service's own io_context thread), the devices found by discovery, commands confirmed
// from the devices' reported state, and Marvin's own presence on the bus.
//
// Devices: Home Assistant MQTT discovery (<discovery_prefix>/<light|switch|fan>/.../config)
// and Zigbee2MQTT (<base>/bridge/devices, state on <base>/<name>). Malformed discovery
// payloads, state garbage and payloads over kMaxPayloadBytes are ignored with a warning
// naming the topic; nothing stored changes.
//
// Marvin on the bus (README.md has the full topic tree), under marvin/<site>/:
//   availability  "online" / "offline" (retained; "offline" is the last will)
//   status        {"activity": "idle|listening|speaking|acting", "room": "..."} (retained)
//   event         {"event_type": "reminder_fired|reminder_missed|intruder_alert|call",
//                  "text": "...", "time_ms": N}
//   command/say, command/utterance   only with HomeConfig::commands (off by default)
// with Home Assistant discovery configs for them, so Home Assistant shows them unasked.
//
// Thread-safety: every public member may be called from any thread.
#pragma once

#include <boost/asio/io_context.hpp>
#include <chrono>
#include <condition_variable>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "home/config.h"
#include "home/device.h"
#include "home/mqtt_client.h"

namespace marvin::home {

class HomeService {
 public:
  explicit HomeService(HomeConfig config);
  ~HomeService();
  HomeService(const HomeService&) = delete;
  HomeService& operator=(const HomeService&) = delete;

  // Connects (in the background; retried with back-off until stop()).
  void start();
  void stop();

  const HomeConfig& config() const { return config_; }
  bool connected() const;
  bool wait_connected(std::chrono::milliseconds timeout) const;
  int connections() const;  // how often the connection came up

  // The devices known now, sorted by room then name, with the owner's aliases.
  std::vector<Device> devices() const;
  std::optional<Device> device(const std::string& id) const;
  // Waits until `done(devices())` holds; false on timeout.
  bool wait_devices(const std::function<bool(const std::vector<Device>&)>& done,
                    std::chrono::milliseconds timeout) const;
  // Waits until what the broker had retained for this client (discovery, states) has
  // arrived: a message sent to itself on marvin/<site>/sync comes back after it. False when
  // not connected within `timeout`.
  bool settle(std::chrono::milliseconds timeout);
  // The owner's aliases: alias -> device id or name ("the big lamp" -> "living room lamp").
  void set_aliases(std::map<std::string, std::string> aliases);

  // Where the robot is: `room()` asks the hook (navigation) and falls back on the config.
  void set_room_hook(std::function<std::string()> hook);
  std::string room() const;

  enum class Outcome {
    kConfirmed,          // the device reported the asked state
    kNoAnswer,           // no matching report within the answer timeout
    kDeviceOffline,      // the device's availability says offline
    kBrokerUnreachable,  // not connected to the broker (reconnecting meanwhile)
    kUnknownDevice
  };
  struct SetResult {
    Outcome outcome = Outcome::kUnknownDevice;
    DeviceState state;  // the last reported state
  };
  // Sends `command` to device `id` and waits for the device to report it carried out
  // (at most `timeout`, default the config's answer timeout).
  SetResult set(const std::string& id, const DeviceCommand& command,
                std::optional<std::chrono::milliseconds> timeout = std::nullopt);

  // --- Marvin on the bus --------------------------------------------------------------
  void publish_activity(const std::string& activity);  // idle, listening, speaking, acting
  void publish_event(const std::string& event_type, const std::string& text);
  // Receives commands on marvin/<site>/command/<name> ("say", "utterance") when
  // HomeConfig::commands is on; called on the service's thread.
  void on_command(std::function<void(const std::string& name, const std::string& payload)> f);
  std::string topic(const std::string& leaf) const;  // "marvin/<site>/<leaf>"

  // Told after the devices changed: a reported state or availability, a device found or
  // gone, the broker connected or lost. Whoever switched it (a voice command, a skill, the
  // web page, `marvin devices`, another app on the bus): the report is what counts. Called
  // on the service's thread, outside its lock; one listener, empty to stop. After
  // on_devices_changed() returns, the previous listener is not running and not called again.
  void on_devices_changed(std::function<void()> listener);

 private:
  void handle_message(const std::string& topic, std::string_view payload, bool retained);
  void handle_connection(bool up);
  void add_devices(std::vector<Device> found, const std::string& source_key);  // mutex_ held
  void remove_devices_from(const std::string& source_key);                     // mutex_ held
  void publish_presence();
  std::string status_json() const;
  void tell_devices_changed();  // changed_.notify_all(), then the listener

  HomeConfig config_;
  boost::asio::io_context io_;
  std::unique_ptr<MqttClient> client_;
  std::thread thread_;

  mutable std::mutex mutex_;
  mutable std::condition_variable changed_;
  std::map<std::string, Device> devices_;                   // by id
  std::map<std::string, std::set<std::string>> sources_;    // discovery topic -> device ids
  std::map<std::string, std::vector<std::string>> routes_;  // state topic -> device ids
  std::set<std::string> subscribed_;
  std::map<std::string, std::string> aliases_;
  std::function<std::string()> room_hook_;
  std::string activity_ = "idle";
  std::function<void(const std::string&, const std::string&)> command_handler_;
  bool up_ = false;
  std::string last_sync_;  // mutex_
  std::function<void()> devices_listener_;
  std::mutex devices_listener_mutex_;  // held while the listener runs
};

const char* to_string(HomeService::Outcome outcome);

}  // namespace marvin::home
