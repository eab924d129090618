// Reading what devices announce about themselves (Home Assistant MQTT discovery,
// Zigbee2MQTT's bridge/devices) and what they report (state, availability).
//
// Everything here is pure: payload text in, devices or state out. A payload that is not
// what the dialect promises throws DiscoveryError with a sentence naming what is wrong;
// the service logs it with the topic and carries on.
#pragma once

#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "home/device.h"

namespace marvin::home {

class DiscoveryError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Payloads larger than this are ignored unread (a home's device list is far smaller).
inline constexpr std::size_t kMaxPayloadBytes = 256 * 1024;

// The component and object id of a discovery topic
// homeassistant/<component>/[<node_id>/]<object_id>/config, for light, switch and fan;
// false for other topics or components.
bool parse_ha_config_topic(std::string_view prefix, std::string_view topic, std::string* component,
                           std::string* object_id);
// The device a Home Assistant discovery config describes. An empty payload (a removed
// device) is not an error: it returns a device with an empty name.
Device parse_ha_config(std::string_view component, std::string_view object_id,
                       std::string_view payload);

// The lights, switches and fans in Zigbee2MQTT's bridge/devices list (the coordinator and
// sensors are left out). Room: the part of the friendly name before its last "/"
// ("bedroom/bedroom light"), else a "room: <name>" line in the device's description.
std::vector<Device> parse_z2m_devices(std::string_view base_topic, std::string_view payload);

// Applies a state report to `state`; false if the payload is not a state report.
bool apply_state(const Device& device, std::string_view topic, std::string_view payload,
                 DeviceState* state);
// Applies an availability report; false if it is neither the online nor the offline payload.
bool apply_availability(const Device& device, std::string_view payload, DeviceState* state);

std::string lower(std::string_view text);
// A temperature as a thermostat is sent it and a person reads it: "21", "21.5", "-2".
std::string celsius_text(double value);

}  // namespace marvin::home
