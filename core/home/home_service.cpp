#include "home/home_service.h"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <nlohmann/json.hpp>

#include "common/log.h"
#include "home/discovery.h"

namespace marvin::home {
namespace {

using nlohmann::json;

std::int64_t now_ms() {
  return std::chrono::duration_cast<std::chrono::milliseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

void ignored(const std::string& topic, const std::string& why) {
  log(LogLevel::kWarning, "home", "ignored " + topic + ": " + why);
}

}  // namespace

const char* to_string(HomeService::Outcome outcome) {
  switch (outcome) {
    case HomeService::Outcome::kConfirmed:
      return "confirmed";
    case HomeService::Outcome::kNoAnswer:
      return "no answer";
    case HomeService::Outcome::kDeviceOffline:
      return "device offline";
    case HomeService::Outcome::kBrokerUnreachable:
      return "broker unreachable";
    case HomeService::Outcome::kUnknownDevice:
      return "unknown device";
  }
  return "?";
}

HomeService::HomeService(HomeConfig config) : config_(std::move(config)) {
  MqttOptions options = config_.broker;
  if (options.client_id.empty()) options.client_id = "marvin-" + config_.site;
  options.will_topic = topic("availability");
  options.will_payload = "offline";
  options.birth_topic = topic("availability");
  options.birth_payload = "online";
  client_ = std::make_unique<MqttClient>(
      io_, std::move(options),
      [this](const std::string& t, std::string_view payload, bool retained) {
        handle_message(t, payload, retained);
      },
      [this](bool up) { handle_connection(up); });
  client_->subscribe(config_.discovery_prefix + "/+/+/config");
  client_->subscribe(config_.discovery_prefix + "/+/+/+/config");
  client_->subscribe(config_.zigbee2mqtt_base + "/#");
  if (config_.commands) client_->subscribe(topic("command/+"));
  client_->subscribe(topic("sync"));
}

bool HomeService::settle(std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  static std::atomic<unsigned> counter{0};
  // Twice: state topics subscribed after the first round's discovery have their retained
  // messages delivered before the second round's marker.
  for (int round = 0; round < 2; ++round) {
    {
      std::unique_lock lock(mutex_);
      if (!changed_.wait_until(lock, deadline, [&] { return up_; })) return false;
    }
    const std::string nonce = std::to_string(::getpid()) + "-" + std::to_string(counter++);
    if (!client_->publish(topic("sync"), nonce, 0, false)) return false;
    std::unique_lock lock(mutex_);
    if (!changed_.wait_until(lock, deadline, [&] { return last_sync_ == nonce; })) return false;
  }
  return true;
}

HomeService::~HomeService() { stop(); }

void HomeService::start() {
  if (thread_.joinable()) return;
  client_->start();
  thread_ = std::thread([this] { io_.run(); });
}

void HomeService::stop() {
  if (!thread_.joinable()) return;
  // Say goodbye on the bus before leaving (a clean disconnect sends no last will).
  client_->publish(topic("availability"), "offline", 1, true);
  client_->stop();
  io_.stop();
  thread_.join();
}

std::string HomeService::topic(const std::string& leaf) const {
  return "marvin/" + config_.site + "/" + leaf;
}

bool HomeService::connected() const { return client_->connected(); }

int HomeService::connections() const { return client_->connections(); }

bool HomeService::wait_connected(std::chrono::milliseconds timeout) const {
  std::unique_lock lock(mutex_);
  return changed_.wait_for(lock, timeout, [&] { return up_; });
}

std::vector<Device> HomeService::devices() const {
  std::lock_guard lock(mutex_);
  std::vector<Device> out;
  for (const auto& [id, d] : devices_) {
    Device copy = d;
    for (const auto& [alias, target] : aliases_) {
      if (target == d.id || target == d.name) copy.aliases.push_back(alias);
    }
    out.push_back(std::move(copy));
  }
  std::sort(out.begin(), out.end(), [](const Device& a, const Device& b) {
    return a.room != b.room ? a.room < b.room : a.name < b.name;
  });
  return out;
}

std::optional<Device> HomeService::device(const std::string& id) const {
  for (Device& d : devices()) {
    if (d.id == id) return d;
  }
  return std::nullopt;
}

bool HomeService::wait_devices(const std::function<bool(const std::vector<Device>&)>& done,
                               std::chrono::milliseconds timeout) const {
  auto deadline = std::chrono::steady_clock::now() + timeout;
  while (true) {
    if (done(devices())) return true;
    std::unique_lock lock(mutex_);
    if (changed_.wait_until(lock, deadline) == std::cv_status::timeout) {
      lock.unlock();
      return done(devices());
    }
  }
}

void HomeService::set_aliases(std::map<std::string, std::string> aliases) {
  std::lock_guard lock(mutex_);
  aliases_.clear();
  for (auto& [alias, target] : aliases) aliases_[lower(alias)] = lower(target);
}

void HomeService::set_room_hook(std::function<std::string()> hook) {
  std::lock_guard lock(mutex_);
  room_hook_ = std::move(hook);
}

std::string HomeService::room() const {
  std::function<std::string()> hook;
  {
    std::lock_guard lock(mutex_);
    hook = room_hook_;
  }
  std::string r = hook ? hook() : std::string();
  return r.empty() ? lower(config_.room) : lower(r);
}

HomeService::SetResult HomeService::set(const std::string& id, const DeviceCommand& command,
                                        std::optional<std::chrono::milliseconds> timeout) {
  SetResult result;
  std::vector<std::pair<std::string, std::string>> messages;
  std::uint64_t before = 0;
  {
    std::lock_guard lock(mutex_);
    auto it = devices_.find(id);
    if (it == devices_.end()) return result;
    result.state = it->second.state;
    if (!up_) {
      result.outcome = Outcome::kBrokerUnreachable;
      return result;
    }
    if (!it->second.state.available) {
      result.outcome = Outcome::kDeviceOffline;
      return result;
    }
    before = it->second.state.reports;
    messages = command_messages(it->second, command);
  }
  for (auto& [t, payload] : messages) {
    // QoS 0: a command lost with the connection is reported as unanswered, never
    // delivered late (a redelivery after a broker restart would be a second action).
    if (!client_->publish(t, payload, 0, false)) {
      result.outcome = Outcome::kBrokerUnreachable;
      return result;
    }
  }
  const auto deadline = std::chrono::steady_clock::now() + timeout.value_or(config_.answer_timeout);
  std::unique_lock lock(mutex_);
  bool done = changed_.wait_until(lock, deadline, [&] {
    auto it = devices_.find(id);
    if (!up_ || it == devices_.end()) return true;
    return it->second.state.reports > before && state_matches(it->second.state, command);
  });
  auto it = devices_.find(id);
  if (it == devices_.end()) {
    result.outcome = Outcome::kUnknownDevice;
  } else {
    result.state = it->second.state;
    if (!up_) {
      result.outcome = Outcome::kBrokerUnreachable;
    } else if (done) {
      result.outcome = Outcome::kConfirmed;
    } else {
      result.outcome = it->second.state.available ? Outcome::kNoAnswer : Outcome::kDeviceOffline;
    }
  }
  return result;
}

void HomeService::remove_devices_from(const std::string& source_key) {
  auto src = sources_.find(source_key);
  if (src == sources_.end()) return;
  for (const std::string& id : src->second) devices_.erase(id);
  sources_.erase(src);
}

void HomeService::add_devices(std::vector<Device> found, const std::string& source_key) {
  // Keep the last reported state of devices that are announced again.
  std::map<std::string, DeviceState> kept;
  if (auto src = sources_.find(source_key); src != sources_.end()) {
    for (const std::string& id : src->second) {
      if (auto d = devices_.find(id); d != devices_.end()) kept[id] = d->second.state;
    }
  }
  remove_devices_from(source_key);
  std::set<std::string>& ids = sources_[source_key];
  for (Device& d : found) {
    if (d.name.empty()) continue;
    if (auto k = kept.find(d.id); k != kept.end()) d.state = k->second;
    for (const std::string* t :
         {&d.protocol.state_topic, &d.protocol.availability_topic,
          &d.protocol.brightness_state_topic, &d.protocol.setpoint_state_topic,
          &d.protocol.current_temperature_topic}) {
      if (t->empty()) continue;
      std::vector<std::string>& route = routes_[*t];
      if (std::find(route.begin(), route.end(), d.id) == route.end()) route.push_back(d.id);
      // Zigbee2MQTT topics arrive through <base>/#; others need their own subscription.
      if (t->rfind(config_.zigbee2mqtt_base + "/", 0) != 0 && subscribed_.insert(*t).second) {
        client_->subscribe(*t);
      }
    }
    ids.insert(d.id);
    devices_[d.id] = std::move(d);
  }
}

void HomeService::handle_message(const std::string& t, std::string_view payload, bool) {
  if (payload.size() > kMaxPayloadBytes) {
    ignored(t, "a payload of " + std::to_string(payload.size()) + " bytes is larger than " +
                   std::to_string(kMaxPayloadBytes) + " bytes");
    return;
  }
  std::string component, object_id;
  if (parse_ha_config_topic(config_.discovery_prefix, t, &component, &object_id)) {
    try {
      Device d = parse_ha_config(component, object_id, payload);
      std::lock_guard lock(mutex_);
      std::vector<Device> found;
      if (!d.name.empty()) found.push_back(std::move(d));
      add_devices(std::move(found), t);
    } catch (const DiscoveryError& e) {
      ignored(t, e.what());
      return;
    }
    tell_devices_changed();
    return;
  }
  if (t == config_.zigbee2mqtt_base + "/bridge/devices") {
    try {
      std::vector<Device> found = parse_z2m_devices(config_.zigbee2mqtt_base, payload);
      std::lock_guard lock(mutex_);
      add_devices(std::move(found), t);
    } catch (const DiscoveryError& e) {
      ignored(t, e.what());
      return;
    }
    tell_devices_changed();
    return;
  }
  if (t == topic("sync")) {
    {
      std::lock_guard lock(mutex_);
      last_sync_ = std::string(payload);
    }
    changed_.notify_all();
    return;
  }
  if (config_.commands && t.rfind(topic("command/"), 0) == 0) {
    const std::string name = t.substr(topic("command/").size());
    if (name != "say" && name != "utterance") {
      ignored(t, "not a command Marvin takes (say, utterance)");
      return;
    }
    std::function<void(const std::string&, const std::string&)> handler;
    {
      std::lock_guard lock(mutex_);
      handler = command_handler_;
    }
    if (handler && !payload.empty()) handler(name, std::string(payload));
    return;
  }
  bool changed = false;
  {
    std::lock_guard lock(mutex_);
    auto route = routes_.find(t);
    if (route == routes_.end()) return;
    for (const std::string& id : route->second) {
      auto it = devices_.find(id);
      if (it == devices_.end()) continue;
      Device& d = it->second;
      bool ok = t == d.protocol.availability_topic ? apply_availability(d, payload, &d.state)
                                                   : apply_state(d, t, payload, &d.state);
      if (ok) {
        changed = true;
      } else {
        ignored(t, "not a state or availability report of " + d.name + ": \"" +
                       std::string(payload.substr(0, 40)) + "\"");
      }
    }
  }
  if (changed) tell_devices_changed();
}

void HomeService::handle_connection(bool up) {
  {
    std::lock_guard lock(mutex_);
    up_ = up;
  }
  tell_devices_changed();
  if (up) publish_presence();
}

std::string HomeService::status_json() const {
  std::string activity;
  {
    std::lock_guard lock(mutex_);
    activity = activity_;
  }
  return json{{"activity", activity}, {"room", room()}}.dump();
}

void HomeService::publish_activity(const std::string& activity) {
  {
    std::lock_guard lock(mutex_);
    if (activity_ == activity) return;
    activity_ = activity;
  }
  client_->publish(topic("status"), status_json(), 0, true);
}

void HomeService::publish_event(const std::string& event_type, const std::string& text) {
  json event{{"event_type", event_type}, {"text", text}, {"time_ms", now_ms()}};
  if (!client_->publish(topic("event"), event.dump(), 1, false)) {
    log(LogLevel::kInfo, "home", "event " + event_type + " not published: no broker");
  }
}

void HomeService::on_devices_changed(std::function<void()> listener) {
  std::lock_guard listening(devices_listener_mutex_);
  devices_listener_ = std::move(listener);
}

void HomeService::tell_devices_changed() {
  changed_.notify_all();
  std::lock_guard listening(devices_listener_mutex_);
  if (devices_listener_) devices_listener_();
}

void HomeService::on_command(
    std::function<void(const std::string& name, const std::string& payload)> f) {
  std::lock_guard lock(mutex_);
  command_handler_ = std::move(f);
}

// Home Assistant discovery for Marvin itself: one device with an activity sensor, a room
// sensor and an event entity, all bound to marvin/<site>/availability.
void HomeService::publish_presence() {
  const std::string node = "marvin_" + config_.site;
  const json device{{"identifiers", json::array({node})},
                    {"name", "Marvin (" + config_.site + ")"},
                    {"manufacturer", "Marvin project"},
                    {"model", "home robot"}};
  auto common = [&](const std::string& key, const std::string& name) {
    return json{{"name", name},
                {"unique_id", node + "_" + key},
                {"availability_topic", topic("availability")},
                {"device", device}};
  };
  json activity = common("activity", "Activity");
  activity["state_topic"] = topic("status");
  activity["value_template"] = "{{ value_json.activity }}";
  json room = common("room", "Room");
  room["state_topic"] = topic("status");
  room["value_template"] = "{{ value_json.room }}";
  json event = common("event", "Event");
  event["state_topic"] = topic("event");
  event["event_types"] =
      json::array({"reminder_fired", "reminder_missed", "intruder_alert", "call"});
  const std::string prefix = config_.discovery_prefix;
  client_->publish(prefix + "/sensor/" + node + "/activity/config", activity.dump(), 1, true);
  client_->publish(prefix + "/sensor/" + node + "/room/config", room.dump(), 1, true);
  client_->publish(prefix + "/event/" + node + "/event/config", event.dump(), 1, true);
  client_->publish(topic("status"), status_json(), 0, true);
}

}  // namespace marvin::home
