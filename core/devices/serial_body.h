// Body over the serial link: the real base, or marvin-mcu-sim through its pseudo-terminal.
#pragma once

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <string>

#include "devices/body.h"
#include "devices/head_servo.h"
#include "devices/motor_base.h"
#include "devices/serial_link.h"
#include "devices/sonar_scanner.h"
#include "devices/status_light.h"

namespace marvin::devices {

// Owns the link and the devices built on it. Reconnects by itself; after each (re)connect
// it sends the head angle, light and sweep settings again (the MCU may have restarted).
// An obstacle fault or a lost link ends the current move; a turn starts the sonar's scan
// afresh (its readings so far point elsewhere). Thread-safe.
class SerialBody : public Body {
 public:
  // Opens `tty_path` (retrying until it appears), e.g. /dev/ttyACM0 or a pty link made by
  // marvin-mcu-sim --link.
  explicit SerialBody(const std::string& tty_path);
  explicit SerialBody(LinkOptions options, SweepSettings sweep = {});
  ~SerialBody() override;

  void move(Direction direction, std::uint8_t speed, std::chrono::milliseconds duration) override;
  void stop() override;
  void tilt_head(int degrees) override;
  std::vector<ScanPoint> latest_scan() override;
  void set_light(Light light) override;

  // Waits until the link is connected; false if `timeout` passed first. The body works
  // without it (commands are dropped while the link is down, state is re-sent on connect);
  // the host waits once at start so the first command is not lost.
  bool wait_connected(std::chrono::milliseconds timeout);

  SerialLink& link() { return link_; }
  MotorBase& motors() { return motors_; }
  SonarScanner& sonar() { return sonar_; }

 private:
  SerialLink link_;
  MotorBase motors_;
  HeadServo head_;
  SonarScanner sonar_;
  StatusLight light_;
  int state_callback_ = 0, telemetry_callback_ = 0;
  std::mutex connected_mutex_;  // with connected_changed_: wait_connected()
  std::condition_variable connected_changed_;
};

}  // namespace marvin::devices
