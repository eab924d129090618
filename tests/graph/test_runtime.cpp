#include <doctest/doctest.h>

#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "graph/graph.h"
#include "test_nodes.h"

using namespace marvin::graph;
using testing::quiet_options;
using testing::Recorder;

namespace {

StreamOptions lossless(std::size_t capacity) {
  StreamOptions o;
  o.capacity = capacity;
  return o;
}

std::vector<Timestamp> iota(Timestamp n) {
  std::vector<Timestamp> v;
  for (Timestamp i = 0; i < n; ++i) v.push_back(i);
  return v;
}

const StreamStats& stream(const GraphStats& s, const std::string& name) {
  for (const StreamStats& st : s.streams) {
    if (st.name == name) return st;
  }
  FAIL("no stream " << name);
  return s.streams.front();
}

const NodeStats& node(const GraphStats& s, const std::string& name) {
  for (const NodeStats& n : s.nodes) {
    if (n.name == name) return n;
  }
  FAIL("no node " << name);
  return s.nodes.front();
}

}  // namespace

TEST_CASE("lossless: a slow consumer gets every packet, in order, and the queue stays bounded") {
  GraphConfig c;
  c.add_node("count", "CounterSource", {{"count", 2000}})
      .add_node("slow", "TestSlow", {{"yields", 50}})
      .add_node("sink", "Sink")
      .connect("count.out", "slow.in", lossless(2))
      .connect("slow.out", "sink.in", lossless(2));
  Graph g(c, quiet_options());
  Recorder seen;
  g.observe("slow.out", seen.observer());
  g.start();
  g.wait();
  CHECK(seen.timestamps() == iota(2000));
  const GraphStats s = g.stats();
  const StreamStats& in = stream(s, "count.out -> slow.in");
  CHECK(in.pushed == 2000);
  CHECK(in.delivered == 2000);
  CHECK(in.dropped == 0);
  CHECK(in.high_water <= 2);
  CHECK(node(s, "sink").process_calls == 2000);
}

TEST_CASE("ordering is preserved through a pipeline on several threads") {
  GraphConfig c;
  c.add_node("count", "CounterSource", {{"count", 20000}})
      .add_node("a", "PassThrough")
      .add_node("b", "PassThrough")
      .add_node("sink", "Sink")
      .connect("count.out", "a.in", lossless(8))
      .connect("a.out", "b.in", lossless(8))
      .connect("b.out", "sink.in", lossless(8));
  Graph g(c, quiet_options(3));
  Recorder seen;
  g.observe("b.out", seen.observer());
  g.start();
  g.wait();
  const std::vector<Packet> packets = seen.packets();
  REQUIRE(packets.size() == 20000);
  for (std::size_t i = 0; i < packets.size(); ++i) {
    REQUIRE(packets[i].timestamp() == static_cast<Timestamp>(i));
    REQUIRE(packets[i].get<int64_t>() == static_cast<int64_t>(i));
  }
}

TEST_CASE("fan-out: one output feeds streams with their own policies") {
  GraphConfig c;
  StreamOptions lossy;
  lossy.policy = StreamPolicy::kDropOldest;
  lossy.capacity = 1;
  c.add_node("count", "CounterSource", {{"count", 3000}})
      .add_node("fast", "PassThrough")
      .add_node("slow", "TestSlow", {{"yields", 50}})
      .connect("count.out", "fast.in", lossless(4))
      .connect("count.out", "slow.in", lossy);
  Graph g(c, quiet_options());
  Recorder fast, slow;
  g.observe("fast.out", fast.observer());
  g.observe("slow.out", slow.observer());
  g.start();
  g.wait();
  CHECK(fast.timestamps() == iota(3000));
  const GraphStats stats = g.stats();
  const StreamStats& st = stream(stats, "count.out -> slow.in");
  CHECK(st.pushed == 3000);
  CHECK(st.delivered + st.dropped == 3000);
  CHECK(st.delivered == slow.packets().size());
  std::size_t flagged = 0;
  Timestamp last = -1;
  for (const Packet& p : slow.packets()) {
    CHECK(p.timestamp() > last);
    // A packet is flagged exactly when something was dropped just before it.
    CHECK(p.discontinuous() == (p.timestamp() != last + 1));
    flagged += p.discontinuous() ? 1 : 0;
    last = p.timestamp();
  }
  CHECK(flagged <= st.dropped);
}

TEST_CASE("stop under load drains the lossless streams") {
  GraphConfig c;
  c.add_node("count", "CounterSource")  // endless
      .add_node("slow", "TestSlow", {{"yields", 2}})
      .add_node("sink", "Sink")
      .connect("count.out", "slow.in", lossless(16))
      .connect("slow.out", "sink.in", lossless(16));
  Graph g(c, quiet_options());
  Recorder seen;
  g.observe("slow.out", seen.observer());
  g.start();
  REQUIRE(seen.wait_for_count(5000));
  g.stop();
  g.wait();
  const GraphStats s = g.stats();
  const uint64_t produced = node(s, "count").emitted;
  CHECK(produced >= 5000);
  CHECK(node(s, "slow").emitted == produced);
  CHECK(node(s, "sink").process_calls == produced);
  for (const StreamStats& st : s.streams) {
    CHECK(st.delivered == st.pushed);
    CHECK(st.dropped == 0);
  }
  CHECK(seen.timestamps() == iota(static_cast<Timestamp>(produced)));
}

TEST_CASE("a paced CounterSource holds each packet until it is due, and stop ends the wait") {
  // One packet an hour: the first comes at once, the second not before stop() ends the graph.
  GraphConfig c;
  c.add_node("count", "CounterSource", {{"count", 3}, {"interval_us", int64_t{3'600'000'000}}})
      .add_node("sink", "Sink")
      .connect("count.out", "sink.in");
  Graph g(c, quiet_options());
  Recorder seen;
  g.observe("count.out", seen.observer());
  g.start();
  REQUIRE(seen.wait_for_count(1));
  g.stop();
  g.wait();
  CHECK(node(g.stats(), "count").emitted == 1);
  CHECK(seen.timestamps() == iota(1));
}

TEST_CASE("cancel stops an endless graph at once; the destructor cancels too") {
  GraphConfig c;
  c.add_node("count", "CounterSource").add_node("sink", "Sink").connect("count.out", "sink.in");
  {
    Graph g(c, quiet_options());
    Recorder seen;
    g.observe("count.out", seen.observer());
    g.start();
    REQUIRE(seen.wait_for_count(100));
    g.cancel();
    g.wait();
  }
  {
    Graph g(c, quiet_options());
    g.start();
  }  // destroyed while running
  CHECK(true);  // returned: nothing hung
}

TEST_CASE("a node that throws stops the graph with its error, even with a blocked producer") {
  GraphConfig c;
  c.add_node("count", "CounterSource")  // endless: would fill any queue
      .add_node("boom", "TestThrow", {{"at", 100}})
      .add_node("sink", "Sink")
      .connect("count.out", "boom.in", lossless(1))
      .connect("boom.out", "sink.in", lossless(1));
  Graph g(c, quiet_options());
  g.start();
  CHECK_THROWS_WITH_AS(g.wait(),
                       "node 'boom' (TestThrow) failed in process() at timestamp 100: model file "
                       "is corrupt",
                       GraphError);
  CHECK(node(g.stats(), "sink").process_calls <= 100);
}

TEST_CASE("a node that throws in open() makes start() fail and nothing runs") {
  GraphConfig c;
  c.add_node("count", "CounterSource", {{"count", 10}})
      .add_node("boom", "TestThrow", {{"in_open", true}})
      .connect("count.out", "boom.in");
  Graph g(c, quiet_options());
  CHECK_THROWS_WITH_AS(g.start(), "node 'boom' (TestThrow) failed in open(): microphone unplugged",
                       GraphError);
  CHECK(node(g.stats(), "count").emitted == 0);
}

TEST_CASE("input policies: synchronized joins equal timestamps, immediate does not wait") {
  for (const bool immediate : {false, true}) {
    GraphConfig c;
    c.add_node("a", "GraphInput", {{"type", "int64"}})
        .add_node("b", "GraphInput", {{"type", "int64"}})
        .add_node("join", "TestJoin")
        .connect("a.out", "join.a")
        .connect("b.out", "join.b");
    if (immediate) c.nodes[2].input_policy = InputPolicy::kImmediate;
    Graph g(c, quiet_options());
    Recorder seen;
    g.observe("join.out", seen.observer());
    g.start();
    if (immediate) {
      g.push("a", Packet::make<int64_t>(int64_t{1}).at(1));  // b has nothing yet: not awaited
      REQUIRE(seen.wait_for_count(1));
      g.push("b", Packet::make<int64_t>(int64_t{2}).at(2));
    } else {
      g.push("a", Packet::make<int64_t>(int64_t{1}).at(1));
      g.push("b", Packet::make<int64_t>(int64_t{1}).at(1));
      g.push("b", Packet::make<int64_t>(int64_t{2}).at(2));
    }
    g.close_input("a");
    g.close_input("b");
    g.wait();
    std::vector<int64_t> codes;
    for (const Packet& p : seen.packets()) codes.push_back(p.get<int64_t>());
    CHECK(codes == (immediate ? std::vector<int64_t>{1, 2} : std::vector<int64_t>{3, 2}));
  }
}

TEST_CASE("a node emitting a timestamp that goes back fails naming node and port") {
  GraphConfig c;
  c.add_node("in", "GraphInput", {{"type", "int64"}})
      .add_node("join", "TestJoin")
      .connect("in.out", "join.a");
  c.add_node("in2", "GraphInput", {{"type", "int64"}}).connect("in2.out", "join.b");
  c.nodes[1].input_policy = InputPolicy::kImmediate;
  Graph g(c, quiet_options());
  g.start();
  g.push("in", Packet::make<int64_t>(int64_t{0}).at(5));
  g.push("in2", Packet::make<int64_t>(int64_t{0}).at(5));
  g.close_input("in");
  g.close_input("in2");
  CHECK_THROWS_WITH_AS(g.wait(),
                       "node 'join' (TestJoin) failed in process() at timestamp 5: node 'join' "
                       "(TestJoin) output 'out': timestamp 5 is below the port's bound 6 "
                       "(timestamps must increase)",
                       GraphError);
}

TEST_CASE("watchdog events reach a WatchdogEvents node, which does not keep the graph alive") {
  FakeClock clock;
  GraphConfig c;
  c.add_node("in", "GraphInput", {{"type", "int64"}})
      .add_node("sink", "Sink")
      .add_node("events", "WatchdogEvents")
      .add_node("event_sink", "Sink")
      .connect("in.out", "sink.in")
      .connect("events.events", "event_sink.in");
  c.streams[0].watchdog.deadline_ns = 100'000'000;
  GraphOptions o = quiet_options();
  o.clock = &clock;
  Graph g(c, o);
  Recorder events;
  g.observe("events.events", events.observer());
  g.start();
  clock.advance_ms(101);
  g.watchdog().check();
  REQUIRE(events.wait_for_count(1));
  const WatchdogEvent& e = events.packets()[0].get<WatchdogEvent>();
  CHECK(e.kind == WatchdogEventKind::kDeadline);
  CHECK(e.subject == "stream in.out -> sink.in");
  g.close_input("in");
  g.wait();
  CHECK(g.stats().watchdog_events == 1);
}

TEST_CASE("a Chrome trace of node spans and the counters table") {
  GraphConfig c;
  c.add_node("count", "CounterSource", {{"count", 100}})
      .add_node("pass", "PassThrough")
      .add_node("sink", "Sink")
      .connect("count.out", "pass.in")
      .connect("pass.out", "sink.in");
  GraphOptions o = quiet_options();
  o.trace = true;
  Graph g(c, o);
  g.start();
  g.wait();
  const char* dir = std::getenv("MARVIN_BUILD_DIR");
  const std::string path = std::string(dir ? dir : ".") + "/graph_test_trace.json";
  g.write_trace(path);
  std::ifstream in(path);
  const nlohmann::json trace = nlohmann::json::parse(in);
  std::map<std::string, int> spans;
  for (const auto& e : trace["traceEvents"]) {
    if (e["ph"] == "X") ++spans[e["name"].get<std::string>()];
  }
  CHECK(spans["count"] == 101);  // the last call finds the count reached and finishes
  CHECK(spans["pass"] == 100);
  CHECK(spans["sink"] == 100);
  std::remove(path.c_str());

  const std::string table = g.stats().to_text();
  CHECK(table.find("count.out -> pass.in") != std::string::npos);
  CHECK(table.find("watchdog events: 0") != std::string::npos);
}
