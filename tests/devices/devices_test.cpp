// Host devices without a device: telemetry decoding, the median filter, the scan, the
// link's behaviour while the tty is absent.
#include <doctest/doctest.h>

#include <filesystem>

#include "devices/motor_base.h"
#include "devices/serial_body.h"
#include "devices/serial_link.h"
#include "devices/sonar_scanner.h"
#include "devices/status_light.h"

using namespace marvin::devices;

namespace {
mv_frame ext(std::uint8_t type, std::vector<std::uint8_t> payload) {
  mv_frame f{};
  f.type = type;
  f.len = static_cast<std::uint8_t>(payload.size());
  for (std::size_t i = 0; i < payload.size(); ++i) f.payload[i] = payload[i];
  return f;
}
}  // namespace

TEST_CASE("telemetry frames decode into their structs") {
  Telemetry t;
  std::uint8_t d[2], tm[4];
  mv_put14(d, 1234);
  mv_put28(tm, 987654);
  REQUIRE(decode_telemetry(ext(MV_SONAR_READING, {30, 0, d[0], d[1], tm[0], tm[1], tm[2], tm[3]}),
                           5, &t));
  auto r = std::get<SonarReading>(t);
  CHECK(r.angle_deg == 30);
  CHECK(r.distance_mm == 1234);
  CHECK(r.echo);
  CHECK(r.mcu_time_ms == 987654);
  CHECK(r.host_time_ms == 5);
  REQUIRE(decode_telemetry(
      ext(MV_FAULT, {MV_FAULT_DEADMAN, d[0], d[1], tm[0], tm[1], tm[2], tm[3]}), 0, &t));
  CHECK(std::get<Fault>(t).code == MV_FAULT_DEADMAN);
  std::uint8_t left[2], right[2];
  mv_put14(left, 0x100 | 200);
  mv_put14(right, 17);
  REQUIRE(decode_telemetry(ext(MV_STATUS, {left[0], left[1], right[0], right[1], 64 - 10,
                                           MV_STATUS_BLOCKED, 0, 2, tm[0], tm[1], tm[2], tm[3]}),
                           0, &t));
  auto s = std::get<Status>(t);
  CHECK(s.left_speed == 200);
  CHECK(s.left_backward);
  CHECK(s.right_speed == 17);
  CHECK_FALSE(s.right_backward);
  CHECK(s.head_deg == -10);
  CHECK(s.blocked);
  CHECK_FALSE(s.sweeping);
  CHECK(s.rx_errors == 2);
  CHECK_FALSE(decode_telemetry(ext(MV_PING, {}), 0, &t));  // a command, not telemetry
}

TEST_CASE("the median filter ignores single wild echoes") {
  MedianFilter m(5);
  for (int v : {1000, 1010, 990}) m.add(v);
  CHECK(m.median() == 1000);
  CHECK(m.add(2500) == 1000);              // one missed echo
  CHECK(m.add(30) == 1000);                // one multipath short echo
  for (int i = 0; i < 3; ++i) m.add(500);  // a real change wins after 3 of 5
  CHECK(m.median() == 500);
}

TEST_CASE("the scan keeps one filtered point per angle, drops stale ones, ordered by angle") {
  SerialLink link(LinkOptions{"/nonexistent/marvin-tty"});
  SonarScanner scanner(link, 3, std::chrono::milliseconds(1000));
  scanner.add({30, 800, true, 0, 1000});
  scanner.add({0, 400, true, 0, 1000});
  scanner.add({0, 2500, false, 0, 1100});
  scanner.add({0, 410, true, 0, 1200});
  auto scan = scanner.latest_scan(1500);  // fake clock
  REQUIRE(scan.size() == 2);
  CHECK(scan[0].angle_deg == 0);
  CHECK(scan[0].distance_m == doctest::Approx(0.41));
  CHECK(scan[0].time_ms == 1200);
  CHECK(scan[1].angle_deg == 30);
  scan = scanner.latest_scan(2101);  // the 30 degree point is older than 1 s
  REQUIRE(scan.size() == 1);
  CHECK(scan[0].angle_deg == 0);
  CHECK_THROWS_WITH_AS(scanner.sweep({0, 130, 10}), "sonar sweep: to_deg must be from_deg..120",
                       std::invalid_argument);
}

TEST_CASE("after a turn the scan holds only what the sonar saw since") {
  SerialLink link(LinkOptions{"/nonexistent/marvin-tty"});
  SonarScanner scanner(link, 5, std::chrono::milliseconds(3000));
  // During the turn, a wall 0.6 m away at 30 degrees down, three times.
  for (std::int64_t t : {1000, 1140, 1280}) scanner.add({30, 600, true, 0, t});
  scanner.add({0, 1500, true, 0, 1300});
  scanner.forget_readings();
  CHECK(scanner.latest_scan(1400).empty());  // nothing read since: no point, not a stale one
  // Facing the new way: the floor at 1.7 m. Without forgetting, the median of five would
  // still be the wall (600, 600, 600, 1700, 1720 -> 600).
  scanner.add({30, 1700, true, 0, 1500});
  scanner.add({30, 1720, true, 0, 1640});
  auto scan = scanner.latest_scan(1700);
  REQUIRE(scan.size() == 1);
  CHECK(scan[0].angle_deg == 30);
  CHECK(scan[0].distance_m == doctest::Approx(1.7));
  CHECK(scan[0].time_ms == 1640);
}

TEST_CASE("wheel codes and light bits") {
  CHECK(MotorBase::wheel_codes(Direction::kForward) ==
        std::pair<std::uint8_t, std::uint8_t>{MV_LEFT_FORWARD, MV_RIGHT_FORWARD});
  CHECK(MotorBase::wheel_codes(Direction::kLeft) ==
        std::pair<std::uint8_t, std::uint8_t>{MV_LEFT_BACKWARD, MV_RIGHT_FORWARD});
  CHECK(MotorBase::wheel_codes(Direction::kRight) ==
        std::pair<std::uint8_t, std::uint8_t>{MV_LEFT_FORWARD, MV_RIGHT_BACKWARD});
  CHECK(StatusLight::bits(Light::kAwaiting) == MV_LED_RED);
  CHECK(StatusLight::bits(Light::kListening) == MV_LED_GREEN);
  CHECK(StatusLight::bits(Light::kExecuting) == MV_LED_YELLOW);
  CHECK(StatusLight::bits(Light::kOff) == 0);
}

TEST_CASE("without its device the body drops commands, never throws, and shuts down cleanly") {
  SerialBody body(LinkOptions{"/nonexistent/marvin-tty", std::chrono::milliseconds(20)});
  CHECK(body.link().state() == LinkState::kDisconnected);
  CHECK_FALSE(body.link().send_locomotion(MV_LEFT_FORWARD, 10));
  body.move(Direction::kForward, 100, std::chrono::milliseconds(50));
  body.tilt_head(90);
  body.set_light(Light::kListening);
  body.stop();
  CHECK(body.latest_scan().empty());
  CHECK(body.link().counters().connects == 0);
}
