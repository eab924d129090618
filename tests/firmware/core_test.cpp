// The portable firmware core against the fake layer, with a fake clock (plain integers).
#include <doctest/doctest.h>

#include "core/marvin_core.h"
#include "core/sonar.h"
#include "fake/fake_body.h"
#include "frames.h"

using namespace marvin::fwtest;

namespace {

struct Rig {
  mv_fake_body body;
  mv_core core;
  std::uint32_t now = 1000;  // the fake clock, in ms

  explicit Rig(bool sweep = false) {
    mv_fake_body_init(&body);
    mv_core_init(&core, &body.hal, nullptr, now);
    if (!sweep) send(ext(MV_SONAR_SWEEP, {MV_SWEEP_OFF, 0, 0, 0}));
    mv_fake_clear(&body);
  }
  void send(const mv_frame& f) {
    for (std::uint8_t b : encode_stream({f})) mv_core_rx(&core, b, now);
  }
  void advance(std::uint32_t ms) {
    for (std::uint32_t i = 0; i < ms; ++i) {
      ++now;
      mv_core_tick(&core, now);
    }
  }
  // One sonar reading at the current servo angle with an echo of `echo_us`.
  std::uint8_t reading(std::uint32_t echo_us) {
    std::uint8_t angle = 0;
    REQUIRE(mv_core_ping_due(&core, now, &angle));
    mv_core_echo(&core, echo_us, now);
    return angle;
  }
  void forward(std::uint8_t speed) {
    send(loco(MV_LEFT_FORWARD, speed));
    send(loco(MV_RIGHT_FORWARD, speed));
  }
};

// The echo of an obstacle at `mm` millimetres: T = 2 D / C.
std::uint32_t echo_for_mm(std::uint32_t mm) { return mm * 2000 / MV_SOUND_SPEED_M_S; }

}  // namespace

TEST_CASE("locomotion frames drive each side and are acknowledged") {
  Rig rig;
  rig.forward(180);
  CHECK(rig.body.speed[0] == 180);
  CHECK(rig.body.speed[1] == 180);
  CHECK(rig.body.backward[0] == 0);
  rig.send(loco(MV_RIGHT_BACKWARD, 90));
  CHECK(rig.body.backward[1] == 1);
  CHECK(rig.body.speed[1] == 90);
  rig.send(loco(MV_LEFT_FORWARD, 0));  // speed 0 stops that side
  CHECK(rig.body.speed[0] == 0);
  CHECK(mv_fake_count(&rig.body, MV_ACK) == 4);
  rig.send(ext(MV_STOP_ALL, {}));
  CHECK(rig.body.speed[1] == 0);
}

TEST_CASE("head tilt, LEDs and bad arguments") {
  Rig rig;
  rig.send(ext(MV_HEAD_TILT, {64 - 30}));
  CHECK(rig.body.head_deg == -30);
  rig.send(ext(MV_HEAD_TILT, {64 + 61}));  // out of range: fault, head unchanged
  CHECK(rig.body.head_deg == -30);
  const mv_frame* fault = mv_fake_last(&rig.body, MV_FAULT);
  REQUIRE(fault != nullptr);
  CHECK(fault->payload[0] == MV_FAULT_BAD_ARGUMENT);
  rig.send(ext(MV_LEDS, {static_cast<std::uint8_t>(MV_LED_RED | MV_LED_YELLOW)}));
  CHECK(rig.body.leds == (MV_LED_RED | MV_LED_YELLOW));
}

TEST_CASE("deadman: motors stop when no valid command arrives for 300 ms, and a fault is sent") {
  Rig rig;
  rig.forward(100);
  rig.advance(299);
  CHECK(rig.body.speed[0] == 100);
  rig.send(ext(MV_PING, {}));  // any valid frame keeps the motors alive
  rig.advance(299);
  CHECK(rig.body.speed[0] == 100);
  CHECK(mv_fake_count(&rig.body, MV_FAULT) == 0);
  // Garbage is not a valid command.
  for (int b : {0x12, 0x80, 0x13, 0xFF})
    mv_core_rx(&rig.core, static_cast<std::uint8_t>(b), rig.now);
  rig.advance(1);
  CHECK(rig.body.speed[0] == 0);
  CHECK(rig.body.speed[1] == 0);
  const mv_frame* fault = mv_fake_last(&rig.body, MV_FAULT);
  REQUIRE(fault != nullptr);
  CHECK(fault->payload[0] == MV_FAULT_DEADMAN);
  CHECK(mv_get14(&fault->payload[1]) == 300);
}

TEST_CASE("the deadman time is configurable") {
  Rig rig;
  rig.send(ext(MV_CONFIG, {0, 100, 0x02, 0x2C}));  // 100 ms, 300 mm
  rig.forward(50);
  rig.advance(99);
  CHECK(rig.body.speed[0] == 50);
  rig.advance(1);
  CHECK(rig.body.speed[0] == 0);
}

TEST_CASE(
    "obstacle stop: forward motion stops before an obstacle and is refused while it is there") {
  Rig rig;
  rig.send(ext(MV_SONAR_SWEEP, {MV_SWEEP_FIXED, 0, 0, 0}));
  rig.advance(mv_servo_settle_ms(0, 0));
  rig.forward(120);
  rig.reading(echo_for_mm(1000));  // clear
  CHECK(rig.body.speed[0] == 120);
  rig.reading(echo_for_mm(250));  // 25 cm ahead: stop
  CHECK(rig.body.speed[0] == 0);
  CHECK(rig.body.speed[1] == 0);
  const mv_frame* fault = mv_fake_last(&rig.body, MV_FAULT);
  REQUIRE(fault != nullptr);
  CHECK(fault->payload[0] == MV_FAULT_OBSTACLE);
  CHECK(mv_get14(&fault->payload[1]) == doctest::Approx(250).epsilon(0.01));
  rig.forward(120);  // refused
  CHECK(rig.body.speed[0] == 0);
  CHECK(rig.body.speed[1] == 0);
  rig.send(loco(MV_LEFT_BACKWARD, 80));  // backing away is allowed
  CHECK(rig.body.speed[0] == 80);
  rig.send(ext(MV_STOP_ALL, {}));
  rig.reading(echo_for_mm(2000));  // the way is clear again
  rig.forward(120);
  CHECK(rig.body.speed[1] == 120);
}

TEST_CASE("obstacle stop uses the horizontal component D cos(theta)") {
  Rig rig;
  rig.send(ext(MV_SONAR_SWEEP, {MV_SWEEP_FIXED, 60, 60, 0}));
  rig.advance(mv_servo_settle_ms(0, 60));
  rig.forward(120);
  // 500 mm at 60 degrees: 250 mm ahead but 433 mm up (below the 600 mm clearance): stop.
  CHECK(rig.reading(echo_for_mm(500)) == 60);
  CHECK(rig.body.speed[0] == 0);
  rig.send(ext(MV_STOP_ALL, {}));
  Rig high;
  high.send(ext(MV_SONAR_SWEEP, {MV_SWEEP_FIXED, 60, 60, 0}));
  high.advance(mv_servo_settle_ms(0, 60));
  high.forward(120);
  // 1000 mm at 60 degrees: 500 mm ahead, beyond the 300 mm stop distance: keep going.
  high.reading(echo_for_mm(1000));
  CHECK(high.body.speed[0] == 120);
}

TEST_CASE("sonar arithmetic: D = C T / 2, capped at 2.5 m, echo timeout 14.5 ms") {
  CHECK(mv_sonar_distance_mm(1000) == 173);   // 346 m/s * 1 ms / 2
  CHECK(mv_sonar_distance_mm(5780) == 1000);  // 1 m
  CHECK(mv_sonar_distance_mm(14000) == 2422);
  CHECK(mv_sonar_distance_mm(14451) == 2500);  // the timeout
  CHECK(mv_sonar_distance_mm(30000) == 2500);  // capped
  CHECK(mv_sonar_distance_mm(0) == 2500);      // no echo
  CHECK(MV_SONAR_ECHO_TIMEOUT_US == doctest::Approx(2.0 * 2.5 / 346.0 * 1e6).epsilon(0.001));
  CHECK(1000000 / MV_SONAR_ECHO_TIMEOUT_US == 69);  // readings per second at most
  // Components: horizontal D cos(theta), vertical D sin(theta) (not the paper's tan).
  std::int32_t h = 0, v = 0;
  mv_sonar_components(1000, 0, &h, &v);
  CHECK(h == 1000);
  CHECK(v == 0);
  mv_sonar_components(1000, 30, &h, &v);
  CHECK(h == 866);
  CHECK(v == 500);
  mv_sonar_components(2000, 60, &h, &v);
  CHECK(h == 1000);
  CHECK(v == 1732);
  mv_sonar_components(1000, 90, &h, &v);
  CHECK(h == 0);
  CHECK(v == 1000);
  mv_sonar_components(1000, 120, &h, &v);
  CHECK(h == -500);
  CHECK(v == 866);
}

TEST_CASE("sweep timing: the servo settles 0.14 s per 60 degrees before each reading") {
  CHECK(mv_servo_settle_ms(0, 60) == 140);
  CHECK(mv_servo_settle_ms(120, 0) == 280);
  CHECK(mv_servo_settle_ms(0, 10) == 24);  // 23.3 ms, rounded up
  Rig rig;
  rig.send(ext(MV_SONAR_SWEEP, {MV_SWEEP_ON, 0, 120, 60}));
  // init already aimed the servo at 0, so the first reading needs no travel.
  std::uint8_t angle = 0;
  std::vector<std::uint8_t> angles;
  for (int i = 0; i < 5; ++i) {
    std::uint32_t start = rig.now;
    while (!mv_core_ping_due(&rig.core, rig.now, &angle)) rig.advance(1);
    std::uint32_t waited = rig.now - start;
    if (i > 0) CHECK(waited == 140);  // 60 degrees per step
    CHECK(rig.body.sonar_deg == angle);
    angles.push_back(angle);
    mv_core_echo(&rig.core, echo_for_mm(2000), rig.now);
  }
  CHECK(angles == std::vector<std::uint8_t>{0, 60, 120, 60, 0});
  const mv_frame* r = mv_fake_last(&rig.body, MV_SONAR_READING);
  REQUIRE(r != nullptr);
  CHECK(r->payload[0] == 0);
  CHECK(mv_get14(&r->payload[2]) == doctest::Approx(2000).epsilon(0.01));
  CHECK(mv_get28(&r->payload[4]) == rig.now);
}

TEST_CASE("status telemetry is sent periodically") {
  Rig rig;
  rig.forward(77);
  mv_fake_clear(&rig.body);
  rig.advance(250);
  const mv_frame* s = mv_fake_last(&rig.body, MV_STATUS);
  REQUIRE(s != nullptr);
  CHECK(mv_get14(&s->payload[0]) == 77);
  CHECK(mv_get14(&s->payload[2]) == 77);
  CHECK(mv_get28(&s->payload[8]) == rig.now);
}
