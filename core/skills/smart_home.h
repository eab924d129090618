// What the Robot API's smart-home calls need from the host (core/app adapts the home
// service, core/home, to it; the MockRobot has an in-memory one). core/skills knows no
// MQTT: only devices as JSON and a "set and confirm".
#pragma once

#include <functional>
#include <nlohmann/json.hpp>
#include <string>

namespace marvin::skills {

class SmartHome {
 public:
  virtual ~SmartHome() = default;

  // {"connected": bool, "room": "<where the robot is>", "devices": [{"id", "name", "room",
  //  "type": "light"|"switch"|"fan", "dimmable", "aliases": [...], "available",
  //  "on": bool|null, "brightness": 0..100|null}]} (the format of marvin/README.md).
  virtual nlohmann::json devices() = 0;

  enum class Result { kDone, kNotFound, kInvalid, kUnavailable };
  struct Reply {
    Result result = Result::kDone;
    std::string sentence;   // why, when not kDone ("the broker is unreachable", ...)
    nlohmann::json device;  // the device as in devices(), with its reported state
  };
  // Carries out `state` ({"on": bool, "brightness": 0..100}, either or both) on the device
  // `device` (an id, or a name or alias of exactly one device) and waits for the device to
  // report it: kDone only then.
  virtual Reply set(const std::string& device, const nlohmann::json& state) = 0;

  // Told (on any thread) after devices() changed, whoever switched a device: the web page's
  // open Devices pages refresh. One listener, empty to stop; after the call returns the
  // previous one is not running. A smart home that cannot tell ignores it.
  virtual void on_change(std::function<void()> listener) { (void)listener; }
};

}  // namespace marvin::skills
