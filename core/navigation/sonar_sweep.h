// What the sonar's sweep says about the way ahead. The sonar sweeps in the vertical plane
// of the heading, down as well as up: a reading at tilt θ (above level; negative looks
// down) and slant distance D hit something D_x = D cos θ ahead and D_y = D sin θ above the
// sonar. (The issue, after the original paper, writes D_y = D tan θ; the sonar measures
// the slant side, so the opposite side is D sin θ = D_x tan θ.)
//
// Looking down, a flat floor answers at D = h / sin|θ| (h: the sonar's height). A shorter
// echo is something standing on the floor; a clearly longer one means the floor is lower
// there: a step down. No echo at all is not taken for a step (the sonar loses echoes now
// and then, and a step down a few tens of centimetres deep answers well within range).
#pragma once

#include <vector>

#include "devices/body.h"

namespace marvin::navigation {

struct Echo {
  enum class Kind { kNone, kFloor, kSomething, kStepDown } kind = Kind::kNone;
  double ahead_m = 0;   // D_x; for kStepDown: where the floor should have been (in the drop)
  double height_m = 0;  // D_y, above the sonar (negative below it)
};

// One reading. Tilts below -1° are compared with the floor `sonar_height_m` below.
Echo classify_echo(double angle_deg, double distance_m, double sonar_height_m);

// The nearest thing ahead within `range_m` (horizontal), from one sweep (tilts -90..90).
struct Ahead {
  enum class Kind { kClear, kWall, kLow, kStepDown } kind = Kind::kClear;
  double distance_m = 0;  // horizontal; for kStepDown at most where the drop begins
};
// A wall (or anything tall): echoes at the same distance (within 0.15 m) from higher than
// 0.35 m above the sonar; low: only from below that. A step down nearer than every
// obstacle wins.
Ahead classify_sweep(const std::vector<devices::ScanPoint>& scan, double sonar_height_m,
                     double range_m);

// The words for it: "a wall or something tall", "something low", "a step down".
const char* to_words(Ahead::Kind kind);

}  // namespace marvin::navigation
