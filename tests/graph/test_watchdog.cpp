#include <doctest/doctest.h>

#include <vector>

#include "graph/watchdog.h"

using namespace marvin::graph;

namespace {

struct Fixture {
  FakeClock clock{1'000'000'000};
  std::vector<WatchdogEvent> events;
  Watchdog dog{clock, [this](const WatchdogEvent& e) { events.push_back(e); }};
  WatchPoint point;
};

}  // namespace

TEST_CASE("deadline: one event per full deadline of silence, counted") {
  Fixture f;
  WatchSpec spec;
  spec.deadline_ns = 200'000'000;
  f.dog.watch("stream mic.out -> agg.in", spec, &f.point);
  f.dog.arm();

  f.clock.advance_ms(150);
  f.point.record_activity(f.clock.now_ns());
  f.clock.advance_ms(200);  // exactly the deadline: not missed
  f.dog.check();
  CHECK(f.events.empty());
  f.clock.advance_ms(1);
  f.dog.check();
  REQUIRE(f.events.size() == 1);
  CHECK(f.events[0].kind == WatchdogEventKind::kDeadline);
  CHECK(f.events[0].total == 1);
  CHECK(f.events[0].count_since_last == 1);
  CHECK(f.events[0].message.find("stream mic.out -> agg.in: no activity for 201.0 ms") == 0);

  f.clock.advance_ms(100);
  f.dog.check();
  CHECK(f.events.size() == 1);  // the next deadline counts from the event
  f.clock.advance_ms(101);
  f.dog.check();
  REQUIRE(f.events.size() == 2);
  CHECK(f.events[1].total == 2);

  f.point.record_activity(f.clock.now_ns());
  f.clock.advance_ms(150);
  f.dog.check();
  CHECK(f.events.size() == 2);

  f.point.finished = true;  // a finished stream is expected to be silent
  f.clock.advance_ms(1000);
  f.dog.check();
  CHECK(f.events.size() == 2);
  CHECK(f.dog.event_count() == 2);
}

TEST_CASE("latency: violations counted on the hot path, reported with counts since last") {
  Fixture f;
  WatchSpec spec;
  spec.max_latency_ns = 50'000'000;
  f.dog.watch("node kws", spec, &f.point);
  f.dog.arm();
  f.point.record_latency(50'000'000);  // at the limit: fine
  f.point.record_latency(50'000'001);
  f.point.record_latency(70'000'000);
  f.point.record_latency(10'000'000);
  f.dog.check();
  REQUIRE(f.events.size() == 1);
  CHECK(f.events[0].kind == WatchdogEventKind::kLatency);
  CHECK(f.events[0].count_since_last == 2);
  CHECK(f.events[0].total == 2);
  f.point.record_latency(90'000'000);
  f.dog.check();
  REQUIRE(f.events.size() == 2);
  CHECK(f.events[1].count_since_last == 1);
  CHECK(f.events[1].total == 3);
  CHECK(f.events[1].message == "node kws: latency above 50.0 ms (1 since last event, 3 in total)");
}

TEST_CASE("rate: low and high rates over each window") {
  Fixture f;
  WatchSpec spec;
  spec.min_rate_hz = 40;
  spec.max_rate_hz = 60;
  spec.rate_window_ns = 1'000'000'000;
  f.dog.watch("stream mic.out -> agg.in", spec, &f.point);
  f.dog.arm();

  for (int i = 0; i < 50; ++i) f.point.record_activity(f.clock.now_ns());
  f.clock.advance_ms(999);
  f.dog.check();  // window not complete yet
  CHECK(f.events.empty());
  f.clock.advance_ms(1);
  f.dog.check();
  CHECK(f.events.empty());  // 50/s is within [40, 60]

  for (int i = 0; i < 30; ++i) f.point.record_activity(f.clock.now_ns());
  f.clock.advance_ms(1000);
  f.dog.check();
  REQUIRE(f.events.size() == 1);
  CHECK(f.events[0].kind == WatchdogEventKind::kRateLow);
  CHECK(f.events[0].message.find("rate 30.0/s below minimum 40.0/s") != std::string::npos);

  for (int i = 0; i < 61; ++i) f.point.record_activity(f.clock.now_ns());
  f.clock.advance_ms(1000);
  f.dog.check();
  REQUIRE(f.events.size() == 2);
  CHECK(f.events[1].kind == WatchdogEventKind::kRateHigh);
  CHECK(f.events[1].total == 1);
}
