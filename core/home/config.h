// The smart-home settings in Marvin's config file (home.json), for example:
//
//   {
//     "broker": {"host": "homeserver.local", "port": 8883, "tls": true,
//                "ca_file": "/etc/ssl/certs/home-ca.pem",
//                "user": "marvin", "password_file": "/home/anna/.config/marvin/mqtt-password"},
//     "site": "flat",                  // marvin/<site>/... on the bus
//     "room": "living room",           // where the robot is when navigation does not say
//     "discovery_prefix": "homeassistant",
//     "zigbee2mqtt_base": "zigbee2mqtt",
//     "commands": false,               // accept commands on marvin/<site>/command/...
//     "answer_timeout_ms": 3000        // how long a device has to report its new state
//   }
//
// Every key is optional. The password lives in its own file, which must be readable only
// by its owner (mode 0600 or stricter): anything else is refused with a message naming the
// file and its mode, so a password is never used from a file other users can read.
#pragma once

#include <chrono>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>

#include "home/mqtt_client.h"

namespace marvin::home {

class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct HomeConfig {
  MqttOptions broker;
  std::string site = "home";
  std::string room = "living room";
  std::string discovery_prefix = "homeassistant";
  std::string zigbee2mqtt_base = "zigbee2mqtt";
  bool commands = false;
  std::chrono::milliseconds answer_timeout{3000};
};

// Reads `path`. Throws ConfigError naming the file and the field that is wrong.
HomeConfig load_home_config(const std::filesystem::path& path);
// The password in `path` (first line), after checking it is a regular file owned by this
// user and readable by nobody else. Throws ConfigError otherwise.
std::string read_password_file(const std::filesystem::path& path);
// $MARVIN_HOME_CONFIG, else $XDG_CONFIG_HOME/marvin/home.json, else
// ~/.config/marvin/home.json; nullopt without a home directory.
std::optional<std::filesystem::path> default_home_config_path();
// "HOST:PORT" (or "HOST", port 1883) as broker options without authentication.
MqttOptions broker_from_address(const std::string& address);

}  // namespace marvin::home
