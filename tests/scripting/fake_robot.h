// A tiny in-memory Robot API for the scripting tests: records what a skill says and does,
// answers questions from a queue, keeps storage in a map, checks permissions like the host.
// (The SDK's MockRobot serves the same purpose with the host's real code; this one also
// exposes the skill's log, which the output-flood tests need.)
#pragma once

#include <cstdint>
#include <cstring>
#include <deque>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <marvin/robot.h>

namespace marvin::scripting::testing {

struct FakeRobot {
  std::string skill_id = "test";
  std::set<std::string> permissions;
  std::vector<std::string> said, asked, actions, log;
  std::deque<std::string> answers;
  std::map<std::string, std::string> storage;
  std::vector<std::string> reminders;
  std::int64_t now_ms = 1767603600000;  // 2026-01-05T09:00:00Z
  std::int64_t ask_thinking_ms = 0;      // how far the fake clock moves while the user thinks
  std::int64_t* clock_ms = nullptr;      // the test's fake steady clock, moved by ask()
  bool cancelled = false;
  std::string last_error;
  bool in_call = false;
  std::vector<std::string> phone_events;
  std::string room = "hall";  // where_am_i; go_to("kitchen") moves here, go_to("garden") fails

  marvin_host* host() { return reinterpret_cast<marvin_host*>(this); }
  static FakeRobot& of(marvin_host* host) { return *reinterpret_cast<FakeRobot*>(host); }

  std::size_t log_bytes() const {
    std::size_t total = 0;
    for (const auto& line : log) total += line.size();
    return total;
  }

  static marvin_status write(marvin_text_out* out, const std::string& text) {
    out->length = text.size();
    if (out->capacity < text.size() + 1) return MARVIN_ERR_TRUNCATED;
    std::memcpy(out->data, text.c_str(), text.size() + 1);
    return MARVIN_OK;
  }

  marvin_status deny_unless(const char* permission) {
    if (permissions.count(permission) != 0) return MARVIN_OK;
    last_error = std::string("permission '") + permission + "' is not granted to skill '" +
                 skill_id + "'";
    return MARVIN_ERR_PERMISSION;
  }

  static const marvin_robot_api* api() {
    static const marvin_robot_api table = [] {
      marvin_robot_api t{};
      t.struct_size = sizeof(marvin_robot_api);
      t.major = MARVIN_ROBOT_API_MAJOR;
      t.minor = MARVIN_ROBOT_API_MINOR;
      t.last_error = [](marvin_host* h) { return of(h).last_error.c_str(); };
      t.say = [](marvin_host* h, const char* text) {
        of(h).said.emplace_back(text);
        return MARVIN_OK;
      };
      t.ask = [](marvin_host* h, const char* question, marvin_text_out* answer) {
        FakeRobot& r = of(h);
        r.said.emplace_back(question);
        r.asked.emplace_back(question);
        if (r.clock_ms != nullptr) *r.clock_ms += r.ask_thinking_ms;
        if (r.answers.empty()) {
          r.last_error = "the user did not answer";
          return MARVIN_ERR_CANCELLED;
        }
        const std::string text = r.answers.front();
        r.answers.pop_front();
        return write(answer, text);
      };
      t.set_light = [](marvin_host* h, marvin_light light) {
        FakeRobot& r = of(h);
        if (marvin_status s = r.deny_unless("light"); s != MARVIN_OK) return s;
        r.actions.push_back("light " + std::to_string(static_cast<int>(light)));
        return MARVIN_OK;
      };
      t.move = [](marvin_host* h, marvin_direction d, std::uint8_t speed, std::uint32_t ms) {
        FakeRobot& r = of(h);
        if (marvin_status s = r.deny_unless("motion"); s != MARVIN_OK) return s;
        r.actions.push_back("move " + std::to_string(static_cast<int>(d)) + " " +
                            std::to_string(speed) + " " + std::to_string(ms));
        return MARVIN_OK;
      };
      t.stop = [](marvin_host* h) {
        FakeRobot& r = of(h);
        if (marvin_status s = r.deny_unless("motion"); s != MARVIN_OK) return s;
        r.actions.push_back("stop");
        return MARVIN_OK;
      };
      t.now = [](marvin_host* h, std::int64_t* ms) {
        *ms = of(h).now_ms;
        return MARVIN_OK;
      };
      t.schedule_add = [](marvin_host* h, const char* json, marvin_text_out* out) {
        FakeRobot& r = of(h);
        if (marvin_status s = r.deny_unless("schedule"); s != MARVIN_OK) return s;
        r.reminders.emplace_back(json);
        std::string created(json);
        created.insert(1, "\"id\":" + std::to_string(r.reminders.size()) + ",");
        return write(out, created);
      };
      t.storage_get = [](marvin_host* h, const char* key, marvin_text_out* out) {
        FakeRobot& r = of(h);
        if (marvin_status s = r.deny_unless("storage"); s != MARVIN_OK) return s;
        auto it = r.storage.find(key);
        if (it == r.storage.end()) return MARVIN_ERR_NOT_FOUND;
        return write(out, it->second);
      };
      t.storage_set = [](marvin_host* h, const char* key, const char* value, size_t length) {
        FakeRobot& r = of(h);
        if (marvin_status s = r.deny_unless("storage"); s != MARVIN_OK) return s;
        r.storage[key] = std::string(value, length);
        return MARVIN_OK;
      };
      t.storage_remove = [](marvin_host* h, const char* key) {
        FakeRobot& r = of(h);
        if (marvin_status s = r.deny_unless("storage"); s != MARVIN_OK) return s;
        return r.storage.erase(key) != 0 ? MARVIN_OK : MARVIN_ERR_NOT_FOUND;
      };
      t.log = [](marvin_host* h, marvin_log_level, const char* message) {
        of(h).log.emplace_back(message);
        return MARVIN_OK;
      };
      t.is_cancelled = [](marvin_host* h) { return of(h).cancelled ? 1 : 0; };
      t.go_to = [](marvin_host* h, const char* place) {
        FakeRobot& r = of(h);
        if (marvin_status s = r.deny_unless("motion"); s != MARVIN_OK) return s;
        r.actions.push_back(std::string("go_to ") + place);
        if (std::string(place) == "garden") {
          r.last_error = "the garden door is blocked";
          return MARVIN_ERR_UNAVAILABLE;
        }
        r.room = place;
        return MARVIN_OK;
      };
      // Guiding (API 1.4): two events on the way (a step down, then an obstacle), then
      // there, unless on_event stops it.
      t.guide_to = [](marvin_host* h, const char* place, uint32_t speed,
                      marvin_guide_event_fn on_event, void* user) {
        FakeRobot& r = of(h);
        if (marvin_status s = r.deny_unless("motion"); s != MARVIN_OK) return s;
        r.actions.push_back(std::string("guide_to ") + place + " speed=" + std::to_string(speed));
        for (const char* e : {R"({"event":"step_down","distance_m":0.43,"kind":"step"})",
                              R"({"event":"obstacle","distance_m":1.0,"kind":"low"})"}) {
          if (on_event && on_event(user, e) != 0) {
            r.last_error = "the skill stopped the trip";
            return MARVIN_ERR_CANCELLED;
          }
        }
        r.room = place;
        return MARVIN_OK;
      };
      t.where_am_i = [](marvin_host* h, marvin_text_out* out) {
        FakeRobot& r = of(h);
        if (marvin_status s = r.deny_unless("sensors"); s != MARVIN_OK) return s;
        if (r.room.empty()) return MARVIN_ERR_NOT_FOUND;
        return write(out, r.room);
      };
      // Smart home: one lamp that answers, a fan that never does.
      t.smarthome_devices = [](marvin_host* h, marvin_text_out* out) {
        FakeRobot& r = of(h);
        if (marvin_status s = r.deny_unless("smarthome")) return s;
        return write(out, R"({"connected":true,"room":"hall","devices":[)"
                          R"({"id":"lamp","name":"lamp","room":"hall","type":"light"}]})");
      };
      t.smarthome_set = [](marvin_host* h, const char* device, const char* state) {
        FakeRobot& r = of(h);
        if (marvin_status s = r.deny_unless("smarthome")) return s;
        r.actions.push_back(std::string("home.set ") + device + " " + state);
        if (std::string(device) == "fan") {
          r.last_error = "the fan did not report the new state within 3000 ms";
          return MARVIN_ERR_UNAVAILABLE;
        }
        return MARVIN_OK;
      };
      // Phone: every call is answered at once; "0000" cannot be called.
      t.phone_resolve = [](marvin_host* h, const char* who, marvin_text_out* out) {
        FakeRobot& r = of(h);
        if (marvin_status s = r.deny_unless("phone")) return s;
        return write(out, std::string(R"({"kind":"contact","name":")") + who +
                              R"(","number":"sip:anna@127.0.0.1","say":"Call )" + who + "?\"}");
      };
      t.phone_dial = [](marvin_host* h, const char* number, const char* name) {
        FakeRobot& r = of(h);
        if (marvin_status s = r.deny_unless("phone")) return s;
        if (std::string(number) == "0000") {
          r.last_error = "number: \"0000\" cannot be dialled";
          return MARVIN_ERR_INVALID;
        }
        r.actions.push_back(std::string("phone.dial ") + number + " " + name);
        r.in_call = true;
        r.phone_events = {R"({"event":"ringing"})", R"({"event":"answered"})"};
        return MARVIN_OK;
      };
      t.phone_wait_event = [](marvin_host* h, uint32_t, marvin_text_out* out) {
        FakeRobot& r = of(h);
        if (marvin_status s = r.deny_unless("phone")) return s;
        if (r.phone_events.empty()) return MARVIN_ERR_NOT_FOUND;
        std::string e = r.phone_events.front();
        r.phone_events.erase(r.phone_events.begin());
        return write(out, e);
      };
      t.phone_hang_up = [](marvin_host* h) {
        FakeRobot& r = of(h);
        if (marvin_status s = r.deny_unless("phone")) return s;
        if (!r.in_call) {
          r.last_error = "there is no call to hang up";
          return MARVIN_ERR_NOT_FOUND;
        }
        r.in_call = false;
        r.actions.push_back("phone.hang_up");
        return MARVIN_OK;
      };
      return t;
    }();
    return &table;
  }
};

}  // namespace marvin::scripting::testing
