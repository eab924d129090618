#include "navigation/sonar_sweep.h"

#include <cmath>

#include "navigation/geometry.h"

namespace marvin::navigation {
namespace {

constexpr double kSweepNoEchoM = 2.5;  // the sonar's cap: nothing within range
constexpr double kSweepTallM = 0.35;   // echoes higher than this above the sonar: tall
constexpr double kSweepSameM = 0.15;   // echoes this close in D_x are the same thing

}  // namespace

Echo classify_echo(double angle_deg, double distance_m, double sonar_height_m) {
  Echo e;
  if (distance_m >= kSweepNoEchoM) return e;
  const double t = angle_deg * kPi / 180.0;
  e.ahead_m = distance_m * std::cos(t);
  e.height_m = distance_m * std::sin(t);
  if (angle_deg >= -1) {
    e.kind = Echo::Kind::kSomething;
    return e;
  }
  // The floor's echo, with room for the noise (1 cm + 1 %) and a tilted floor: a step
  // down must be at least ~5 cm deep to be told.
  const double floor_m = sonar_height_m / std::sin(-t);
  if (distance_m < floor_m * 0.85 - 0.03) {
    e.kind = Echo::Kind::kSomething;
  } else if (distance_m > floor_m * 1.15 + 0.03) {
    e.kind = Echo::Kind::kStepDown;
    e.ahead_m = floor_m * std::cos(t);
    e.height_m = -sonar_height_m;
  } else {
    e.kind = Echo::Kind::kFloor;
  }
  return e;
}

Ahead classify_sweep(const std::vector<devices::ScanPoint>& scan, double sonar_height_m,
                     double range_m) {
  Ahead a;
  double nearest = range_m, drop = range_m;
  std::vector<Echo> things;
  for (const devices::ScanPoint& p : scan) {
    if (p.angle_deg < -90 || p.angle_deg > 90) continue;
    const Echo e = classify_echo(p.angle_deg, p.distance_m, sonar_height_m);
    if (e.kind == Echo::Kind::kStepDown && e.ahead_m < drop) drop = e.ahead_m;
    if (e.kind != Echo::Kind::kSomething) continue;
    things.push_back(e);
    if (e.ahead_m < nearest) nearest = e.ahead_m;
  }
  if (drop < range_m && drop <= nearest) {
    a.kind = Ahead::Kind::kStepDown;
    a.distance_m = drop;
    return a;
  }
  if (nearest >= range_m) return a;
  a.distance_m = nearest;
  a.kind = Ahead::Kind::kLow;
  for (const Echo& e : things) {
    if (std::fabs(e.ahead_m - nearest) < kSweepSameM && e.height_m > kSweepTallM)
      a.kind = Ahead::Kind::kWall;
  }
  return a;
}

const char* to_words(Ahead::Kind kind) {
  switch (kind) {
    case Ahead::Kind::kWall:
      return "a wall or something tall";
    case Ahead::Kind::kLow:
      return "something low";
    case Ahead::Kind::kStepDown:
      return "a step down";
    case Ahead::Kind::kClear:
      break;
  }
  return "nothing";
}

}  // namespace marvin::navigation
