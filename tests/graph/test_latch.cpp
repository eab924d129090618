#include <doctest/doctest.h>

#include "graph/graph.h"
#include "test_nodes.h"

using namespace marvin::graph;
using testing::int_at;
using testing::quiet_options;
using testing::Recorder;

namespace {

Packet bool_at(bool v, Timestamp ts) { return Packet::make<bool>(v).at(ts); }

GraphConfig latch_graph() {
  GraphConfig c;
  c.add_node("ctl", "GraphInput", {{"type", "bool"}})
      .add_node("data", "GraphInput", {{"type", "int64"}})
      .add_node("other", "GraphInput", {{"type", "int64"}})
      .add_node("latch", "Latch")
      .add_node("join", "TestJoin")
      .connect("ctl.out", "latch.control")
      .connect("data.out", "latch.in0")
      .connect("latch.out0", "join.a")
      .connect("other.out", "join.b");
  return c;
}

}  // namespace

TEST_CASE("a two-input node downstream of a closed latch keeps running") {
  Graph g(latch_graph(), quiet_options());
  Recorder joined, passed;
  g.observe("join.out", joined.observer());
  g.observe("latch.out0", passed.observer());
  g.start();
  g.push("ctl", bool_at(true, 0));
  g.push("ctl", bool_at(false, 5));
  g.close_input("ctl");
  for (Timestamp t = 1; t <= 10; ++t) {
    g.push("data", int_at(t));
    g.push("other", int_at(t));
  }
  // data and other stay open: only the latch's bounds tell join that input a is settled.
  REQUIRE(joined.wait_for_count(10));
  std::vector<int64_t> codes;
  for (const Packet& p : joined.packets()) codes.push_back(p.get<int64_t>());
  CHECK(codes == std::vector<int64_t>{3, 3, 3, 3, 2, 2, 2, 2, 2, 2});
  CHECK(passed.timestamps() == std::vector<Timestamp>{1, 2, 3, 4});
  g.close_input("data");
  g.close_input("other");
  g.wait();
}

TEST_CASE("a latch reopening flags the next packet discontinuous") {
  GraphConfig c = latch_graph();
  Graph g(c, quiet_options());
  Recorder passed;
  g.observe("latch.out0", passed.observer());
  g.start();
  g.push("ctl", bool_at(true, 0));
  g.push("ctl", bool_at(false, 3));
  g.push("ctl", bool_at(true, 6));
  g.close_input("ctl");
  for (Timestamp t = 1; t <= 8; ++t) {
    g.push("data", int_at(t));
    g.push("other", int_at(t));
  }
  g.close_input("data");
  g.close_input("other");
  g.wait();
  std::vector<bool> flags;
  for (const Packet& p : passed.packets()) flags.push_back(p.discontinuous());
  CHECK(passed.timestamps() == std::vector<Timestamp>{1, 2, 6, 7, 8});
  CHECK(flags == std::vector<bool>{true, false, true, false, false});
}

TEST_CASE("a latch gates several channels with one control") {
  GraphConfig c;
  c.add_node("ctl", "GraphInput", {{"type", "bool"}})
      .add_node("x", "GraphInput", {{"type", "int64"}})
      .add_node("y", "GraphInput", {{"type", "string"}})
      .add_node("latch", "Latch", {{"channels", 2}, {"start_open", true}})
      .connect("ctl.out", "latch.control")
      .connect("x.out", "latch.in0")
      .connect("y.out", "latch.in1");
  Graph g(c, quiet_options());
  Recorder xs, ys;
  g.observe("latch.out0", xs.observer());
  g.observe("latch.out1", ys.observer());
  g.start();
  g.push("ctl", bool_at(false, 2));
  g.close_input("ctl");
  for (Timestamp t = 1; t <= 3; ++t) {
    g.push("x", int_at(t));
    g.push("y", Packet::make<std::string>("word").at(t));
  }
  g.close_input("x");
  g.close_input("y");
  g.wait();
  CHECK(xs.timestamps() == std::vector<Timestamp>{1});
  CHECK(ys.timestamps() == std::vector<Timestamp>{1});
}

TEST_CASE("attention nodes emit state changes only, and advance the bound otherwise") {
  GraphConfig c;
  c.add_node("toggle", "ToggleSource",
             {{"period_ms", 100}, {"tick_ms", 25}, {"duration_ms", 400}, {"pace", 0}})
      .add_node("sink", "Sink")
      .connect("toggle.out", "sink.in");
  Graph g(c, quiet_options());
  Recorder seen;
  g.observe("toggle.out", seen.observer());
  g.start();
  g.wait();
  CHECK(seen.timestamps() == std::vector<Timestamp>{0, 100'000, 200'000, 300'000});
  std::vector<bool> values;
  for (const Packet& p : seen.packets()) values.push_back(p.get<bool>());
  CHECK(values == std::vector<bool>{true, false, true, false});
}
