// Marvin SDK, C++ layer: write a native skill as one class and one macro.
//
//   #include <marvin/skill.hpp>
//
//   class Dice : public marvin::Skill {
//    public:
//     using marvin::Skill::Skill;
//     void handle(const marvin::Request& request) override {
//       int count = request.slots.value("count", 1);
//       robot().say("You rolled " + std::to_string(...) + ".");
//     }
//   };
//   MARVIN_SKILL(Dice, "dice")   // the id must equal "id" in skill.json
//
// Life cycle: the host constructs one instance of the class when it loads the skill (the
// constructor gets the Robot; throwing from it refuses the load with your message), calls
// handle() once per recognised request, never on two threads at once, and destroys the
// instance before unloading the library.
//
// Errors: handle() reports failure by throwing. A marvin::Error carries its status (a
// Robot API call that failed throws one, e.g. MARVIN_ERR_CANCELLED when the user said
// "stop" during ask() or move()); any other std::exception becomes MARVIN_ERR_INTERNAL with
// its what(). Nothing escapes across the C ABI: the macro's functions catch everything.
// The host logs the message and apologises to the user; it never speaks your message.
//
// Header-only; needs C++17 and nlohmann/json (slots and the JSON formats of schedules and
// contacts, see README.md next to this file).
#ifndef MARVIN_SKILL_HPP_
#define MARVIN_SKILL_HPP_

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <exception>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "marvin/skill.h"

namespace marvin {

// A failed call, with its status. what() is the host's (or the skill's) sentence.
class Error : public std::runtime_error {
 public:
  Error(marvin_status status, const std::string& message)
      : std::runtime_error(message), status_(status) {}
  marvin_status status() const { return status_; }

 private:
  marvin_status status_;
};

// One recognised request.
struct Request {
  std::string intent;     // the intent's name in skill.json
  nlohmann::json slots;   // {"slot": value}: numbers, seconds, {"at": ...}, names, text
  std::string utterance;  // what the user said, normalised
};

// The robot, as a skill sees it: the Robot API table of marvin/robot.h with C++ types.
// Every call throws marvin::Error on failure (permission, cancelled, unavailable, ...).
// Use it only from the thread that called your handle(). Cheap to copy.
class Robot {
 public:
  Robot(const marvin_robot_api* api, marvin_host* host) : api_(api), host_(host) {}

  const marvin_robot_api* api() const { return api_; }
  marvin_host* host() const { return host_; }

  void say(std::string_view text) {
    check(fn(&marvin_robot_api::say, "say")(host_, str(text).c_str()));
  }
  // Speaks `question` and returns the user's answer. Throws Error(MARVIN_ERR_CANCELLED)
  // if the user said "stop" instead.
  std::string ask(std::string_view question) {
    std::string q = str(question);
    auto call = fn(&marvin_robot_api::ask, "ask");
    return text([&](marvin_text_out* out) { return call(host_, q.c_str(), out); });
  }
  void set_light(marvin_light light) {
    check(fn(&marvin_robot_api::set_light, "set_light")(host_, light));
  }
  // Returns once the motion has run its course; throws Error(MARVIN_ERR_CANCELLED) if the
  // user said "stop" (the base is stopped then).
  void move(marvin_direction direction, std::uint8_t speed, std::chrono::milliseconds duration) {
    check(fn(&marvin_robot_api::move, "move")(host_, direction, speed,
                                              static_cast<std::uint32_t>(duration.count())));
  }
  void stop() { check(fn(&marvin_robot_api::stop, "stop")(host_)); }
  void tilt_head(int degrees) {
    check(fn(&marvin_robot_api::tilt_head, "tilt_head")(host_, static_cast<std::int32_t>(degrees)));
  }
  std::vector<marvin_scan_point> obstacle_scan() {
    std::vector<marvin_scan_point> points(256);
    std::size_t count = 0;
    auto call = fn(&marvin_robot_api::obstacle_scan, "obstacle_scan");
    marvin_status s = call(host_, points.data(), points.size(), &count);
    if (s != MARVIN_ERR_TRUNCATED) check(s);
    points.resize(count);
    return points;
  }
  // Milliseconds since the Unix epoch, UTC, from the host's clock.
  std::int64_t now_ms() {
    std::int64_t ms = 0;
    check(fn(&marvin_robot_api::now, "now")(host_, &ms));
    return ms;
  }
  // The owner's IANA time zone, e.g. "Europe/Berlin".
  std::string time_zone() {
    auto call = fn(&marvin_robot_api::time_zone, "time_zone");
    return text([&](marvin_text_out* out) { return call(host_, out); });
  }

  // Schedules, contacts and people: JSON in the formats of README.md.
  nlohmann::json schedule_add(const nlohmann::json& reminder) {
    std::string in = reminder.dump();
    auto call = fn(&marvin_robot_api::schedule_add, "schedule_add");
    return nlohmann::json::parse(
        text([&](marvin_text_out* out) { return call(host_, in.c_str(), out); }));
  }
  nlohmann::json schedule_list(std::int64_t from_unix_ms, std::int64_t to_unix_ms) {
    auto call = fn(&marvin_robot_api::schedule_list, "schedule_list");
    return nlohmann::json::parse(
        text([&](marvin_text_out* out) { return call(host_, from_unix_ms, to_unix_ms, out); }));
  }
  void schedule_remove(std::int64_t reminder_id) {
    check(fn(&marvin_robot_api::schedule_remove, "schedule_remove")(host_, reminder_id));
  }
  // Robot API 1.1 (Error(MARVIN_ERR_UNAVAILABLE) on an older host).
  void schedule_snooze(std::int64_t reminder_id, std::int64_t until_unix_ms) {
    check(fn(&marvin_robot_api::schedule_snooze, "schedule_snooze")(host_, reminder_id,
                                                                    until_unix_ms));
  }
  void schedule_done(std::int64_t reminder_id) {
    check(fn(&marvin_robot_api::schedule_done, "schedule_done")(host_, reminder_id));
  }
  // The reminder announced most recently, or nullopt if none fired since the host started.
  std::optional<nlohmann::json> schedule_last_fired() {
    auto call = fn(&marvin_robot_api::schedule_last_fired, "schedule_last_fired");
    try {
      return nlohmann::json::parse(text([&](marvin_text_out* out) { return call(host_, out); }));
    } catch (const Error& e) {
      if (e.status() == MARVIN_ERR_NOT_FOUND) return std::nullopt;
      throw;
    }
  }
  // Going places (API 1.2). go_to returns once there; throws Error(NOT_FOUND) for a place
  // the map does not know, Error(UNAVAILABLE) when the robot gave up (what() says why:
  // "the kitchen door is blocked"), Error(CANCELLED) on "stop".
  void go_to(std::string_view place) {
    check(fn(&marvin_robot_api::go_to, "go_to")(host_, str(place).c_str()));
  }
  void go_stop() { check(fn(&marvin_robot_api::go_stop, "go_stop")(host_)); }
  // Guiding (API 1.4): go_to at `speed_percent` of the normal speed (0: 50), calling
  // `on_event` with each thing worth telling on the way (its JSON: marvin/robot.h,
  // marvin_guide_event_fn); on_event returns false to stop the trip (then this throws
  // Error(CANCELLED)). An exception from on_event stops the trip and is rethrown here.
  void guide_to(std::string_view place, std::uint32_t speed_percent,
                const std::function<bool(const nlohmann::json&)>& on_event) {
    struct Guided {
      const std::function<bool(const nlohmann::json&)>* on_event;
      std::exception_ptr error;
    } guided{&on_event, nullptr};
    marvin_guide_event_fn tell = [](void* user, const char* event_json) -> int {
      auto* g = static_cast<Guided*>(user);
      try {
        return (*g->on_event)(nlohmann::json::parse(event_json)) ? 0 : 1;
      } catch (...) {
        g->error = std::current_exception();
        return 1;
      }
    };
    const marvin_status status = fn(&marvin_robot_api::guide_to, "guide_to")(
        host_, str(place).c_str(), speed_percent, on_event ? tell : nullptr, &guided);
    if (guided.error) std::rethrow_exception(guided.error);
    check(status);
  }
  // The room the robot is in, or nullopt between rooms.
  std::optional<std::string> where_am_i() {
    auto call = fn(&marvin_robot_api::where_am_i, "where_am_i");
    try {
      return text([&](marvin_text_out* out) { return call(host_, out); });
    } catch (const Error& e) {
      if (e.status() == MARVIN_ERR_NOT_FOUND) return std::nullopt;
      throw;
    }
  }
  // Smart home (Robot API 1.2). Sets a device ("on", "off" or {"on", "brightness"}) and
  // returns once the device reported it; throws Error(MARVIN_ERR_UNAVAILABLE) when the
  // broker is unreachable or the device did not answer (what() says which).
  void smarthome_set(std::string_view device, const nlohmann::json& state) {
    std::string d = str(device);
    std::string s = state.is_string() ? state.get<std::string>() : state.dump();
    check(fn(&marvin_robot_api::smarthome_set, "smarthome_set")(host_, d.c_str(), s.c_str()));
  }
  // {"connected", "room", "devices": [...]} (see marvin/robot.h).
  nlohmann::json smarthome_devices() {
    auto call = fn(&marvin_robot_api::smarthome_devices, "smarthome_devices");
    return nlohmann::json::parse(text([&](marvin_text_out* out) { return call(host_, out); }));
  }
  // Phone calls (Robot API 1.3; see marvin/robot.h). Who "my daughter" / "Anna" /
  // "0123 456 789" means: {"kind", "name", "number", "candidates", "say"}.
  nlohmann::json phone_resolve(std::string_view who) {
    std::string w = str(who);
    auto call = fn(&marvin_robot_api::phone_resolve, "phone_resolve");
    return nlohmann::json::parse(
        text([&](marvin_text_out* out) { return call(host_, w.c_str(), out); }));
  }
  // Starts a call; the progress comes from phone_wait_event().
  void phone_dial(std::string_view number, std::string_view name = {}) {
    std::string n = str(number);
    std::string who = str(name);
    check(fn(&marvin_robot_api::phone_dial, "phone_dial")(host_, n.c_str(), who.c_str()));
  }
  void phone_hang_up() { check(fn(&marvin_robot_api::phone_hang_up, "phone_hang_up")(host_)); }
  void phone_answer() { check(fn(&marvin_robot_api::phone_answer, "phone_answer")(host_)); }
  void phone_decline() { check(fn(&marvin_robot_api::phone_decline, "phone_decline")(host_)); }
  // {"state", "number", "name"}.
  nlohmann::json phone_state() {
    auto call = fn(&marvin_robot_api::phone_state, "phone_state");
    return nlohmann::json::parse(text([&](marvin_text_out* out) { return call(host_, out); }));
  }
  // The next event of the call this skill placed; nullopt when nothing happened within
  // `timeout`. Throws Error(MARVIN_ERR_CANCELLED) when the user said "stop".
  std::optional<nlohmann::json> phone_wait_event(std::chrono::milliseconds timeout) {
    auto call = fn(&marvin_robot_api::phone_wait_event, "phone_wait_event");
    const auto ms = static_cast<std::uint32_t>(timeout.count());
    try {
      return nlohmann::json::parse(
          text([&](marvin_text_out* out) { return call(host_, ms, out); }));
    } catch (const Error& e) {
      if (e.status() == MARVIN_ERR_NOT_FOUND) return std::nullopt;
      throw;
    }
  }
  void phone_call_for_help() {
    check(fn(&marvin_robot_api::phone_call_for_help, "phone_call_for_help")(host_));
  }
  nlohmann::json contacts_find(std::string_view name) {
    std::string n = str(name);
    auto call = fn(&marvin_robot_api::contacts_find, "contacts_find");
    return nlohmann::json::parse(
        text([&](marvin_text_out* out) { return call(host_, n.c_str(), out); }));
  }
  // Since API 1.5: every contact, sorted by name.
  nlohmann::json contacts_list() {
    auto call = fn(&marvin_robot_api::contacts_list, "contacts_list");
    return nlohmann::json::parse(text([&](marvin_text_out* out) { return call(host_, out); }));
  }
  // Since API 1.7: forgets the contact with this id (Error(MARVIN_ERR_NOT_FOUND) if none).
  void contacts_remove(std::int64_t id) {
    check(fn(&marvin_robot_api::contacts_remove, "contacts_remove")(host_, id));
  }
  nlohmann::json contacts_add(const nlohmann::json& contact) {
    std::string in = contact.dump();
    auto call = fn(&marvin_robot_api::contacts_add, "contacts_add");
    return nlohmann::json::parse(
        text([&](marvin_text_out* out) { return call(host_, in.c_str(), out); }));
  }
  nlohmann::json people_list() {
    auto call = fn(&marvin_robot_api::people_list, "people_list");
    return nlohmann::json::parse(text([&](marvin_text_out* out) { return call(host_, out); }));
  }

  // --- seeing (API 1.2; see marvin/robot.h) ---
  // What the camera sees now: {"width", "height", "faces": [...], "objects": [...]}.
  nlohmann::json vision_look() {
    auto call = fn(&marvin_robot_api::vision_look, "vision_look");
    return nlohmann::json::parse(text([&](marvin_text_out* out) { return call(host_, out); }));
  }
  // Takes a photo; returns the JPEG's path.
  std::string vision_capture_photo() {
    auto call = fn(&marvin_robot_api::vision_capture_photo, "vision_capture_photo");
    return text([&](marvin_text_out* out) { return call(host_, out); });
  }
  // Learns the one face in view as `name` from up to `frames` frames: {"name", "frames_used"}.
  nlohmann::json vision_enroll_face(std::string_view name, std::uint32_t frames = 5) {
    std::string n = str(name);
    auto call = fn(&marvin_robot_api::vision_enroll_face, "vision_enroll_face");
    return nlohmann::json::parse(
        text([&](marvin_text_out* out) { return call(host_, n.c_str(), frames, out); }));
  }
  void vision_forget_face(std::string_view name) {
    std::string n = str(name);
    check(fn(&marvin_robot_api::vision_forget_face, "vision_forget_face")(host_, n.c_str()));
  }
  // "These are my keys": learns the look of what is held up in the middle of the view.
  void vision_teach_object(std::string_view name) {
    std::string n = str(name);
    check(fn(&marvin_robot_api::vision_teach_object, "vision_teach_object")(host_, n.c_str()));
  }
  // {"name", "found", "box"} for a taught object, or for a word naming a COCO class when the
  // host has a detector ("name" is then the host's word for it, "class" the COCO class);
  // nullopt if it was never taught and names no class the host knows.
  std::optional<nlohmann::json> vision_find_object(std::string_view name) {
    std::string n = str(name);
    auto call = fn(&marvin_robot_api::vision_find_object, "vision_find_object");
    try {
      return nlohmann::json::parse(
          text([&](marvin_text_out* out) { return call(host_, n.c_str(), out); }));
    } catch (const Error& e) {
      if (e.status() == MARVIN_ERR_NOT_FOUND) return std::nullopt;
      throw;
    }
  }

  // --- finding and guarding (API 1.3; see marvin/robot.h) ---
  // Turns a full circle in `stops` stops, looking at each: {"stops", "seen": [...]}.
  nlohmann::json look_around(std::uint32_t stops = 0) {
    auto call = fn(&marvin_robot_api::look_around, "look_around");
    return nlohmann::json::parse(
        text([&](marvin_text_out* out) { return call(host_, stops, out); }));
  }
  // Where `what` ("" for everything) was seen, newest first: [{"what", "kind", "room",
  // "near", "seen_unix_ms"}].
  nlohmann::json sightings_find(std::string_view what, std::int64_t since_unix_ms = 0) {
    std::string w = str(what);
    auto call = fn(&marvin_robot_api::sightings_find, "sightings_find");
    return nlohmann::json::parse(
        text([&](marvin_text_out* out) { return call(host_, w.c_str(), since_unix_ms, out); }));
  }
  // The rooms in the order a search visits them (the robot's room first).
  std::vector<std::string> rooms_to_search() {
    auto call = fn(&marvin_robot_api::rooms_to_search, "rooms_to_search");
    return nlohmann::json::parse(text([&](marvin_text_out* out) { return call(host_, out); }))
        .get<std::vector<std::string>>();
  }
  // {"name", "kind": "room" | "place" | "person", "room"} and, when the robot can tell,
  // "distance_m" (how far it would drive there); nullopt for a name the map does not know.
  std::optional<nlohmann::json> place_find(std::string_view name) {
    std::string n = str(name);
    auto call = fn(&marvin_robot_api::place_find, "place_find");
    try {
      return nlohmann::json::parse(
          text([&](marvin_text_out* out) { return call(host_, n.c_str(), out); }));
    } catch (const Error& e) {
      if (e.status() == MARVIN_ERR_NOT_FOUND) return std::nullopt;
      throw;
    }
  }
  // Turns in place, counter-clockwise positive.
  void turn(std::int32_t degrees) { check(fn(&marvin_robot_api::turn, "turn")(host_, degrees)); }
  // Guard mode: 1 on, 0 off (throws Error(PERMISSION) unless a known face is in view),
  // -1 report. Returns {"on", "since_unix_ms", "alerts", "by"}.
  nlohmann::json guard(std::int32_t mode) {
    auto call = fn(&marvin_robot_api::guard, "guard");
    return nlohmann::json::parse(
        text([&](marvin_text_out* out) { return call(host_, mode, out); }));
  }
  // Events of `kind` ("" for all) since then, newest first: [{"kind", "message",
  // "time_unix_ms"}].
  nlohmann::json events_list(std::string_view kind, std::int64_t since_unix_ms = 0) {
    std::string k = str(kind);
    auto call = fn(&marvin_robot_api::events_list, "events_list");
    return nlohmann::json::parse(
        text([&](marvin_text_out* out) { return call(host_, k.c_str(), since_unix_ms, out); }));
  }

  // This skill's own key-value storage. storage_get returns nullopt for a missing key.
  std::optional<std::string> storage_get(std::string_view key) {
    std::string k = str(key);
    auto call = fn(&marvin_robot_api::storage_get, "storage_get");
    try {
      return text([&](marvin_text_out* out) { return call(host_, k.c_str(), out); });
    } catch (const Error& e) {
      if (e.status() == MARVIN_ERR_NOT_FOUND) return std::nullopt;
      throw;
    }
  }
  void storage_set(std::string_view key, std::string_view value) {
    check(fn(&marvin_robot_api::storage_set, "storage_set")(host_, str(key).c_str(), value.data(),
                                                            value.size()));
  }
  // False if there was nothing stored under `key`.
  bool storage_remove(std::string_view key) {
    marvin_status s =
        fn(&marvin_robot_api::storage_remove, "storage_remove")(host_, str(key).c_str());
    if (s == MARVIN_ERR_NOT_FOUND) return false;
    check(s);
    return true;
  }

  void log(marvin_log_level level, std::string_view message) {
    check(fn(&marvin_robot_api::log, "log")(host_, level, str(message).c_str()));
  }
  // True once the user said "stop" or the time limit ran out; long loops poll it.
  bool cancelled() const {
    return has(offsetof(marvin_robot_api, is_cancelled), sizeof(api_->is_cancelled)) &&
           api_->is_cancelled && api_->is_cancelled(host_) != 0;
  }
  // Throws Error(MARVIN_ERR_CANCELLED) once cancelled().
  void check_cancelled() const {
    if (cancelled()) throw Error(MARVIN_ERR_CANCELLED, "cancelled");
  }

 private:
  static std::string str(std::string_view s) { return std::string(s); }

  bool has(std::size_t offset, std::size_t size) const {
    return api_ && api_->struct_size >= offset + size;
  }

  // The table's function `member`, or Error(UNAVAILABLE) when the host's (older) table
  // does not have it.
  template <class F>
  F fn(F marvin_robot_api::*member, const char* name) const {
    static const marvin_robot_api probe{};
    std::size_t offset = static_cast<std::size_t>(reinterpret_cast<const char*>(&(probe.*member)) -
                                                  reinterpret_cast<const char*>(&probe));
    if (!has(offset, sizeof(F)) || !(api_->*member)) {
      throw Error(MARVIN_ERR_UNAVAILABLE,
                  std::string("this host's Robot API has no ") + name + "()");
    }
    return api_->*member;
  }

  void check(marvin_status status) const {
    if (status == MARVIN_OK) return;
    const char* why = api_->last_error ? api_->last_error(host_) : nullptr;
    throw Error(status, why && *why ? why : "Robot API call failed");
  }

  // Calls a function writing text into a caller-owned buffer, retrying once with a buffer
  // of the size the host reported when the first was too small. The retry of a call that
  // acts (turns the robot, adds a reminder, ...) does not act again: the host kept the
  // answer for it (marvin/abi.h, marvin_text_out).
  template <class Call>
  std::string text(Call&& call) const {
    std::string buffer(512, '\0');
    marvin_text_out out{buffer.data(), buffer.size(), 0};
    marvin_status s = call(&out);
    if (s == MARVIN_ERR_TRUNCATED) {
      buffer.assign(out.length + 1, '\0');
      out = marvin_text_out{buffer.data(), buffer.size(), 0};
      s = call(&out);
    }
    check(s);
    buffer.resize(out.length);
    return buffer;
  }

  const marvin_robot_api* api_;
  marvin_host* host_;
};

// Base class of a C++ skill. Derive, implement handle(), register with MARVIN_SKILL.
class Skill {
 public:
  explicit Skill(Robot robot) : robot_(robot) {}
  virtual ~Skill() = default;
  Skill(const Skill&) = delete;
  Skill& operator=(const Skill&) = delete;

  // Acts on one request; throw to fail (see the top of this file).
  virtual void handle(const Request& request) = 0;

 protected:
  Robot& robot() { return robot_; }

 private:
  Robot robot_;
};

namespace detail {

inline void write_error(marvin_text_out* out, const char* text) {
  if (!out) return;
  std::size_t length = std::strlen(text);
  out->length = length;
  if (!out->data || out->capacity == 0) return;
  std::size_t n = length < out->capacity - 1 ? length : out->capacity - 1;
  std::memcpy(out->data, text, n);
  out->data[n] = '\0';
}

template <class S>
void* create(const marvin_robot_api* api, marvin_host* host, marvin_text_out* error) {
  try {
    return new S(Robot(api, host));
  } catch (const std::exception& e) {
    write_error(error, e.what());
  } catch (...) {
    write_error(error, "unknown exception in the skill's constructor");
  }
  return nullptr;
}

template <class S>
void destroy(void* instance) {
  try {
    delete static_cast<S*>(instance);
  } catch (...) {
    // A destructor that throws cannot be reported anywhere useful; swallowing it keeps the
    // exception from crossing the C ABI.
  }
}

template <class S>
marvin_status handle(void* instance, const marvin_request* request, marvin_text_out* error) {
  try {
    if (!instance || !request || !request->intent) {
      write_error(error, "no instance or request");
      return MARVIN_ERR_INVALID;
    }
    Request r;
    r.intent = request->intent;
    r.slots = request->slots_json && *request->slots_json
                  ? nlohmann::json::parse(request->slots_json)
                  : nlohmann::json::object();
    r.utterance = request->utterance ? request->utterance : "";
    static_cast<S*>(instance)->handle(r);
    return MARVIN_OK;
  } catch (const Error& e) {
    write_error(error, e.what());
    return e.status() == MARVIN_OK ? MARVIN_ERR_INTERNAL : e.status();
  } catch (const std::exception& e) {
    write_error(error, e.what());
  } catch (...) {
    write_error(error, "unknown exception in the skill");
  }
  return MARVIN_ERR_INTERNAL;
}

}  // namespace detail

// The descriptor of skill class S with id `skill_id`. Use it directly to hand a skill
// compiled into a test to the SkillHarness; MARVIN_SKILL exports it. The descriptor lives
// as long as the process; asking again for the same class and id returns the same one.
template <class S>
const marvin_skill_descriptor* skill_descriptor(const char* skill_id) {
  static std::mutex mutex;
  static std::map<std::string, marvin_skill_descriptor> by_id;  // nodes never move
  std::lock_guard<std::mutex> lock(mutex);
  auto it = by_id.find(skill_id);
  if (it == by_id.end()) {
    it = by_id.emplace(skill_id, marvin_skill_descriptor{}).first;
    it->second = marvin_skill_descriptor{sizeof(marvin_skill_descriptor),
                                         MARVIN_ABI_MAJOR,
                                         MARVIN_ABI_MINOR,
                                         it->first.c_str(),
                                         &detail::create<S>,
                                         &detail::destroy<S>,
                                         &detail::handle<S>};
  }
  return &it->second;
}

}  // namespace marvin

// Exports skill class `SkillClass` with id `skill_id` (must equal "id" in skill.json).
// Use once per shared library, at namespace scope.
#define MARVIN_SKILL(SkillClass, skill_id)                                                    \
  extern "C" MARVIN_EXPORT const marvin_skill_descriptor* marvin_get_skill_descriptor(void) { \
    return ::marvin::skill_descriptor<SkillClass>(skill_id);                                  \
  }

#endif  // MARVIN_SKILL_HPP_
