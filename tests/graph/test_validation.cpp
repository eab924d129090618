#include <doctest/doctest.h>

#include <cstdlib>
#include <fstream>
#include <string>

#include "graph/graph.h"
#include "test_nodes.h"

using namespace marvin::graph;
using nlohmann::json;

namespace {

// The message of the GraphError that building `j` throws ("" if it builds).
std::string build_error(const json& j) {
  try {
    Graph g(parse_graph_config(j, "test.json"), testing::quiet_options());
  } catch (const GraphError& e) {
    return e.what();
  }
  return "";
}

json counter_to_needs_int() {
  return json::parse(R"({
    "nodes": [
      {"name": "count", "type": "CounterSource", "options": {"count": 3}},
      {"name": "check", "type": "TestNeedsInt"}
    ],
    "streams": [{"from": "count.out", "to": "check.value"}]
  })");
}

}  // namespace

TEST_CASE("a valid graph builds") { CHECK(build_error(counter_to_needs_int()) == ""); }

TEST_CASE("unknown node type is named with the known types") {
  json j = counter_to_needs_int();
  j["nodes"][1]["type"] = "TestNeedsInteger";
  const std::string e = build_error(j);
  CHECK(e.find("node 'check': unknown node type 'TestNeedsInteger' (known: ") == 0);
  CHECK(e.find("TestNeedsInt,") != std::string::npos);
}

TEST_CASE("an unconnected required input names node, port and type") {
  json j = counter_to_needs_int();
  j["streams"] = json::array();
  CHECK(build_error(j) ==
        "node 'check' (TestNeedsInt): required input 'value' (int64) is not connected");
}

TEST_CASE("a type mismatch names both ends and both types") {
  json j = counter_to_needs_int();
  j["streams"].push_back({{"from", "count.out"}, {"to", "check.enable"}});
  CHECK(build_error(j) ==
        "stream 'count.out -> check.enable': type mismatch: output 'count.out' of node 'count' "
        "(CounterSource) carries 'int64' but input 'check.enable' of node 'check' "
        "(TestNeedsInt) expects 'bool'");
}

TEST_CASE("types flow through pass-through outputs before being checked") {
  json j = json::parse(R"({
    "nodes": [
      {"name": "count", "type": "CounterSource"},
      {"name": "p1", "type": "PassThrough"},
      {"name": "p2", "type": "PassThrough"},
      {"name": "check", "type": "TestNeedsInt"}
    ],
    "streams": [{"from": "count.out", "to": "p1.in"}, {"from": "p1.out", "to": "p2.in"},
                {"from": "p2.out", "to": "check.value"}, {"from": "p2.out", "to": "check.enable"}]
  })");
  CHECK(build_error(j).find("output 'p2.out' of node 'p2' (PassThrough) carries 'int64' but "
                            "input 'check.enable' of node 'check' (TestNeedsInt) expects 'bool'") !=
        std::string::npos);
}

TEST_CASE("a cycle needs a declared back edge") {
  json j = json::parse(R"({
    "nodes": [
      {"name": "in", "type": "GraphInput", "options": {"type": "int64"}},
      {"name": "join", "type": "TestJoin"},
      {"name": "loop", "type": "PassThrough"}
    ],
    "streams": [{"from": "in.out", "to": "join.a"}, {"from": "join.out", "to": "loop.in"},
                {"from": "loop.out", "to": "join.b"}]
  })");
  CHECK(build_error(j) ==
        "cycle without a back edge: join.out -> loop.in, loop.out -> join.b (mark one of these "
        "streams \"back_edge\": true)");
  j["streams"][2]["back_edge"] = true;
  CHECK(build_error(j) == "");
}

TEST_CASE("bad options: wrong type, out of range, not a choice, unknown") {
  json j = counter_to_needs_int();
  j["nodes"][1]["options"] = {{"threshold", "high"}};
  CHECK(build_error(j) ==
        "node 'check' (TestNeedsInt): option 'threshold' must be an integer, got \"high\"");
  j["nodes"][1]["options"] = {{"threshold", 101}};
  CHECK(build_error(j) ==
        "node 'check' (TestNeedsInt): option 'threshold' must be in [0, 100], got 101");
  j["nodes"][1]["options"] = {{"mode", "slow"}};
  CHECK(build_error(j) ==
        "node 'check' (TestNeedsInt): option 'mode' must be one of fast, exact, got 'slow'");
  j["nodes"][1]["options"] = {{"treshold", 5}};
  CHECK(build_error(j) ==
        "node 'check' (TestNeedsInt): unknown option 'treshold' (known: mode, threshold)");
  j = json::parse(R"({"nodes": [{"name": "agg", "type": "Aggregator",
                                 "options": {"window_ms": 100, "hop_ms": 250}}]})");
  CHECK(build_error(j).find("node 'agg' (Aggregator): option 'hop_ms' must be in [1, 100], got 250") == 0);
}

TEST_CASE("unknown ports, doubly fed inputs and duplicate names") {
  json j = counter_to_needs_int();
  j["streams"][0]["to"] = "check.valeu";
  CHECK(build_error(j) ==
        "stream 'count.out -> check.valeu': node 'check' (TestNeedsInt) has no input port "
        "'valeu' (inputs: value (int64), enable (bool))\n"
        "node 'check' (TestNeedsInt): required input 'value' (int64) is not connected");
  j = counter_to_needs_int();
  j["nodes"].push_back({{"name", "count2"}, {"type", "CounterSource"}});
  j["streams"].push_back({{"from", "count2.out"}, {"to", "check.value"}});
  CHECK(build_error(j) ==
        "stream 'count2.out -> check.value': input 'check.value' is already fed by stream "
        "'count.out -> check.value' (an input takes one stream; fan-out is from outputs)");
  j = counter_to_needs_int();
  j["nodes"][1]["name"] = "count";
  CHECK(build_error(j).find("node 'count': the name is used by two nodes") == 0);
}

TEST_CASE("every error found is reported, one per line") {
  json j = json::parse(R"({"nodes": [{"name": "a", "type": "Nope"}, {"name": "b", "type": "Nada"}]})");
  const std::string e = build_error(j);
  CHECK(e.find("node 'a': unknown node type 'Nope'") == 0);
  CHECK(e.find("\nnode 'b': unknown node type 'Nada'") != std::string::npos);
}

TEST_CASE("JSON loading errors name the file and the field") {
  auto parse_error = [](const json& j) {
    try {
      parse_graph_config(j, "demo.json");
    } catch (const GraphError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  CHECK(parse_error(json::array()) == "demo.json: expected a JSON object, got []");
  CHECK(parse_error(json::object()) == "demo.json: missing field \"nodes\"");
  CHECK(parse_error(json::parse(R"({"nodes": [{"name": "a"}]})")) ==
        "demo.json: nodes[0]: missing field \"type\"");
  CHECK(parse_error(json::parse(R"({"nodes": [{"name": "a", "type": "Sink", "option": {}}]})")) ==
        "demo.json: nodes[0]: unknown field 'option' (expected one of: input_policy, name, "
        "options, type, watchdog)");
  CHECK(parse_error(json::parse(
            R"({"nodes": [], "streams": [{"from": "a.out", "to": "b.in", "policy": "lossy"}]})")) ==
        "demo.json: streams[0].policy: must be \"lossless\", \"drop_oldest\" or \"drop_newest\", "
        "got \"lossy\"");
  CHECK(parse_error(json::parse(
            R"({"nodes": [], "streams": [{"from": "a.out", "to": "b.in", "capacity": 0}]})")) ==
        "demo.json: streams[0].capacity: must be in [1, 1048576], got 0");
  CHECK(parse_error(json::parse(
            R"({"nodes": [], "streams": [{"from": "a.out", "to": "b.in", "watchdog": {"deadline": 5}}]})"))
            .find("demo.json: streams[0].watchdog: unknown field 'deadline'") == 0);

  const std::string path = std::string(std::getenv("MARVIN_BUILD_DIR") ? std::getenv("MARVIN_BUILD_DIR") : ".") +
                           "/graph_test_broken.json";
  {
    std::ofstream(path) << "{\"nodes\": [";
  }
  try {
    load_graph_config(path);
    FAIL("expected an error");
  } catch (const GraphError& e) {
    CHECK(std::string(e.what()).find(path + ": not valid JSON (byte 12)") == 0);
  }
  std::remove(path.c_str());
  CHECK_THROWS_WITH_AS(load_graph_config("/nonexistent/graph.json"),
                       "/nonexistent/graph.json: cannot open the file", GraphError);
}

TEST_CASE("the example graphs are valid") {
  const char* src = std::getenv("MARVIN_SOURCE_DIR");
  REQUIRE(src != nullptr);
  const GraphConfig c = load_graph_config(std::string(src) + "/examples/graphs/audio_demo.json");
  Graph g(c, testing::quiet_options());
  const std::string dot = g.to_dot();
  CHECK(dot.find("digraph") == 0);
  CHECK(dot.find("\"mic\" -> \"window\"") != std::string::npos);
}
