#include "marvin/testing/mock_robot.hpp"

#include <algorithm>
#include <cmath>
#include <cctype>
#include <limits>

#include "mock_robot_impl.h"
#include "skills/api_json.h"

namespace marvin::testing {

namespace {
// The mock body's steady clock: it stands still (any value would do).
constexpr std::int64_t kSteadyNowMs = 1'000'000;
}  // namespace

MockRobot::Impl::Impl(std::string id, std::vector<std::string> permissions)
    : skill_id(std::move(id)) {
  services.data = &data;
  services.body = this;
  services.user = this;
  services.now_ms = [this] { return now_ms; };
  services.steady_now_ms = [] { return kSteadyNowMs; };
  services.time_zone = "UTC";
  services.wait_for_motion = false;
  services.last_fired_reminder = [this] { return last_fired; };
  services.going_places = this;
  home.actions = &actions;
  services.smarthome = &home;
  services.sightings = &sightings;
  skills::GuardOptions guard_options;
  guard_options.watch = false;  // the mock's guard keeps its state only
  guard = std::make_unique<skills::Guard>(eyes, nullptr, [this] { return now_ms; },
                                          [](const std::string&, const std::string&) {},
                                          guard_options);
  services.guard = guard.get();
  // The log holds what a test adds (add_event) and what the skill's own calls write to
  // the store ("I took them"), newest first as the host's.
  services.events = [this](std::string_view kind, std::int64_t since) {
    std::vector<skills::HostServices::LoggedEvent> out;
    for (auto it = events.rbegin(); it != events.rend(); ++it) {
      if (it->time_ms >= since && (kind.empty() || it->kind == kind)) out.push_back(*it);
    }
    for (const auto& e : data.recent_events(kind, since)) {
      out.push_back({e.kind, e.message, e.time_ms});
    }
    std::stable_sort(out.begin(), out.end(),
                     [](const auto& a, const auto& b) { return a.time_ms > b.time_ms; });
    return out;
  };
  phone.actions = &actions;
  phone.data = &data;
  services.telephone = &phone;
  context = std::make_unique<skills::SkillContext>(skill_id, std::move(permissions), services);
}

void MockRobot::Impl::move(devices::Direction direction, std::uint8_t speed,
                           std::chrono::milliseconds duration) {
  actions.push_back(std::string("move ") + devices::to_string(direction) +
                    " speed=" + std::to_string(speed) + " ms=" + std::to_string(duration.count()));
}
void MockRobot::Impl::stop() { actions.push_back("stop"); }
void MockRobot::Impl::tilt_head(int degrees) {
  actions.push_back("tilt_head " + std::to_string(degrees));
}
std::vector<devices::ScanPoint> MockRobot::Impl::latest_scan() {
  // The host converts body (steady clock) stamps to the wall clock by the two clocks' now;
  // the mock's body clock stands still, so points come out exactly as the test set them.
  std::vector<devices::ScanPoint> out;
  for (const auto& p : scan) {
    out.push_back(
        devices::ScanPoint{p.angle_deg, p.distance_m, kSteadyNowMs - (now_ms - p.time_ms)});
  }
  return out;
}
void MockRobot::Impl::set_light(devices::Light light) {
  actions.push_back(std::string("light ") + devices::to_string(light));
}

nlohmann::json FakePhone::event(const std::string& kind) const {
  return nlohmann::json{{"event", kind}, {"number", number}, {"name", name.empty() ? number : name}};
}

std::string FakePhone::outcome_of(const std::string& n) const {
  auto it = outcomes.find(n);
  return it == outcomes.end() ? "answer" : it->second;
}

skills::Telephone::Reply FakePhone::dial(const std::string& n, const std::string& who) {
  if (!failure.empty()) return {Result::kUnavailable, failure};
  if (n.empty() || n.find_first_not_of(" ") == std::string::npos) {
    return {Result::kInvalid, "number: \"" + n + "\" is neither a phone number nor a sip: URI"};
  }
  if (call_state != "idle") {
    return {Result::kUnavailable, "a call with " + (name.empty() ? number : name) + " is going on"};
  }
  actions->push_back("phone_dial " + n);
  number = n;
  name = who;
  events.clear();
  const std::string outcome = outcome_of(n);
  if (outcome == "fail") {
    events.push_back(event("failed"));
    events.back()["reason"] = "503 Service Unavailable";
    return {};
  }
  events.push_back(event("ringing"));
  if (outcome == "answer") {
    events.push_back(event("answered"));
    call_state = "in_call";
  } else {
    events.push_back(event(outcome == "busy" ? "busy" : "no_answer"));
  }
  return {};
}

bool FakePhone::hang_up() {
  if (call_state == "idle") return false;
  actions->push_back(call_state == "incoming" ? "phone_decline" : "phone_hang_up");
  call_state = "idle";
  return true;
}

bool FakePhone::answer() {
  if (call_state != "incoming") return false;
  actions->push_back("phone_answer");
  call_state = "in_call";
  return true;
}

bool FakePhone::decline() { return call_state == "incoming" && hang_up(); }

nlohmann::json FakePhone::state() {
  if (call_state == "idle") return {{"state", "idle"}, {"number", ""}, {"name", ""}};
  return {{"state", call_state}, {"number", number}, {"name", name.empty() ? number : name}};
}

std::optional<nlohmann::json> FakePhone::wait_event(std::chrono::milliseconds,
                                                    const std::function<bool()>& stop) {
  // Nothing runs meanwhile: an empty queue stays empty (as if the time ran out).
  if (stop() || events.empty()) return std::nullopt;
  nlohmann::json e = events.front();
  events.pop_front();
  return e;
}

skills::Telephone::Reply FakePhone::call_for_help(
    std::vector<std::pair<std::string, std::string>> contacts) {
  if (!failure.empty()) return {Result::kUnavailable, failure};
  actions->push_back("phone_call_for_help");
  events.clear();
  auto step = [&](const std::string& text) {
    data->log_event("emergency", "phone", text);
    events.push_back({{"event", "emergency_step"}, {"text", text}});
  };
  std::string answered_by;
  for (const auto& [who, n] : contacts) {
    step("Calling " + who + " for help");
    const std::string outcome = outcome_of(n);
    if (outcome == "answer") {
      answered_by = who;
      number = n;
      name = who;
      call_state = "in_call";
      step(who + " answered the emergency call");
      break;
    }
    step(who + " did not answer (" + (outcome == "no_answer" ? "no answer" : outcome) + ")");
  }
  if (answered_by.empty()) step("Nobody answered the emergency call");
  events.push_back({{"event", "emergency_done"}, {"answered_by", answered_by}});
  return {};
}

namespace {
// Lower case without a leading "the ": how the robot's map matches names.
std::string place_key(std::string_view name) {
  std::string s;
  for (char c : name) s += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (s.rfind("the ", 0) == 0) s.erase(0, 4);
  return s;
}
}  // namespace

navigation::GoResult MockRobot::Impl::go_to(std::string_view target,
                                            const navigation::WaitFn& wait) {
  actions.push_back("go_to " + std::string(target));
  navigation::GoResult r;
  r.target = std::string(target);
  if (wait(std::chrono::milliseconds(0))) {
    r.outcome = navigation::GoResult::Outcome::kCancelled;
    return r;
  }
  for (const auto& [name, reason] : blocked) {
    if (place_key(name) == place_key(target)) {
      r.outcome = navigation::GoResult::Outcome::kGaveUp;
      r.reason = reason;
      return r;
    }
  }
  for (const auto& [name, in_room] : places) {
    if (place_key(name) == place_key(target)) {
      room = in_room;
      home.room = in_room;
      heading = 0;
      show_room_view();
      return r;
    }
  }
  r.outcome = navigation::GoResult::Outcome::kUnknownPlace;
  r.reason = "I don't know where " + std::string(target) + " is";
  return r;
}
navigation::GoResult MockRobot::Impl::guide_to(std::string_view target, double speed_factor,
                                               const GuideFn& on_event,
                                               const navigation::WaitFn& wait) {
  const std::string action = "guide_to " + std::string(target) + " speed=" +
                             std::to_string(static_cast<int>(std::lround(speed_factor * 100)));
  std::vector<GuideEvent> told = std::move(guide_events);
  std::vector<bool> stops = std::move(guide_stops);
  guide_events.clear();
  guide_stops.clear();
  bool known = false;
  for (const auto& [name, in_room] : places) known = known || place_key(name) == place_key(target);
  for (std::size_t i = 0; known && i < told.size(); ++i) {
    const bool go_on = !on_event || on_event(told[i]);
    // stops[i]: "stop" was heard while the robot told this (the navigator's next wait()
    // reports it and the trip ends).
    if (!go_on || stops[i] || wait(std::chrono::milliseconds(0))) {
      actions.push_back(action);
      actions.push_back("stop");
      navigation::GoResult r;
      r.target = std::string(target);
      r.outcome = navigation::GoResult::Outcome::kCancelled;
      return r;
    }
  }
  navigation::GoResult r = go_to(target, wait);  // records "go_to <target>"
  actions.back() = action;
  return r;
}

std::optional<std::string> MockRobot::Impl::where_am_i() {
  if (room.empty()) return std::nullopt;
  return room;
}

bool MockRobot::Impl::turn(double degrees, const navigation::WaitFn& wait) {
  actions.push_back("turn " + std::to_string(static_cast<int>(std::lround(degrees))));
  // A room's view is what the camera sees facing the way the robot came in; turned away
  // from it, it sees nothing.
  heading = std::fmod(std::fmod(heading + degrees, 360.0) + 360.0, 360.0);
  show_room_view();
  return !wait(std::chrono::milliseconds(0));
}
void MockRobot::Impl::show_room_view() {
  if (room_views.empty()) return;
  auto view = room_views.find(room);
  const bool facing = heading < 1 || heading > 359;
  eyes.set_view(facing && view != room_views.end() ? view->second
                                                   : R"({"faces": [], "objects": []})");
}
std::optional<navigation::GoingPlaces::Spot> MockRobot::Impl::locate(double, double) {
  return Spot{room, ""};
}
std::vector<std::string> MockRobot::Impl::rooms_to_search() {
  std::vector<std::string> order;
  if (!room.empty()) order.push_back(room);
  for (const auto& [name, in_room] : places) {
    if (std::find(order.begin(), order.end(), in_room) == order.end()) order.push_back(in_room);
  }
  return order;
}
std::optional<navigation::GoingPlaces::PlaceInfo> MockRobot::Impl::find_place(
    std::string_view name) {
  for (const auto& [n, in_room] : places) {
    if (place_key(n) != place_key(name)) continue;
    const char* kind = std::isupper(static_cast<unsigned char>(n[0])) ? "person"
                       : place_key(n) == place_key(in_room)            ? "room"
                                                                       : "place";
    return PlaceInfo{n, kind, in_room};
  }
  return std::nullopt;
}

std::optional<double> MockRobot::Impl::path_length_to(std::string_view name) {
  auto it = path_lengths.find(place_key(name));
  if (it == path_lengths.end()) return std::nullopt;
  return it->second;
}

void MockRobot::Impl::say(std::string_view text) { said.emplace_back(text); }

std::optional<std::string> MockRobot::Impl::ask(std::string_view question) {
  said.emplace_back(question);
  asked.emplace_back(question);
  if (answers.empty()) return std::nullopt;
  std::string answer = std::move(answers.front());
  answers.pop_front();
  return answer;
}

nlohmann::json FakeHome::devices() {
  return nlohmann::json{{"connected", reachable}, {"room", room}, {"devices", list}};
}

skills::SmartHome::Reply FakeHome::set(const std::string& device, const nlohmann::json& state) {
  Reply reply;
  nlohmann::json* found = nullptr;
  for (nlohmann::json& d : list) {
    if (d["id"] == device || d["name"] == device) found = &d;
  }
  if (!found) {
    reply.result = Result::kNotFound;
    reply.sentence = "there is no device \"" + device + "\"";
    return reply;
  }
  const std::string id = (*found)["id"].get<std::string>();
  if (!reachable) {
    reply.result = Result::kUnavailable;
    reply.sentence = "the home's broker is unreachable";
    return reply;
  }
  actions->push_back("smarthome_set " + id + " " + state.dump());
  if (std::find(silent.begin(), silent.end(), id) != silent.end()) {
    reply.result = Result::kUnavailable;
    reply.sentence = "the " + (*found)["name"].get<std::string>() + " did not answer";
    reply.device = *found;
    return reply;
  }
  if (state.contains("target_temperature") && found->value("type", "") != "thermostat") {
    reply.result = Result::kInvalid;
    reply.sentence = "the " + (*found)["name"].get<std::string>() + " is not a thermostat";
    return reply;
  }
  if (state.contains("on")) (*found)["on"] = state["on"];
  if (state.contains("target_temperature"))
    (*found)["target_temperature"] = state["target_temperature"];
  if (state.contains("brightness")) (*found)["brightness"] = state["brightness"];
  reply.device = *found;
  return reply;
}

void MockRobot::add_device(const std::string& device_json) {
  nlohmann::json d = nlohmann::json::parse(device_json);
  for (const char* key : {"room", "type"}) {
    if (!d.contains(key)) d[key] = std::string(key) == "type" ? "light" : "";
  }
  if (!d.contains("id")) d["id"] = d["name"];
  if (!d.contains("dimmable")) d["dimmable"] = false;
  if (!d.contains("aliases")) d["aliases"] = nlohmann::json::array();
  if (!d.contains("available")) d["available"] = true;
  if (!d.contains("on")) d["on"] = false;
  if (!d.contains("brightness")) d["brightness"] = 100;
  impl_->home.list.push_back(std::move(d));
}
void MockRobot::set_device_answers(const std::string& id, bool answers) {
  auto& silent = impl_->home.silent;
  silent.erase(std::remove(silent.begin(), silent.end(), id), silent.end());
  if (!answers) silent.push_back(id);
}
void MockRobot::set_broker_reachable(bool reachable) { impl_->home.reachable = reachable; }

void MockRobot::set_call_outcome(const std::string& number, const std::string& outcome) {
  impl_->phone.outcomes[number] = outcome;
}
void MockRobot::incoming_call(const std::string& number, const std::string& name) {
  impl_->phone.call_state = "incoming";
  impl_->phone.number = number;
  impl_->phone.name = name;
}
void MockRobot::remote_hang_up() { impl_->phone.call_state = "idle"; }
void MockRobot::set_phone_failure(std::string reason) { impl_->phone.failure = std::move(reason); }
void MockRobot::set_phone_available(bool available) {
  impl_->services.telephone = available ? &impl_->phone : nullptr;
}
std::string MockRobot::phone_state() const { return impl_->phone.state()["state"]; }
std::vector<std::string> MockRobot::logged_events() const {
  std::vector<std::string> out;
  for (const auto& e : impl_->data.events()) out.push_back(e.kind + ": " + e.message);
  return out;
}
std::int64_t MockRobot::add_contact_json(const std::string& contact_json) {
  data::Contact c = skills::contact_from_json(nlohmann::json::parse(contact_json));
  return impl_->data.add_contact(c);
}
std::optional<std::string> MockRobot::device(const std::string& id) const {
  for (const nlohmann::json& d : impl_->home.list) {
    if (d["id"] == id) return d.dump();
  }
  return std::nullopt;
}

MockRobot::MockRobot(std::string skill_id, std::vector<std::string> permissions)
    : impl_(std::make_unique<Impl>(std::move(skill_id), std::move(permissions))) {}
MockRobot::~MockRobot() = default;

const marvin_robot_api* MockRobot::api() const { return skills::host_robot_api(); }
marvin_host* MockRobot::host() { return impl_->context->host(); }

void MockRobot::set_permissions(std::vector<std::string> permissions) {
  impl_->context->set_permissions(std::move(permissions));
}
void MockRobot::add_answer(std::string answer) { impl_->answers.push_back(std::move(answer)); }
void MockRobot::set_now(std::int64_t unix_ms) { impl_->now_ms = unix_ms; }
void MockRobot::set_time_zone(std::string iana_name) {
  impl_->services.time_zone = std::move(iana_name);
}
void MockRobot::set_scan(std::vector<marvin_scan_point> points) { impl_->scan = std::move(points); }
void MockRobot::cancel() { impl_->context->cancel(); }
void MockRobot::add_place(std::string name, std::string room) {
  impl_->places.emplace_back(std::move(name), std::move(room));
}
void MockRobot::set_path_length(const std::string& place, double metres) {
  impl_->path_lengths[place_key(place)] = metres;
}
void MockRobot::add_guide_event(const std::string& event_json) {
  const nlohmann::json j = nlohmann::json::parse(event_json);
  navigation::GoingPlaces::GuideEvent e;
  e.event = j.at("event").get<std::string>();
  e.turn = j.value("turn", "");
  e.kind = j.value("kind", "");
  e.distance_m = j.value("distance_m", 0.0);
  e.distance_left_m = j.value("distance_left_m", 0.0);
  e.stopped = j.value("stopped", false);
  impl_->guide_events.push_back(std::move(e));
  impl_->guide_stops.push_back(j.value("then_stop", false));
}
void MockRobot::block_place(std::string name, std::string reason) {
  impl_->blocked.emplace_back(std::move(name), std::move(reason));
}
void MockRobot::set_room(std::string room) {
  impl_->home.room = room;
  impl_->room = std::move(room);
  impl_->heading = 0;
  impl_->show_room_view();  // the camera sees the new room, as after go_to
}
const std::string& MockRobot::room() const { return impl_->room; }

std::int64_t MockRobot::add_contact(const std::string& name, std::vector<std::string> aliases,
                                    std::vector<std::string> phone_numbers) {
  data::Contact c;
  c.name = name;
  c.aliases = std::move(aliases);
  c.phone_numbers = std::move(phone_numbers);
  return impl_->data.add_contact(c);
}

std::int64_t MockRobot::add_reminder(const std::string& title, const std::string& at) {
  data::Reminder r = skills::reminder_from_json(nlohmann::json{{"title", title}, {"at", at}},
                                                impl_->services.time_zone);
  r.created_by = "user";
  return impl_->data.add_reminder(r);
}

void MockRobot::Impl::know_person(const std::string& name) {
  for (const data::Person& p : data.list_people()) {
    if (p.name == name) return;
  }
  data.add_person(data::Person{0, name, std::nullopt});
}

void MockRobot::Impl::know_faces_in(const std::string& seen_json) {
  const nlohmann::json seen = nlohmann::json::parse(seen_json, nullptr, false);
  if (!seen.is_object()) return;  // set_view reports the error
  for (const nlohmann::json& f : seen.value("faces", nlohmann::json::array())) {
    const std::string name = f.is_object() ? f.value("name", "") : "";
    if (!name.empty()) know_person(name);
  }
}

void MockRobot::set_camera_view(const std::string& seen_json) {
  impl_->eyes.set_view(seen_json);
  impl_->know_faces_in(seen_json);
  impl_->services.eyes = &impl_->eyes;
}
void MockRobot::set_room_view(const std::string& room, const std::string& seen_json) {
  impl_->room_views[room] = seen_json;
  impl_->know_faces_in(seen_json);
  impl_->services.eyes = &impl_->eyes;
  if (room == impl_->room) impl_->eyes.set_view(seen_json);
}
void MockRobot::add_event(const std::string& kind, const std::string& message) {
  impl_->events.push_back({kind, message, impl_->now_ms});
}
bool MockRobot::guarding() const { return impl_->guard->state().on; }
void MockRobot::set_camera_failure(std::string message) {
  impl_->eyes.set_failure(std::move(message));
  impl_->services.eyes = &impl_->eyes;
}
std::vector<std::string> MockRobot::enrolled_faces() const { return impl_->eyes.enrolled(); }

void MockRobot::set_last_fired(std::optional<std::int64_t> reminder_id) {
  impl_->last_fired = reminder_id;
}

const std::vector<std::string>& MockRobot::said() const { return impl_->said; }
const std::vector<std::string>& MockRobot::asked() const { return impl_->asked; }
const std::vector<std::string>& MockRobot::actions() const { return impl_->actions; }
std::size_t MockRobot::answers_left() const { return impl_->answers.size(); }

std::vector<std::string> MockRobot::reminders() const {
  std::vector<std::string> out;
  for (const auto& r : impl_->data.reminders_between(std::numeric_limits<std::int64_t>::min(),
                                                     std::numeric_limits<std::int64_t>::max())) {
    out.push_back(skills::reminder_to_json(r).dump());
  }
  return out;
}

std::optional<std::string> MockRobot::reminder(std::int64_t id) const {
  std::optional<data::Reminder> r = impl_->data.get_reminder(id);
  if (!r) return std::nullopt;
  nlohmann::json j = skills::reminder_to_json(*r);
  j["state"] = r->state == data::Reminder::State::kActive ? "active"
               : r->state == data::Reminder::State::kDone ? "done"
                                                          : "cancelled";
  return j.dump();
}

std::optional<std::string> MockRobot::stored(const std::string& key) const {
  return impl_->data.storage_get(impl_->skill_id, key);
}

void MockRobot::clear() {
  impl_->said.clear();
  impl_->asked.clear();
  impl_->actions.clear();
}

}  // namespace marvin::testing
