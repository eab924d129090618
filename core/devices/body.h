// The robot's physical parts as the skill platform sees them.
//
// One interface, several implementations: SerialBody (devices/serial_body.h) drives the
// real base, or marvin-mcu-sim through a pseudo-terminal, over the serial link; a
// console-only simulated body lives elsewhere. Implementations are thread-safe: any
// method may be called from any thread at any time, and stop() always wins.
#pragma once

#include <chrono>
#include <cstdint>
#include <vector>

namespace marvin::devices {

// The head's status LEDs.
enum class Light { kOff, kAwaiting /*red*/, kListening /*green*/, kExecuting /*yellow*/ };

enum class Direction { kForward, kBackward, kLeft, kRight };

// "off", "awaiting", "listening", "executing": the names logs and test recordings use.
inline const char* to_string(Light light) {
  static const char* const names[] = {"off", "awaiting", "listening", "executing"};
  return names[static_cast<int>(light)];
}
// "forward", "backward", "left", "right".
inline const char* to_string(Direction direction) {
  static const char* const names[] = {"forward", "backward", "left", "right"};
  return names[static_cast<int>(direction)];
}

// One filtered sonar point. angle_deg is the sweep angle above the horizontal in the
// vertical plane of the heading (0 = straight ahead, 90 = up, 120 = up and backwards);
// distance_m is the measured (slant) distance, capped at 2.5 m when nothing echoed;
// time_ms is when the host received the latest reading at that angle (steady clock, ms).
struct ScanPoint {
  double angle_deg;
  double distance_m;
  std::int64_t time_ms;
};

// The robot's physical parts, real (serial) or simulated. Implementations are thread-safe.
class Body {
 public:
  virtual ~Body() = default;
  // Starts moving and returns at once; the motion ends by itself after `duration`, on
  // stop(), on the next move(), or when the body's safety stops it (obstacle ahead, link
  // lost). Turning (kLeft/kRight) is in place. speed: 0..255 (0 stops).
  virtual void move(Direction direction, std::uint8_t speed,
                    std::chrono::milliseconds duration) = 0;
  // Stops every motor now.
  virtual void stop() = 0;
  // Tilts the head: degrees above level, clamped to -60..60.
  virtual void tilt_head(int degrees) = 0;
  // The latest obstacle scan, one point per sweep angle, ordered by angle.
  virtual std::vector<ScanPoint> latest_scan() = 0;
  virtual void set_light(Light light) = 0;
};

}  // namespace marvin::devices
