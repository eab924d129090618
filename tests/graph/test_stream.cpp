#include <doctest/doctest.h>

#include <vector>

#include "graph/stream.h"
#include "graph/watchdog.h"
#include "test_nodes.h"

using namespace marvin::graph;
using testing::int_at;

namespace {

std::vector<Timestamp> drain(Stream& s, std::vector<bool>* flags = nullptr) {
  std::vector<Timestamp> out;
  while (s.head().has_packet) {
    Packet p = s.take();
    out.push_back(p.timestamp());
    if (flags) flags->push_back(p.discontinuous());
  }
  return out;
}

struct Counting : Wakeable {
  int wakes = 0;
  void wake() override { ++wakes; }
};

}  // namespace

TEST_CASE("lossless stream keeps everything, reports full, and wakes the producer") {
  FakeClock clock;
  StreamOptions o;
  o.capacity = 3;
  Stream s("a.out -> b.in", o, clock);
  Counting producer, consumer;
  s.connect(&producer, &consumer);
  for (Timestamp t = 0; t < 5; ++t) CHECK(s.push(int_at(t)));  // one call may overshoot
  CHECK(s.full());
  CHECK(consumer.wakes == 5);
  CHECK(drain(s) == std::vector<Timestamp>{0, 1, 2, 3, 4});
  CHECK(producer.wakes == 3);  // each take while at or above capacity
  const StreamStats st = s.stats();
  CHECK(st.pushed == 5);
  CHECK(st.delivered == 5);
  CHECK(st.dropped == 0);
  CHECK(st.high_water == 5);
}

TEST_CASE("drop_oldest counts every drop and flags the packet after the gap") {
  FakeClock clock;
  StreamOptions o;
  o.policy = StreamPolicy::kDropOldest;
  o.capacity = 3;
  Stream s("mic.out -> kws.in", o, clock);
  for (Timestamp t = 0; t < 10; ++t) CHECK(s.push(int_at(t)));
  std::vector<bool> flags;
  CHECK(drain(s, &flags) == std::vector<Timestamp>{7, 8, 9});
  CHECK(flags == std::vector<bool>{true, false, false});
  CHECK(s.stats().dropped == 7);
  CHECK(s.stats().delivered == 3);
  CHECK(s.stats().high_water == 3);
}

TEST_CASE("drop_newest keeps the queue and flags the next accepted packet") {
  FakeClock clock;
  StreamOptions o;
  o.policy = StreamPolicy::kDropNewest;
  o.capacity = 3;
  Stream s("mic.out -> kws.in", o, clock);
  int accepted = 0;
  for (Timestamp t = 0; t < 10; ++t) accepted += s.push(int_at(t)) ? 1 : 0;
  CHECK(accepted == 3);
  std::vector<bool> flags;
  CHECK(drain(s, &flags) == std::vector<Timestamp>{0, 1, 2});
  CHECK(flags == std::vector<bool>{false, false, false});
  CHECK(s.push(int_at(10)));
  CHECK(drain(s, &flags) == std::vector<Timestamp>{10});
  CHECK(flags.back());
  CHECK(s.stats().dropped == 7);
  CHECK(s.head().bound == 11);  // dropped packets still advance the bound
}

TEST_CASE("runs of consecutive drops beyond the limit become exact watchdog events") {
  FakeClock clock;
  StreamOptions o;
  o.policy = StreamPolicy::kDropOldest;
  o.capacity = 2;
  o.max_consecutive_drops = 2;
  Stream s("mic.out -> kws.in", o, clock);
  std::vector<WatchdogEvent> events;
  Watchdog dog(clock, [&](const WatchdogEvent& e) { events.push_back(e); });
  dog.watch("stream " + s.name(), WatchSpec{}, &s.watch_point());
  dog.arm();

  for (Timestamp t = 0; t < 6; ++t) s.push(int_at(t));  // 4 drops in a row: a run over 2
  s.take();                                             // the consumer takes: the run ends
  for (Timestamp t = 6; t < 9; ++t) s.push(int_at(t));  // 1 fits, 2 drops: within the limit
  s.take();
  for (Timestamp t = 9; t < 13; ++t) s.push(int_at(t));  // 1 fits, 3 drops: a second run
  CHECK(s.stats().dropped == 4 + 2 + 3);
  dog.check();
  REQUIRE(events.size() == 1);
  CHECK(events[0].kind == WatchdogEventKind::kDrops);
  CHECK(events[0].total == 2);
  CHECK(events[0].count_since_last == 2);
  CHECK(events[0].subject == "stream mic.out -> kws.in");

  s.take();
  for (Timestamp t = 13; t < 17; ++t) s.push(int_at(t));  // 1 fits, 3 drops
  dog.check();
  REQUIRE(events.size() == 2);
  CHECK(events[1].total == 3);
  CHECK(events[1].count_since_last == 1);
  dog.check();
  CHECK(events.size() == 2);  // nothing new, nothing reported
}

TEST_CASE("bounds rise with packets and explicit advances, never fall, and end at done") {
  FakeClock clock;
  Stream s("a.out -> b.in", StreamOptions{}, clock);
  Counting consumer;
  s.connect(nullptr, &consumer);
  CHECK(s.head().bound == kTimestampMin);
  s.advance_bound(100);
  CHECK(consumer.wakes == 1);
  s.advance_bound(50);
  CHECK(consumer.wakes == 1);
  CHECK(s.head().bound == 100);
  CHECK(s.head().next_possible() == 100);
  s.push(int_at(120));
  CHECK(s.head().next_possible() == 120);
  CHECK(s.head().bound == 121);
  s.close();
  CHECK_FALSE(s.head().done());  // still holds a packet
  s.take();
  CHECK(s.head().done());
}

TEST_CASE("queue latency is measured with the injected clock") {
  FakeClock clock;
  Stream s("a.out -> b.in", StreamOptions{}, clock);
  s.push(int_at(0));
  clock.advance_ms(3);
  s.take();
  const StreamStats st = s.stats();
  CHECK(st.latency_p50_ns >= 3'000'000);
  CHECK(st.latency_p50_ns <= 3'000'000 * 9 / 8);  // histogram resolution 12.5%
}
