// `marvin run --sim` in the default home, as a user types to it: "go to the kitchen" ends in
// the kitchen without a collision; "stop" stops the wheels at once; --show keeps a picture;
// a broken --world is refused naming the element. Real process, stdin and stdout; every wait
// is on the output with a generous timeout.
#include <doctest/doctest.h>
#include <sys/wait.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "support/child_process.h"
#include "support/files.h"

namespace fs = std::filesystem;
using marvin::test_support::ChildProcess;
using marvin::test_support::exit_code;

namespace {

ChildProcess start_marvin(const fs::path& dir, std::vector<std::string> extra) {
  fs::create_directories(dir / "skills");
  std::vector<std::string> argv{
      MARVIN_EXE, "run", "--sim", "--in-memory", "--skills-dir", (dir / "skills").string(),
      "--speed",  "20"};
  argv.insert(argv.end(), extra.begin(), extra.end());
  return ChildProcess(argv);
}

}  // namespace

TEST_CASE("run --sim: typing \"go to the kitchen\" ends in the kitchen without a collision") {
  marvin::test_support::TempDir dir;
  const fs::path picture = dir.path() / "map.png";
  ChildProcess marvin = start_marvin(dir.path(), {"--show", picture.string()});
  marvin.wait_for_line("Marvin: Hello, I'm Marvin.");
  marvin.send_line("where are you");
  marvin.wait_for_line("Marvin: I'm in the hall.");
  marvin.send_line("go to the kitchen");
  marvin.wait_for_line("Marvin: On my way to the kitchen.");
  marvin.wait_for_line("Marvin: I'm in the kitchen.");
  marvin.send_line("where are you");
  marvin.wait_for_line("Marvin: I'm in the kitchen.");
  CHECK(fs::file_size(picture) > 1000);
  CHECK(exit_code(marvin.finish()) == 0);
  CHECK(marvin.output().find("[collision") == std::string::npos);
}

TEST_CASE("run --sim: \"stop\" wins over going places and the robot stays where it stopped") {
  marvin::test_support::TempDir dir;
  ChildProcess marvin = start_marvin(dir.path(), {});
  marvin.wait_for_line("Marvin: Hello, I'm Marvin.");
  marvin.send_line("go to the bathroom");
  marvin.wait_for_line("Marvin: On my way to the bathroom.");
  marvin.send_line("stop");
  marvin.wait_for_line("Marvin: OK, I stopped.");
  marvin.send_line("where are you");
  const std::string where = marvin.wait_for_line_containing("Marvin: I'm in");
  CHECK(where != "Marvin: I'm in the bathroom.");
  CHECK(exit_code(marvin.finish()) == 0);
  CHECK(marvin.output().find("I'm in the bathroom.") == std::string::npos);
}

TEST_CASE("run --sim --world with a broken world file: refused, naming the element") {
  marvin::test_support::TempDir dir;
  const fs::path world = dir.path() / "broken.json";
  std::ofstream(world) << R"({"format": "marvin-world", "version": 1,
    "rooms": [{"name": "hall", "outline": [[0,0],[4,0],[4,3],[0,3]]}],
    "doors": [{"name": "back door", "at": [2, 2], "rooms": ["hall"]}],
    "robot": {"start": [1, 1]}})";
  ChildProcess marvin = start_marvin(dir.path(), {"--world", world.string()});
  CHECK(exit_code(marvin.finish()) == 2);
  CHECK(marvin.errors().find("doors[0] \"back door\": 'at' [2, 2] is not on a wall") !=
        std::string::npos);
}

TEST_CASE("marvin world render: a PNG of the floor plan with a path; unknown places are named") {
  marvin::test_support::TempDir dir;
  const fs::path map = dir.path() / "map.png", view = dir.path() / "view.png";
  ChildProcess render({MARVIN_EXE, "world", "render", "--out", map.string(), "--to", "kitchen",
                       "--camera", view.string()});
  CHECK(exit_code(render.finish()) == 0);
  CHECK(render.output().find("wrote " + map.string() +
                             " (5 rooms, 14 pieces of furniture, a path of") != std::string::npos);
  for (const fs::path& png : {map, view}) {
    std::ifstream in(png, std::ios::binary);
    char magic[8] = {};
    in.read(magic, 8);
    CHECK(std::string(magic + 1, 3) == "PNG");
  }
  ChildProcess unknown(
      {MARVIN_EXE, "world", "render", "--out", map.string(), "--to", "the garage"});
  CHECK(exit_code(unknown.finish()) == 1);
  CHECK(unknown.errors().find("--to: \"the garage\" is not a room, place or person of") !=
        std::string::npos);
}

TEST_CASE("run --sim: after \"go to Anna\" the robot faces her, so \"who is this?\" sees her") {
  marvin::test_support::TempDir dir;
  fs::create_directories(dir.path() / "skills");
  ChildProcess marvin({MARVIN_EXE, "run", "--sim", "--data-dir", (dir.path() / "data").string(),
                       "--skills-dir", (dir.path() / "skills").string(), "--speed", "20"});
  marvin.wait_for_line("Marvin: Hello, I'm Marvin.");
  marvin.send_line("go to Anna");
  marvin.wait_for_line("Marvin: On my way to Anna.");
  marvin.wait_for_line("Marvin: I'm at Anna, in the living room.");
  marvin.send_line("who is this");
  marvin.wait_for_line("Marvin: That's someone I don't know.");
  marvin.send_line("this is Anna");
  marvin.wait_for_line("Marvin: Shall I remember this face as Anna?");
  marvin.send_line("yes");
  marvin.wait_for_line("Marvin: Nice to meet you, Anna. I'll remember your face.");
  marvin.send_line("who is this");
  marvin.wait_for_line("Marvin: That's Anna.");
  CHECK(exit_code(marvin.finish()) == 0);
  CHECK(marvin.output().find("the anna") == std::string::npos);
}

TEST_CASE("run --sim: guiding to the bathroom tells the way and arrives; \"stop\" stops it") {
  marvin::test_support::TempDir dir;
  ChildProcess marvin = start_marvin(dir.path(), {});
  marvin.wait_for_line("Marvin: Hello, I'm Marvin.");
  marvin.send_line("guide me to the bathroom");  // up the hall, then left through its door
  marvin.wait_for_line(
      "Marvin: Follow me to the bathroom. I'll go slowly and tell you what's ahead.");
  CHECK(marvin.wait_for_line_containing("Marvin: It's about ").find(" metres.") !=
        std::string::npos);
  CHECK(marvin.wait_for_line_containing(", we turn ").find("Marvin: In ") == 0);
  marvin.wait_for_line("Marvin: We're there: the bathroom.");
  marvin.send_line("guide me to the bedroom");
  marvin.wait_for_line(
      "Marvin: Follow me to the bedroom. I'll go slowly and tell you what's ahead.");
  marvin.send_line("stop");
  marvin.wait_for_line("Marvin: OK, I stopped.");
  marvin.send_line("where are you");
  CHECK(marvin.wait_for_line_containing("Marvin: I'm in") != "Marvin: I'm in the bedroom.");
  CHECK(exit_code(marvin.finish()) == 0);
  CHECK(marvin.output().find("[collision") == std::string::npos);
  CHECK(marvin.output().find("We're there: the bedroom.") == std::string::npos);
}

TEST_CASE("run --sim: a step down across the garden is told, stopped short of, never driven into") {
  marvin::test_support::TempDir dir;
  const fs::path world = dir.path() / "garden.json";
  // The hall and the garden; a step down 20 cm deep across the whole garden, 0.6 m past its
  // door, and a gate before it.
  std::ofstream(world) << R"({"format": "marvin-world", "version": 1,
    "rooms": [{"name": "hall", "outline": [[0,0],[4,0],[4,3],[0,3]]},
              {"name": "garden", "outline": [[4,0],[9,0],[9,3],[4,3]], "spot": [7.5, 1.5]}],
    "doors": [{"name": "garden door", "at": [4, 1.5], "width_m": 0.9,
               "rooms": ["hall", "garden"]}],
    "places": [{"name": "the gate", "at": [4.3, 2.6], "room": "garden"}],
    "drops": [{"name": "the garden step", "min": [4.6, 0], "max": [5.6, 3], "depth_m": 0.2}],
    "robot": {"start": [1, 1.5], "heading_deg": 0}})";
  ChildProcess marvin = start_marvin(dir.path(), {"--world", world.string()});
  marvin.wait_for_line("Marvin: Hello, I'm Marvin.");
  marvin.send_line("guide me to the garden");
  CHECK(
      marvin.wait_for_line_containing("Marvin: Careful: step down ahead, ").find("I've stopped.") !=
      std::string::npos);
  marvin.wait_for_line(
      "Marvin: I can't guide you to the garden: there is a step down on the way to the "
      "garden.");
  marvin.send_line("go to the garden");
  marvin.wait_for_line(
      "Marvin: Sorry, I can't get to the garden: there is a step down on the way to the "
      "garden.");
  marvin.send_line("guide me to the gate");
  marvin.wait_for_line("Marvin: We're there: the gate.");
  CHECK(exit_code(marvin.finish()) == 0);
  CHECK(marvin.output().find("[fell") == std::string::npos);
  CHECK(marvin.output().find("[collision") == std::string::npos);
}
