// The voice loop as a graph (core/perception/graphs/voice_loop.json) on synthetic speech.
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "devices/audio/sound_file.h"
#include "graph/graph.h"
#include "graph/graph_config.h"
#include "perception/voice_nodes.h"
#include "speech_fixture.h"

namespace fs = std::filesystem;
using namespace marvin;
using namespace marvin::perception::testing;

namespace {

// The shipped graph with its file paths pointed at `dir`.
graph::GraphConfig voice_graph(const fs::path& dir) {
  const char* source = std::getenv("MARVIN_SOURCE_DIR");
  const fs::path file = fs::path(source ? source : MARVIN_TEST_SOURCE_DIR) /
                        "core/perception/graphs/voice_loop.json";
  std::ifstream in(file);
  REQUIRE(in.good());
  nlohmann::json json = nlohmann::json::parse(in);
  for (auto& node : json["nodes"]) {
    if (node["name"] == "mic") node["options"]["path"] = (dir / "input.wav").string();
    if (node["name"] == "speaker") node["options"]["path"] = (dir / "reply.wav").string();
  }
  return graph::parse_graph_config(json, file.string());
}

struct TempDir {
  fs::path path = fs::temp_directory_path() / ("marvin_voice_graph_" + std::to_string(::getpid()));
  TempDir() { fs::create_directories(path); }
  ~TempDir() { fs::remove_all(path); }
};

std::vector<std::int16_t> run_graph(const std::vector<std::int16_t>& input) {
  perception::register_voice_nodes();
  TempDir dir;
  audio::write_speech_file(dir.path / "input.wav", input);
  graph::Graph g(voice_graph(dir.path));
  g.start();
  g.wait();
  return audio::read_speech_file(dir.path / "reply.wav");
}

}  // namespace

TEST_CASE("voice graph: \"marvin, what time is it\" gets a spoken reply after the command") {
  const std::vector<std::int16_t> input = utterance("marvin, what time is it", 500, 2500);
  const std::vector<std::int16_t> reply = run_graph(input);
  // The reply is placed at its stream time: silence until the command ended, then speech.
  std::size_t first = 0;
  while (first < reply.size() && std::abs(reply[first]) < 500) ++first;
  REQUIRE(first < reply.size());
  std::size_t command_end = input.size();
  while (command_end > 0 && std::abs(input[command_end - 1]) < 500) --command_end;
  CHECK(first > command_end);
  CHECK(first < command_end + 16000);  // within a second of stream time (trailing silence 400 ms)
  CHECK(rms(std::vector<std::int16_t>(reply.begin() + static_cast<std::ptrdiff_t>(first), reply.end())) > 1000.0);
}

TEST_CASE("voice graph: speech without the wake word gets no reply") {
  const std::vector<std::int16_t> reply = run_graph(utterance("what time is it", 500, 1500));
  CHECK(rms(reply) < 100.0);
}
