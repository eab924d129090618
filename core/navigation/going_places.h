// Going places as skills see it (through the Robot API, core/skills/host_api.h): the
// interface the navigator implements, and the mock robot scripts for skills' tests.
// Header-only, so the skill layer needs no navigation library.
#pragma once

#include <chrono>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace marvin::navigation {

struct GoResult {
  enum class Outcome { kArrived, kUnknownPlace, kGaveUp, kCancelled } outcome = Outcome::kArrived;
  std::string target;  // as the map spells it ("kitchen", "the sofa", "Anna")
  std::string reason;  // for kUnknownPlace / kGaveUp: "the kitchen door is blocked"
  bool arrived() const { return outcome == Outcome::kArrived; }
};

// Waits `ms` of robot time between two control steps; returns true when the request was
// cancelled meanwhile (the user said "stop"), which must end the wait at once.
using WaitFn = std::function<bool(std::chrono::milliseconds)>;

// What skills reach through the Robot API (core/skills/host_api.h).
class GoingPlaces {
 public:
  virtual ~GoingPlaces() = default;
  // Drives to `target` (a room, place or person); returns when there, given up or cancelled.
  virtual GoResult go_to(std::string_view target, const WaitFn& wait) = 0;
  // Stops the wheels now; a running go_to() returns kCancelled at its next step.
  virtual void stop() = 0;
  // Robot seconds per wall-clock second (a simulation run with --speed N: N). The host
  // waits wall time step / time_scale() between control steps.
  virtual double time_scale() const { return 1.0; }
  // The names go_to() knows, as a user would say them ("the kitchen", "kitchen", "the sofa",
  // "Anna", "me"): what the speech recogniser listens for after "go to".
  virtual std::vector<std::string> place_names() const { return {}; }
  // The room the robot believes it is in; nullopt between rooms (a doorway) or outside.
  virtual std::optional<std::string> where_am_i() = 0;

  // --- finding (API 1.3); the defaults are a robot without a map ---------------------
  // Turns in place by `degrees` (counter-clockwise positive); false when cancelled.
  virtual bool turn(double degrees, const WaitFn& wait) {
    (void)degrees;
    (void)wait;
    return false;
  }
  // Where something seen `bearing_deg` off the robot's heading (left positive) about
  // `distance_m` away is: the room it is in and the nearest furniture or place within
  // 1.5 m ("kitchen table"; "" when none). nullopt without a map.
  struct Spot {
    std::string room;
    std::string near;
  };
  virtual std::optional<Spot> locate(double bearing_deg, double distance_m) {
    (void)bearing_deg;
    (void)distance_m;
    return std::nullopt;
  }
  // Every room, in the order a search visits them from where the robot is: the room it is
  // in first, then the nearest of the rest each time (by straight line between spots).
  virtual std::vector<std::string> rooms_to_search() { return {}; }
  // The screen (a TV: furniture the map marks "screen") something seen `bearing_deg` off the
  // heading about `distance_m` away is at, by its name; nullopt when at none (or no map).
  // Guard mode takes a face there for a picture. Additive in session 9: no API change.
  virtual std::optional<std::string> screen_at(double bearing_deg, double distance_m) {
    (void)bearing_deg;
    (void)distance_m;
    return std::nullopt;
  }
  // What a name the user said is on the map: {"Anna", "person", "living room"},
  // {"the sofa", "place", "living room"}, {"kitchen", "room", "kitchen"}; nullopt if unknown.
  struct PlaceInfo {
    std::string name, kind, room;
  };
  virtual std::optional<PlaceInfo> find_place(std::string_view name) {
    (void)name;
    return std::nullopt;
  }
  // Metres along the path the robot would drive to `name` from where it is now ("how far is
  // the kitchen"); nullopt when the map does not know the name, no path leads there, or the
  // robot is driving (its planner is busy).
  virtual std::optional<double> path_length_to(std::string_view name) {
    (void)name;
    return std::nullopt;
  }

  // --- guiding (API 1.4) ---------------------------------------------------------------
  // One thing worth telling a person being led, between two control steps:
  //   "start"     the path is planned: distance_left_m along it
  //   "turn"      the next turn of the path, `turn` "left"/"right", distance_m ahead
  //   "obstacle"  the sonar found something distance_m ahead (horizontal), `kind` "wall"
  //               (echoes from high up too) or "low" (below the knees); `stopped` when the
  //               robot stopped for it (it then plans around it)
  //   "step_down" the floor drops distance_m ahead; the robot stopped and avoids it
  struct GuideEvent {
    std::string event, turn, kind;
    double distance_m = 0, distance_left_m = 0, bearing_deg = 0;
    bool stopped = false;
  };
  // Returns false to stop (guide_to then returns kCancelled, the wheels stopped).
  using GuideFn = std::function<bool(const GuideEvent&)>;
  // go_to() at `speed_factor` (0.1..1) of the normal driving speed, telling `on_event`
  // what happens on the way. The default (a robot without a navigator of its own) goes at
  // its normal speed and tells nothing.
  virtual GoResult guide_to(std::string_view target, double speed_factor, const GuideFn& on_event,
                            const WaitFn& wait) {
    (void)speed_factor;
    (void)on_event;
    return go_to(target, wait);
  }
};

}  // namespace marvin::navigation
