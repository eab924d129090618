#include "navigation/navigator.h"

#include <algorithm>
#include <cctype>
#include <cmath>

#include "navigation/sonar_sweep.h"

namespace marvin::navigation {
namespace {

double degrees(double rad) { return rad * 180.0 / kPi; }
double radians(double deg) { return deg * kPi / 180.0; }

std::string with_the(const std::string& name) {
  if (name.rfind("the ", 0) == 0 || name.empty()) return name;
  if (std::isupper(static_cast<unsigned char>(name[0]))) return name;  // a person
  return "the " + name;
}

// The path cut where it first comes within `keep_m` of `at` (unchanged if it never does, or
// already starts that close).
std::vector<Vec2> stop_short(std::vector<Vec2> path, Vec2 at, double keep_m) {
  if (path.size() < 2 || distance(path.front(), at) <= keep_m) return path;
  for (std::size_t i = 1; i < path.size(); ++i) {
    const Vec2 a = path[i - 1], b = path[i];
    if (distance(b, at) > keep_m) continue;
    // The point on ab at keep_m from `at` (bisection: the distance falls along ab here).
    double lo = 0, hi = 1;
    for (int k = 0; k < 30; ++k) {
      const double mid = (lo + hi) / 2;
      (distance(a + (b - a) * mid, at) > keep_m ? lo : hi) = mid;
    }
    path.resize(i);
    path.push_back(a + (b - a) * hi);
    return path;
  }
  return path;
}

// Metres along `path` from `from` through waypoints i.. to the end.
double length_left(const std::vector<Vec2>& path, std::size_t i, Vec2 from) {
  double total = 0;
  for (; i < path.size(); ++i) {
    total += distance(from, path[i]);
    from = path[i];
  }
  return total;
}

}  // namespace

Navigator::Navigator(FloorMap map, devices::Body& body, PoseSource pose, ScanSource scan,
                     Clock now_ms, NavigatorOptions options)
    : map_(std::move(map)),
      body_(body),
      pose_(std::move(pose)),
      scan_(std::move(scan)),
      now_ms_(std::move(now_ms)),
      options_(options),
      grid_(map_, options.cell_m, options.inflate_m) {}

std::optional<std::vector<Vec2>> Navigator::plan(Vec2 from, Vec2 to) {
  std::lock_guard lock(run_mutex_);
  return planner_.plan(grid_, from, to);
}

std::vector<Vec2> Navigator::path() const {
  std::lock_guard lock(path_mutex_);
  return path_;
}

std::vector<std::string> Navigator::place_names() const {
  std::vector<std::string> names;
  auto add = [&](const std::string& name) {
    const std::string plain = normalise_name(name);  // "the sofa" -> "sofa"
    names.push_back(plain);
    names.push_back("the " + plain);
  };
  for (const Room& r : map_.rooms) add(r.name);
  for (const auto& [word, room] : room_synonyms()) {
    if (map_.find(word)) add(word);  // "the toilet", when the map has a bathroom
  }
  for (const Place& p : map_.places) add(p.name);
  for (const Place& p : map_.people) names.push_back(p.name);
  if (!map_.owner.empty()) names.push_back("me");
  return names;
}

void Navigator::stop() {
  stop_requested_.store(true);
  body_.stop();
}

std::optional<std::string> Navigator::where_am_i() {
  const Room* room = map_.room_at(pose_().position());
  if (!room) return std::nullopt;
  return room->name;
}

GoResult Navigator::go_to(std::string_view name, const WaitFn& wait) {
  return go(name, wait, 1.0, nullptr);
}

GoResult Navigator::guide_to(std::string_view name, double speed_factor, const GuideFn& on_event,
                             const WaitFn& wait) {
  return go(name, wait, std::clamp(speed_factor, 0.1, 1.0), on_event ? &on_event : nullptr);
}

bool Navigator::tell(const GuideEvent& event) { return !on_event_ || (*on_event_)(event); }

GoResult Navigator::go(std::string_view name, const WaitFn& wait, double speed_factor,
                       const GuideFn* on_event) {
  std::lock_guard lock(run_mutex_);
  driver_.store(std::this_thread::get_id());
  struct ClearDriver {
    std::atomic<std::thread::id>& driver;
    ~ClearDriver() { driver.store(std::thread::id()); }
  } clear_driver{driver_};
  stop_requested_.store(false);
  speed_factor_ = speed_factor;
  on_event_ = on_event;
  told_obstacle_ms_ = -1000000;
  told_drops_.clear();
  GoResult result;
  std::optional<Target> target = map_.find(name);
  if (!target) {
    result.outcome = GoResult::Outcome::kUnknownPlace;
    result.target = std::string(name);
    result.reason = "I don't know where " + with_the(std::string(name)) + " is";
    return result;
  }
  result.target = target->name;
  grid_.clear_obstacles();
  seen_.clear();
  drops_.clear();
  const std::int64_t deadline =
      now_ms_() + static_cast<std::int64_t>(options_.give_up_after_s * 1000);
  for (int attempt = 0; attempt <= options_.max_replans; ++attempt) {
    const Vec2 from = pose_().position();
    std::optional<std::vector<Vec2>> path = planner_.plan(grid_, from, target->at);
    if (!path) {
      body_.stop();
      result.outcome = GoResult::Outcome::kGaveUp;
      result.reason = blocked_reason(*target);
      return result;
    }
    // A person: stop at arm's length, facing them, not on their toes (the camera then
    // sees their whole face).
    if (target->kind == Target::Kind::kPerson) *path = stop_short(*path, target->at, 0.7);
    if (attempt == 0) {
      GuideEvent start;
      start.event = "start";
      start.distance_left_m = length_left(*path, 1, from);
      if (!tell(start)) {
        body_.stop();
        result.outcome = GoResult::Outcome::kCancelled;
        result.reason = "stopped";
        return result;
      }
    }
    {
      std::lock_guard plock(path_mutex_);
      path_ = *path;
    }
    switch (follow(*path, wait, deadline)) {
      case Follow::kArrived:
        body_.stop();
        // A person: look at them ("who is this?" right after "go to Anna" sees her).
        if (target->kind == Target::Kind::kPerson) {
          const Vec2 to = target->at - pose_().position();
          if (length(to) > 0.05 && !turn_to(std::atan2(to.y, to.x), wait)) {
            result.outcome = GoResult::Outcome::kCancelled;
            result.reason = "stopped";
          }
        }
        return result;
      case Follow::kCancelled:
        body_.stop();
        result.outcome = GoResult::Outcome::kCancelled;
        result.reason = "stopped";
        return result;
      case Follow::kTimeOut:
        body_.stop();
        result.outcome = GoResult::Outcome::kGaveUp;
        result.reason = "it is taking too long to get to " + with_the(target->name);
        return result;
      case Follow::kBlocked:
        continue;  // re-plan around what the sonar saw
    }
  }
  body_.stop();
  result.outcome = GoResult::Outcome::kGaveUp;
  result.reason = blocked_reason(*target);
  return result;
}

bool Navigator::turn(double degrees_ccw, const WaitFn& wait) {
  std::lock_guard lock(run_mutex_);
  stop_requested_.store(false);
  // Big turns go in steps of at most 120 degrees, so the direction is never ambiguous.
  double left = radians(degrees_ccw);
  while (std::fabs(left) > 1e-9) {
    const double step = std::clamp(left, -radians(120), radians(120));
    if (!turn_to(wrap_angle(pose_().heading + step), wait)) return false;
    left -= step;
  }
  return true;
}

bool Navigator::turn_to(double heading, const WaitFn& wait) {
  const auto move_ms = options_.step * 3;
  const std::int64_t deadline = now_ms_() + 20000;
  while (true) {
    if (stop_requested_.load() || wait(options_.step) || stop_requested_.load()) {
      body_.stop();
      return false;
    }
    const double err = wrap_angle(heading - pose_().heading);
    if (std::fabs(degrees(err)) <= options_.aim_deg / 2 || now_ms_() > deadline) break;
    const std::uint8_t speed =
        std::fabs(degrees(err)) > 30 ? options_.turn_speed : options_.fine_turn_speed;
    body_.move(err > 0 ? devices::Direction::kLeft : devices::Direction::kRight, speed, move_ms);
  }
  body_.stop();
  return true;
}

std::optional<GoingPlaces::Spot> Navigator::locate(double bearing_deg, double distance_m) {
  const Pose pose = pose_();
  const double a = pose.heading + radians(bearing_deg);
  const Vec2 dir{std::cos(a), std::sin(a)};
  // The camera does not see through walls: an estimate behind the first wall along the
  // bearing (a box cut by the frame's edge looks smaller, so farther) is pulled back to
  // 10 cm in front of it.
  auto behind_wall = [&](double t) {
    const Vec2 p = pose.position() + dir * t;
    for (const Segment& w : map_.walls) {
      if (segments_intersect(pose.position(), p, w.a, w.b)) return true;
    }
    return false;
  };
  double reach = distance_m;
  if (behind_wall(reach)) {
    double lo = 0, hi = reach;
    for (int i = 0; i < 20; ++i) (behind_wall((lo + hi) / 2) ? hi : lo) = (lo + hi) / 2;
    reach = std::max(0.0, lo - 0.1);
  }
  const Vec2 at = pose.position() + dir * reach;
  Spot spot;
  // The thing's room; when the estimate falls outside every room (behind a wall, a bad
  // distance), the robot's own room.
  const Room* room = map_.room_at(at);
  if (!room) room = map_.room_at(pose.position());
  if (room) spot.room = room->name;
  double best = 1.5;
  auto consider = [&](const std::string& name, double d, const std::string& in_room) {
    if (d < best && (spot.room.empty() || in_room.empty() || in_room == spot.room)) {
      best = d;
      spot.near = normalise_name(name);
    }
  };
  for (const Furniture& f : map_.furniture) {
    const Vec2 c{std::clamp(at.x, f.box.min.x, f.box.max.x),
                 std::clamp(at.y, f.box.min.y, f.box.max.y)};
    const Room* fr = map_.room_at((f.box.min + f.box.max) * 0.5);
    consider(f.name, distance(c, at), fr ? fr->name : "");
  }
  for (const Place& p : map_.places) consider(p.name, distance(p.at, at) + 0.2, p.room);
  return spot;
}

std::optional<GoingPlaces::PlaceInfo> Navigator::find_place(std::string_view name) {
  std::optional<Target> t = map_.find(name);
  if (!t) return std::nullopt;
  static const char* kKinds[] = {"room", "place", "person"};
  return PlaceInfo{t->name, kKinds[static_cast<int>(t->kind)], t->room};
}

std::optional<double> Navigator::path_length_to(std::string_view name) {
  std::optional<Target> target = map_.find(name);
  if (!target) return std::nullopt;
  // Not while driving: go() holds the lock for the whole drive and owns the grid (asked from
  // the driving thread itself, by a guide callback, trying the lock would be undefined).
  if (driver_.load() == std::this_thread::get_id()) return std::nullopt;
  std::unique_lock lock(run_mutex_, std::try_to_lock);
  if (!lock.owns_lock()) return std::nullopt;
  const Vec2 from = pose_().position();
  std::optional<std::vector<Vec2>> path = planner_.plan(grid_, from, target->at);
  if (!path) return std::nullopt;
  if (target->kind == Target::Kind::kPerson) *path = stop_short(*path, target->at, 0.7);
  return length_left(*path, 1, from);
}

// At a screen: the bearing within the box's extent as the robot sees it (corners, 3 degrees
// more each side for the pose's error), and the distance within the box's nearest and
// farthest points, with room for the error of a distance told from a face's size (a face on
// a screen is rarely life-size: half to 1.5 times). A person standing beside the TV is at
// another bearing; one standing between the robot and the TV is closer than half its distance
// (or hides it); one right in front of it is taken for the picture (sim/README.md).
std::optional<std::string> Navigator::screen_at(double bearing_deg, double distance_m) {
  const Pose pose = pose_();
  for (const Furniture& f : map_.furniture) {
    if (!f.screen) continue;
    // Angles relative to the box's centre as the robot sees it: no wrap-around at +-pi.
    const Vec2 mid = (f.box.min + f.box.max) * 0.5 - pose.position();
    const double centre = std::atan2(mid.y, mid.x);
    const double seen = std::remainder(pose.heading + radians(bearing_deg) - centre, 2 * kPi);
    const Vec2 corners[] = {
        f.box.min, {f.box.max.x, f.box.min.y}, f.box.max, {f.box.min.x, f.box.max.y}};
    double lo = 1e9, hi = -1e9, far = 0;
    for (Vec2 c : corners) {
      const Vec2 d = c - pose.position();
      const double a = std::remainder(std::atan2(d.y, d.x) - centre, 2 * kPi);
      lo = std::min(lo, a);
      hi = std::max(hi, a);
      far = std::max(far, std::hypot(d.x, d.y));
    }
    const Vec2 nearest{std::clamp(pose.x, f.box.min.x, f.box.max.x),
                       std::clamp(pose.y, f.box.min.y, f.box.max.y)};
    const double near = distance(nearest, pose.position());
    const double margin = radians(3);
    if (seen >= lo - margin && seen <= hi + margin && distance_m >= 0.5 * near &&
        distance_m <= 1.5 * far) {
      return normalise_name(f.name);
    }
  }
  return std::nullopt;
}

std::vector<std::string> Navigator::rooms_to_search() {
  std::vector<const Room*> left;
  for (const Room& r : map_.rooms) left.push_back(&r);
  std::vector<std::string> order;
  Vec2 from = pose_().position();
  if (const Room* here = map_.room_at(from)) {
    order.push_back(here->name);
    from = here->spot;
    std::erase(left, here);
  }
  while (!left.empty()) {
    auto next = std::min_element(left.begin(), left.end(), [&](const Room* a, const Room* b) {
      return distance(a->spot, from) < distance(b->spot, from);
    });
    order.push_back((*next)->name);
    from = (*next)->spot;
    left.erase(next);
  }
  return order;
}

bool Navigator::leg_free(Vec2 from, Vec2 to) const {
  // Cells within the inflation radius of the robot itself do not count: it stands there.
  const double len = distance(from, to);
  for (double t = options_.inflate_m; t < len; t += options_.cell_m) {
    if (grid_.blocked(grid_.cell_of(from + (to - from) * (t / len)))) return false;
  }
  return true;
}

std::string Navigator::blocked_reason(const Target& target) {
  const std::string where = with_the(target.name);
  if (!grid_.has_obstacles()) return "I can't find a way to " + where;
  if (!drops_.empty()) return "there is a step down on the way to " + where;
  // Without what the sonar found there is a way: name the door nearest to the obstacles.
  const Door* nearest = nullptr;
  double best = 1.0;  // metres: farther than this, it is not "the door" that is blocked
  for (const Door& d : map_.doors) {
    if (!d.open) continue;
    const Vec2 mid = (d.a + d.b) * 0.5;
    for (Vec2 p : seen_) {
      double dist = distance(p, mid);
      if (dist < best) {
        best = dist;
        nearest = &d;
      }
    }
  }
  if (nearest) return with_the(nearest->name) + " is blocked";
  return "something is in the way to " + where;
}

Navigator::Follow Navigator::follow(const std::vector<Vec2>& path, const WaitFn& wait,
                                    std::int64_t deadline_ms) {
  const auto step_ms = options_.step;
  const auto move_ms = step_ms * 3;  // outlives one missed step; the next step replaces it
  std::int64_t aimed_since = now_ms_();
  bool driving_forward = false;
  Vec2 progress_at = pose_().position();
  std::int64_t progress_ms = now_ms_();
  const auto forward_speed =
      static_cast<std::uint8_t>(std::max(30.0, std::round(options_.forward_speed * speed_factor_)));
  for (std::size_t i = 1; i < path.size(); ++i) {
    const Vec2 wp = path[i];
    const bool last = i + 1 == path.size();
    // The turn at this waypoint (guiding: told once, when it is announce_m ahead).
    double turn_deg = 0;
    if (!last) {
      const Vec2 in = wp - path[i - 1], out = path[i + 1] - wp;
      turn_deg = degrees(wrap_angle(std::atan2(out.y, out.x) - std::atan2(in.y, in.x)));
    }
    // Only real corners are told: a turn of 35° or more after a leg of 0.8 m or more (the
    // short legs of a path planned around something would be a stream of turns).
    bool turn_told = std::fabs(turn_deg) < 35 || distance(path[i - 1], wp) < 0.8;
    while (true) {
      if (stop_requested_.load() || wait(step_ms) || stop_requested_.load()) {
        body_.stop();
        return Follow::kCancelled;
      }
      const std::int64_t now = now_ms_();
      if (now > deadline_ms) return Follow::kTimeOut;
      const Pose pose = pose_();
      const Vec2 to = wp - pose.position();
      const double dist = length(to);
      if (dist < (last ? options_.goal_m : options_.waypoint_m)) break;
      if (!turn_told && dist < options_.announce_m) {
        turn_told = true;
        GuideEvent e;
        e.event = "turn";
        e.turn = turn_deg > 0 ? "left" : "right";
        e.distance_m = dist;
        e.bearing_deg = turn_deg;
        e.distance_left_m = length_left(path, i, pose.position());
        if (!tell(e)) {
          body_.stop();
          return Follow::kCancelled;
        }
      }
      // Stuck (a collision the base reported by stopping, or wheels slipping): treat
      // like an obstacle ahead.
      if (distance(pose.position(), progress_at) > 0.05) {
        progress_at = pose.position();
        progress_ms = now;
      } else if (now - progress_ms > 8000) {
        body_.stop();
        Vec2 ahead{pose.x + std::cos(pose.heading) * 0.3, pose.y + std::sin(pose.heading) * 0.3};
        seen_.push_back(ahead);
        grid_.add_obstacle(ahead, options_.mark_radius_m);
        return Follow::kBlocked;
      }
      const double err = wrap_angle(std::atan2(to.y, to.x) - pose.heading);
      if (std::fabs(degrees(err)) > options_.aim_deg) {
        driving_forward = false;
        const std::uint8_t speed =
            std::fabs(degrees(err)) > 30 ? options_.turn_speed : options_.fine_turn_speed;
        body_.move(err > 0 ? devices::Direction::kLeft : devices::Direction::kRight, speed,
                   move_ms);
        continue;
      }
      if (!driving_forward) {
        driving_forward = true;
        aimed_since = now;  // sonar readings from before this heading point elsewhere
      }
      // What the sonar sees ahead goes on the map (things the plan did not show); something
      // close ahead stops the robot, and a leg the new marks block is planned again.
      // Downward readings tell a step down (the floor answers from farther than it should)
      // from the floor and from something standing on it (sonar_sweep.h).
      bool marked = false, stopped = false;
      std::optional<GuideEvent> news;  // the nearest new thing, for guiding
      for (const devices::ScanPoint& p : scan_()) {
        if (p.time_ms < aimed_since || p.angle_deg > 60) continue;
        const Echo echo = classify_echo(p.angle_deg, p.distance_m, options_.sonar_height_m);
        if (echo.kind == Echo::Kind::kNone || echo.kind == Echo::Kind::kFloor) continue;
        const bool drop = echo.kind == Echo::Kind::kStepDown;
        const double horizontal = echo.ahead_m;
        if (echo.height_m > options_.clearance_m || horizontal > options_.mark_m) continue;
        const Vec2 hit{pose.x + std::cos(pose.heading) * horizontal,
                       pose.y + std::sin(pose.heading) * horizontal};
        const double stop_m = drop ? options_.step_down_stop_m : options_.stop_m;
        const bool stop = horizontal < stop_m && horizontal < dist + 0.15;
        bool new_mark = false;
        // An echo from a wall or furniture of the map (it can land a cell short of it) is
        // not news: marking it again, inflated, narrows doors the plan needs (a downward ray
        // that meets a door jamb's foot did that: guidance found "the kitchen door is
        // blocked"). A step down is always marked; anything close ahead still stops below.
        const bool on_map = grid_.near_static(hit, 0.15);
        if (!grid_.occupied(grid_.cell_of(hit)) && (drop || !on_map)) {
          grid_.add_obstacle(hit, options_.mark_radius_m);
          seen_.push_back(hit);
          if (drop) {
            // The edge of a step runs across: mark it to either side too, so the robot
            // does not go around the one spot it saw (and in sideways, where a wall hides
            // the floor from the sonar).
            drops_.push_back(hit);
            const Vec2 across{-std::sin(pose.heading), std::cos(pose.heading)};
            for (int k = -6; k <= 6; ++k) {
              grid_.add_obstacle(hit + across * (options_.step_down_side_m * k / 6.0),
                                 options_.mark_radius_m);
            }
          }
          marked = new_mark = true;
        }
        // Told: what is new within announce_m, not a wall or furniture of the map (an echo
        // from it can land a cell short of it), nor a step down already told within 1 m.
        const bool told_before =
            drop && std::any_of(told_drops_.begin(), told_drops_.end(),
                                [&](Vec2 d) { return distance(d, hit) < 1.0; });
        if ((new_mark || stop) && !on_map && !told_before && horizontal < options_.announce_m &&
            (!news || horizontal < news->distance_m)) {
          news.emplace();
          news->event = drop ? "step_down" : "obstacle";
          news->kind = drop ? "step" : echo.height_m > 0.35 ? "wall" : "low";
          news->distance_m = horizontal;
        }
        if (stop) {
          stopped = true;
          body_.stop();
          if (!new_mark) {
            seen_.push_back(hit);
            if (drop) drops_.push_back(hit);
            grid_.add_obstacle(hit, options_.mark_radius_m);
          }
          break;
        }
      }
      // Told sparingly: a step down always, other things at most every 3 s of robot time
      // (and always when the robot stops for one).
      if (news) news->stopped = stopped;
      if (news && news->event == "step_down") {
        told_drops_.push_back({pose.x + std::cos(pose.heading) * news->distance_m,
                               pose.y + std::sin(pose.heading) * news->distance_m});
      }
      if (news && (news->event == "step_down" || news->stopped || now - told_obstacle_ms_ > 3000)) {
        told_obstacle_ms_ = now;
        news->distance_left_m = length_left(path, i, pose.position());
        if (!tell(*news)) {
          body_.stop();
          return Follow::kCancelled;
        }
      }
      if (stopped) return Follow::kBlocked;
      if (marked && !leg_free(pose.position(), wp)) {
        body_.stop();
        return Follow::kBlocked;
      }
      body_.move(devices::Direction::kForward, forward_speed, move_ms);
    }
  }
  return Follow::kArrived;
}

}  // namespace marvin::navigation
