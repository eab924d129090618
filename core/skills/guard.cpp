#include "skills/guard.h"

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "common/log.h"

namespace marvin::skills {

Guard::Guard(Eyes& eyes, navigation::GoingPlaces* places, std::function<std::int64_t()> now_ms,
             std::function<void(const std::string&, const std::string&)> alert,
             GuardOptions options)
    : eyes_(eyes),
      places_(places),
      now_ms_(std::move(now_ms)),
      alert_(std::move(alert)),
      options_(options) {}

Guard::~Guard() {
  GuardState s;
  bool was_on = false;
  {
    std::lock_guard lock(mutex_);
    quit_ = true;
    was_on = state_.on;
    state_.on = false;
    if (was_on) state_.by = kOffByShutdown;
    s = state_;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
  // Nobody watches any more: `marvin guard status` must not say "on".
  if (was_on) tell(s);
}

std::string guard_state_json(const GuardState& s) {
  return nlohmann::json{{"on", s.on},
                        {"since_unix_ms", s.since_ms},
                        {"alerts", s.alerts},
                        {"by", s.by},
                        {"pictures", s.pictures}}
      .dump();
}

namespace {
// The head camera (sim/README.md; the real one is close): 60 degrees across the image. A
// face's distance from its box: chin to brow 0.18 m.
constexpr double kGuardFieldOfViewDeg = 60, kGuardFaceHeightM = 0.18;
constexpr double kGuardPi = 3.14159265358979323846;
}  // namespace

bool is_picture(const nlohmann::json& face, const nlohmann::json& seen,
                navigation::GoingPlaces* places) {
  const auto box = face.value("box", nlohmann::json::array());
  if (box.size() != 4) return false;
  const double cx = box[0].get<double>() + box[2].get<double>() / 2;
  const double cy = box[1].get<double>() + box[3].get<double>() / 2;
  for (const auto& o : seen.value("objects", nlohmann::json::array())) {
    const std::string cls = o.value("class", "");
    const auto ob = o.value("box", nlohmann::json::array());
    if ((cls != "tv" && cls != "laptop") || ob.size() != 4) continue;
    const double x = ob[0].get<double>(), y = ob[1].get<double>();
    if (cx >= x && cx <= x + ob[2].get<double>() && cy >= y && cy <= y + ob[3].get<double>()) {
      return true;
    }
  }
  if (!places) return false;
  const double width = seen.value("width", 640.0);
  const double focal = width / 2 / std::tan(kGuardFieldOfViewDeg / 2 * kGuardPi / 180);
  const double bearing = -std::atan((cx - width / 2) / focal) * 180 / kGuardPi;
  const double distance = focal * kGuardFaceHeightM / std::max(1.0, box[3].get<double>());
  return places->screen_at(bearing, distance).has_value();
}

GuardState guard_state_from_json(const std::string& text) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    throw std::invalid_argument("the guard state is not JSON (byte " + std::to_string(e.byte) +
                                ")");
  }
  using Json = nlohmann::json;
  auto field = [&](const char* name, bool (Json::*is_type)() const noexcept) -> const Json& {
    if (!j.is_object() || !j.contains(name) || !(j[name].*is_type)()) {
      throw std::invalid_argument(std::string("the guard state's '") + name +
                                  "' is missing or of the wrong type");
    }
    return j[name];
  };
  GuardState s;
  s.on = field("on", &Json::is_boolean).get<bool>();
  s.since_ms = field("since_unix_ms", &Json::is_number_integer).get<std::int64_t>();
  s.alerts = field("alerts", &Json::is_number_integer).get<int>();
  s.by = field("by", &Json::is_string).get<std::string>();
  if (j.contains("pictures")) s.pictures = field("pictures", &Json::is_number_integer).get<int>();
  return s;
}

void Guard::tell(const GuardState& s) {
  if (!options_.changed) return;
  try {
    options_.changed(s);
  } catch (const std::exception& e) {
    log(LogLevel::kWarning, "guard", std::string("state not kept: ") + e.what());
  }
}

GuardState Guard::on() {
  std::unique_lock lock(mutex_);
  if (state_.on) return state_;
  if (thread_.joinable()) {  // a previous watch is still ending
    lock.unlock();
    thread_.join();
    lock.lock();
  }
  state_ = GuardState{true, now_ms_(), 0, ""};
  if (options_.watch) thread_ = std::thread([this] { run(); });
  const GuardState s = state_;
  lock.unlock();
  tell(s);
  return s;
}

GuardState Guard::off(const std::string& by) {
  std::thread ending;
  GuardState s;
  {
    std::lock_guard lock(mutex_);
    state_.on = false;
    state_.by = by;
    s = state_;
    ending = std::move(thread_);
  }
  wake_.notify_all();
  if (ending.joinable()) ending.join();
  tell(s);
  return s;
}

GuardState Guard::state() {
  std::lock_guard lock(mutex_);
  return state_;
}

bool Guard::wait(std::chrono::milliseconds robot_ms) {
  const double scale = options_.time_scale > 0 ? options_.time_scale : 1.0;
  const auto wall = std::chrono::microseconds(
      static_cast<std::int64_t>(static_cast<double>(robot_ms.count()) * 1000.0 / scale));
  std::unique_lock lock(mutex_);
  return wake_.wait_for(lock, wall, [this] { return !state_.on || quit_; });
}

void Guard::run() {
  int streak = 0, looks = 0;
  bool alerted_here = false;  // one alert per stop
  while (!wait(options_.look)) {
    if (options_.off_requested) {
      GuardState s = state();
      bool off = false;
      try {
        off = s.on && options_.off_requested(s);
      } catch (const std::exception& e) {
        log(LogLevel::kWarning, "guard", std::string("cannot read an off request: ") + e.what());
      }
      if (off) {
        {
          std::lock_guard lock(mutex_);
          if (!state_.on) break;  // off() meanwhile: it tells
          state_.on = false;
          state_.by = kOffByCommandLine;
          s = state_;
        }
        tell(s);
        break;
      }
    }
    std::string seen;
    try {
      seen = eyes_.look_json();
    } catch (const std::exception& e) {
      log(LogLevel::kWarning, "guard",
          e.what());  // a camera failure: try again later
      streak = 0;
      continue;
    }
    int unknown = 0, pictures = 0;
    const nlohmann::json look = nlohmann::json::parse(seen);
    for (const auto& f : look.value("faces", nlohmann::json::array())) {
      const auto box = f.value("box", nlohmann::json::array());
      const double h = box.size() == 4 ? box[3].get<double>() : 0;
      if (!f.value("name", "").empty() || h < options_.min_face_px) continue;
      if (is_picture(f, look, places_)) {
        ++pictures;
      } else {
        ++unknown;
      }
    }
    if (pictures > 0 && unknown == 0) {
      GuardState now;
      {
        std::lock_guard lock(mutex_);
        if (!state_.on) break;
        ++state_.pictures;
        now = state_;
      }
      // Told (and so stored) at the first and every 20th, not at every look.
      if (now.pictures == 1 || now.pictures % 20 == 0) tell(now);
    }
    streak = unknown > 0 ? streak + 1 : 0;
    if (streak >= options_.frames_needed && !alerted_here) {
      alerted_here = true;
      std::string photo;
      try {
        photo = eyes_.capture_photo("guard");
      } catch (const std::exception& e) {
        log(LogLevel::kWarning, "guard", std::string("no photo of the intruder: ") + e.what());
      }
      GuardState now;
      {
        std::lock_guard lock(mutex_);
        if (!state_.on) break;
        ++state_.alerts;
        now = state_;
      }
      tell(now);
      alert_(photo, unknown == 1 ? "someone I don't know"
                                 : std::to_string(unknown) + " people I don't know");
    }
    if (++looks >= options_.looks_per_stop && options_.looks_per_stop > 0 && places_ &&
        options_.turn_deg != 0 && streak == 0) {
      looks = 0;
      alerted_here = false;
      places_->turn(options_.turn_deg, [this](std::chrono::milliseconds ms) { return wait(ms); });
    }
  }
}

}  // namespace marvin::skills
