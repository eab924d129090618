// A smart-home device as Marvin knows it: found through Home Assistant MQTT discovery or
// Zigbee2MQTT's device list, never configured by hand. How to command it and how to read
// its state are kept with it, so the service can speak either dialect.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace marvin::home {

enum class DeviceType { kLight, kSwitch, kFan, kThermostat };
const char* type_name(DeviceType type);  // "light", "switch", "fan", "thermostat"

// What the device reported last (not what was asked of it).
struct DeviceState {
  std::optional<bool> on;
  std::optional<int> brightness_pct;  // 0..100, dimmable lights only
  std::optional<int> color_temp;      // mireds, as reported
  // Thermostats: "on" is heating (any mode but off); the temperature asked for and the one
  // the thermostat measures, in degrees Celsius.
  std::optional<double> target_c;
  std::optional<double> current_c;
  bool available = true;              // false while its availability topic says offline
  std::uint64_t reports = 0;          // bumped on every state report
};

// How to talk to one device.
struct DeviceProtocol {
  enum class Dialect {
    kZigbee2Mqtt,  // JSON on <base>/<name>, commands on <base>/<name>/set
    kHaJson,       // HA light, schema "json": JSON state and commands
    kHaDefault     // HA default schema: plain payloads (ON/OFF), separate brightness topics
  };
  Dialect dialect = Dialect::kZigbee2Mqtt;
  std::string command_topic;
  std::string state_topic;
  std::string availability_topic;
  std::string payload_on = "ON", payload_off = "OFF";  // kHaDefault commands
  std::string state_on = "ON", state_off = "OFF";      // kHaDefault state
  std::string brightness_command_topic;                // kHaDefault
  std::string brightness_state_topic;                  // kHaDefault
  int brightness_max = 255;                            // the device's full brightness
  // Thermostats. Zigbee2MQTT: the set point's property ("occupied_heating_setpoint" or a
  // radiator valve's "current_heating_setpoint"). Home Assistant (plain payloads): the set
  // point's and the measured temperature's topics; `command_topic`/`state_topic` carry the
  // mode ("heat", "off").
  std::string setpoint_property;
  std::string setpoint_command_topic, setpoint_state_topic, current_temperature_topic;
  std::string heat_mode = "heat";     // the mode that means "on"
  double min_c = 5.0, max_c = 30.0;   // the set point's range
  std::string available_payload = "online", unavailable_payload = "offline";
};

struct Device {
  std::string id;    // stable: "z2m:<friendly name>" or "ha:<component>/<object id>"
  std::string name;  // as the user says it, lower case: "kitchen light"
  std::string room;  // lower case, may be empty
  DeviceType type = DeviceType::kLight;
  bool dimmable = false;
  bool color_temp = false;
  std::vector<std::string> aliases;  // from the owner ("the big lamp"), lower case
  DeviceProtocol protocol;
  DeviceState state;
};

// A change asked of a device. Brightness is absolute (a relative "brighter" is computed
// from the reported state first), so a command delivered twice does no more than once.
struct DeviceCommand {
  std::optional<bool> on;
  std::optional<int> brightness_pct;  // 0..100
  std::optional<int> color_temp;      // mireds
  std::optional<double> target_c;     // thermostats: the set point, within min_c..max_c
};

// The messages that carry `command` to `device`: (topic, payload) pairs.
std::vector<std::pair<std::string, std::string>> command_messages(const Device& device,
                                                                  const DeviceCommand& command);
// True when `state` shows `command` carried out.
bool state_matches(const DeviceState& state, const DeviceCommand& command);

}  // namespace marvin::home
