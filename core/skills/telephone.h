// What the Robot API's phone calls (API 1.3) need from the host: core/app adapts the
// robot's telephone (core/telephony, a supervised baresip) to it; the MockRobot has a
// scripted one. core/skills knows no SIP: numbers, names, a call state and events as JSON.
#pragma once

#include <chrono>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace marvin::skills {

class Telephone {
 public:
  virtual ~Telephone() = default;

  enum class Result { kDone, kInvalid, kUnavailable, kNotFound };
  struct Reply {
    Result result = Result::kDone;
    std::string sentence;  // why, when not kDone ("a call with Anna is going on")
  };

  // Starts calling `number` (a phone number or sip: URI); `name` is whom to name in
  // announcements ("" : the number). The events of this call go to wait_event() from now on.
  virtual Reply dial(const std::string& number, const std::string& name) = 0;
  // Ends the current call or declines the ringing incoming one: false when there is none.
  virtual bool hang_up() = 0;
  // Answers / declines the ringing incoming call: false when nobody is calling.
  virtual bool answer() = 0;
  virtual bool decline() = 0;
  // {"state": "idle"|"calling"|"ringing"|"in_call"|"incoming", "number", "name"}.
  virtual nlohmann::json state() = 0;
  // The next event of the call placed with dial() or call_for_help() (marvin/robot.h,
  // phone_wait_event); nullopt after `timeout`, or as soon as `stop()` is true (checked at
  // least every 50 ms).
  virtual std::optional<nlohmann::json> wait_event(std::chrono::milliseconds timeout,
                                                   const std::function<bool()>& stop) = 0;
  // "Call for help": (name, number) in the order to try, until one answers. Each step is
  // an "emergency_step" event and is logged; the last one is "emergency_done".
  virtual Reply call_for_help(std::vector<std::pair<std::string, std::string>> contacts) = 0;
};

}  // namespace marvin::skills
