// marvin-home-sim: devices that behave like Zigbee2MQTT's, for `scripts/sim` and the tests.
//
// It reads only the "devices" array of a world file ([{"name", "type":
// light|switch|fan|thermostat, "room", "dimmable"?, "temperature"? (a thermostat's room, °C)}])
// and, on the broker, publishes what Zigbee2MQTT would (retained):
// <base>/bridge/devices (friendly names "<room>/<name>"), each device's state on
// <base>/<friendly name> and "online" on <base>/<friendly name>/availability. It carries out
// <base>/<friendly name>/set ({"state": ON|OFF|TOGGLE, "brightness": 0..254, "color_temp"})
// and answers <base>/<friendly name>/get with the state. A thermostat is a Zigbee2MQTT
// "climate" device: {"occupied_heating_setpoint": 5..30, "system_mode": "heat"|"off",
// "local_temperature"} (the room's temperature stays what the world file says). Everything is published again after
// a reconnect (a broker restarted without persistence has lost the retained messages).
//
// Each state change is also printed on stdout, one line: `kitchen light: ON 254`, after
// `ready` once everything was published, so a test or a person watches the home.
#pragma once

#include <filesystem>
#include <map>
#include <mutex>
#include <set>
#include <string>
#include <vector>

#include "home/mqtt_client.h"

namespace marvin::home {

struct SimDevice {
  std::string name;
  std::string type;  // light, switch, fan, thermostat
  std::string room;
  bool dimmable = false;
  bool on = false;
  int brightness = 254;
  int color_temp = 300;
  double setpoint = 20.0;     // thermostats
  double temperature = 19.5;  // thermostats: the room's, as measured
};

// The devices of a world file. Throws std::runtime_error naming the file and the field.
std::vector<SimDevice> load_world_devices(const std::filesystem::path& world);

class HomeSimulator {
 public:
  // `mute`: names of devices that take commands but never report (a device out of range).
  HomeSimulator(std::vector<SimDevice> devices, std::string base, std::set<std::string> mute);

  std::string friendly_name(const SimDevice& d) const { return d.room + "/" + d.name; }
  // What to publish after (re)connecting: (topic, payload) pairs, all retained.
  std::vector<std::pair<std::string, std::string>> announce() const;
  // Handles one message; returns what to publish (retained) and the stdout lines.
  std::vector<std::pair<std::string, std::string>> handle(const std::string& topic,
                                                          std::string_view payload,
                                                          std::vector<std::string>* lines);

 private:
  std::string state_json(const SimDevice& d) const;
  std::string devices_json() const;

  std::vector<SimDevice> devices_;
  std::string base_;
  std::set<std::string> mute_;
};

}  // namespace marvin::home
