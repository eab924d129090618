// Finding people and guarding (issue 22) through `marvin run --sim` in the default home, as
// a user types: Anna is enrolled by voice first; Sam (the world's visitor, face-api's
// sample2) is a face nobody enrolled. Real process, real camera pipeline, real SQLite.
#include <doctest/doctest.h>
#include <signal.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "support/child_process.h"
#include "support/files.h"

namespace fs = std::filesystem;
using marvin::test_support::ChildProcess;
using marvin::test_support::exit_code;

namespace {

ChildProcess start_home(const fs::path& dir) {
  fs::create_directories(dir / "skills");
  return ChildProcess({MARVIN_EXE, "run", "--sim", "--data-dir", (dir / "data").string(),
                       "--skills-dir", (dir / "skills").string(), "--speed", "20"});
}

void enrol_anna(ChildProcess& marvin) {
  marvin.wait_for_line("Marvin: Hello, I'm Marvin.");
  marvin.send_line("go to Anna");
  marvin.wait_for_line("Marvin: I'm at Anna, in the living room.");
  marvin.send_line("this is Anna");
  marvin.wait_for_line("Marvin: Shall I remember this face as Anna?");
  marvin.send_line("yes");
  marvin.wait_for_line("Marvin: Nice to meet you, Anna. I'll remember your face.");
}

}  // namespace

// Anna's face is recognised from about 2 m; the living room's spot is some 2.8 m from her, so
// a search that arrives there sees a face it cannot name about half the time: the finding
// skill then goes closer and looks again (finding_skill.cpp, closer_look). Without that this
// scenario failed about half the runs once looks also ran the COCO detector.
TEST_CASE("run --sim: find Anna from the kitchen, then from memory; who is in the bedroom") {
  marvin::test_support::TempDir dir;
  ChildProcess marvin = start_home(dir.path());
  enrol_anna(marvin);
  marvin.send_line("go to the kitchen");
  marvin.wait_for_line("Marvin: I'm in the kitchen.");
  marvin.send_line("find anna");
  marvin.wait_for_line("Marvin: I'll look for Anna.");
  marvin.wait_for_line_containing("Marvin: Anna is in the living room");
  marvin.send_line("where is anna");
  marvin.wait_for_line_containing("Marvin: I saw Anna in the living room");
  marvin.wait_for_line("Marvin: Shall I look again?");
  marvin.send_line("no");
  // A line typed while a skill is still finishing is not a new request: wait until Marvin
  // listens again.
  marvin.wait_for_line("[light: awaiting (red)]");
  marvin.send_line("is anyone in the bedroom");
  marvin.wait_for_line("Marvin: Yes: someone I don't know is in the bedroom.");
  marvin.send_line("tell anna dinner is ready");
  marvin.wait_for_line("Marvin: I'll tell Anna.");
  marvin.wait_for_line("Marvin: Anna, dinner is ready.");
  // Bad input: an unknown room, somebody nobody knows.
  marvin.send_line("is anyone in the garage");
  marvin.wait_for_line("Marvin: I don't know a room called the garage.");
  marvin.send_line("tell bob dinner is ready");
  marvin.wait_for_line("Marvin: I don't know anyone called Bob.");
  // "No" while it searches (and asks nothing) stops the search.
  marvin.send_line("find anna");
  marvin.wait_for_line("Marvin: I'll look for Anna.");
  marvin.send_line("no");
  marvin.wait_for_line("Marvin: All right, I stopped looking.");
  CHECK(exit_code(marvin.finish()) == 0);
  CHECK(marvin.output().find("[collision") == std::string::npos);
}

TEST_CASE("run --sim: guard mode alerts on Sam with a photo; only Anna's face turns it off") {
  marvin::test_support::TempDir dir;
  ChildProcess marvin = start_home(dir.path());
  enrol_anna(marvin);
  marvin.send_line("go to Sam");
  marvin.wait_for_line("Marvin: I'm at Sam, in the bedroom.");
  marvin.send_line("guard the house");
  marvin.wait_for_line_containing("Marvin: OK, I'm guarding the house.");
  marvin.wait_for_line(
      "Marvin: Intruder alert! I see someone I don't know in the bedroom. I took a photo and "
      "told your carer.");
  marvin.send_line("i'm home");
  marvin.wait_for_line(
      "Marvin: I can only stop guarding for someone I know. Please let me see your face.");
  marvin.send_line("go to Anna");
  marvin.wait_for_line("Marvin: I'm at Anna, in the living room.");
  marvin.send_line("i'm home");
  marvin.wait_for_line_containing("Marvin: Welcome back, Anna. I stopped guarding.");
  marvin.send_line("who came while i was out");
  marvin.wait_for_line_containing("Marvin: One visitor: someone I don't know in the bedroom");
  CHECK(exit_code(marvin.finish()) == 0);
  // Exactly one alert (several frames of one visitor are one alert), and its photo is kept.
  const std::string out = marvin.output();
  CHECK(out.find("Intruder alert!") == out.rfind("Intruder alert!"));
  int photos = 0;
  for (const auto& e : fs::directory_iterator(dir.path() / "data" / "photos" / "guard")) {
    if (e.path().extension() == ".jpg" && fs::file_size(e.path()) > 1000) ++photos;
  }
  CHECK(photos == 1);
}

TEST_CASE("run --sim: guide me to the kitchen arrives without a collision; the sonar tells") {
  marvin::test_support::TempDir dir;
  fs::create_directories(dir.path() / "skills");
  ChildProcess marvin({MARVIN_EXE, "run", "--sim", "--in-memory", "--skills-dir",
                       (dir.path() / "skills").string(), "--speed", "20"});
  marvin.wait_for_line("Marvin: Hello, I'm Marvin.");
  marvin.send_line("guide me to the kitchen");
  marvin.wait_for_line(
      "Marvin: Follow me to the kitchen. I'll go slowly and tell you what's ahead.");
  marvin.wait_for_line("Marvin: We're there: the kitchen.");
  marvin.send_line("guide me to the garage");
  marvin.wait_for_line("Marvin: I don't know where the garage is.");
  marvin.send_line("is the way clear");
  const std::string answer = marvin.wait_for_line_containing("Marvin: ");
  CHECK((answer.find("Marvin: Yes, the way ahead is clear") == 0 ||
         answer.find("Marvin: No: ") == 0));
  CHECK(exit_code(marvin.finish()) == 0);
  CHECK(marvin.output().find("[collision") == std::string::npos);
}

// Ctrl-C (SIGINT) while a task runs stops it as "stop" does and ends Marvin, the input
// still open (a terminal where nobody typed Ctrl-D). Real time (no --speed): the walk to
// the kitchen takes long enough to be under way.
TEST_CASE("run --sim: SIGINT while guiding stops the guide and ends Marvin with exit 0") {
  marvin::test_support::TempDir dir;
  fs::create_directories(dir.path() / "skills");
  ChildProcess marvin({MARVIN_EXE, "run", "--sim", "--in-memory", "--skills-dir",
                       (dir.path() / "skills").string()});
  marvin.wait_for_line("Marvin: Hello, I'm Marvin.");
  marvin.send_line("guide me to the kitchen");
  marvin.wait_for_line(
      "Marvin: Follow me to the kitchen. I'll go slowly and tell you what's ahead.");
  REQUIRE(::kill(marvin.pid(), SIGINT) == 0);
  marvin.wait_for_line("[SIGINT: stopping]");
  marvin.wait_for_line("Marvin: OK, I stopped.");
  CHECK_FALSE(marvin.read_until([](const std::string&) { return false; }));  // it exited
  CHECK(exit_code(marvin.finish()) == 0);
  CHECK(marvin.output().find("We're there") == std::string::npos);
}

// Object finding with what the COCO detector names in the default home (the bicycle in the
// hall, the dog in the living room; examples/worlds/home.json): never seen, so it searches,
// says the room and the nearest furniture, offers to lead the way; then from memory.
TEST_CASE("run --sim: where is my bike, then from memory; unknown things are said so") {
  marvin::test_support::TempDir dir;
  ChildProcess marvin = start_home(dir.path());
  marvin.wait_for_line("Marvin: Hello, I'm Marvin.");
  // Bad input first: nothing taught or detectable by these names; nothing is searched.
  marvin.send_line("where are my keys");
  marvin.wait_for_line(
      "Marvin: I don't know what your keys look like, and I have never seen them. Show me and "
      "say \"these are my keys\".");
  marvin.send_line("find the unicorn");
  marvin.wait_for_line("Marvin: I don't know who or what unicorn is.");
  marvin.send_line("where is my bike");
  marvin.wait_for_line("Marvin: I'll look for your bicycle.");
  marvin.wait_for_line_containing("Marvin: Your bicycle is in the hall");
  marvin.wait_for_line("Marvin: Shall I show you the way?");
  marvin.send_line("yes");
  marvin.wait_for_line("Marvin: Here we are: the hall.");
  marvin.send_line("where is my bike");
  marvin.wait_for_line_containing("Marvin: I saw your bicycle in the hall");
  marvin.wait_for_line("Marvin: Shall I look again?");
  marvin.send_line("no");
  marvin.wait_for_line("[light: awaiting (red)]");
  CHECK(exit_code(marvin.finish()) == 0);
  const std::string out = marvin.output();
  CHECK(out.find("[collision") == std::string::npos);
  // The bad requests moved nothing: no trip before the bicycle's search.
  CHECK(out.find("[move") > out.find("Marvin: I'll look for your bicycle."));
}

// `marvin guard status|off` from another process reaches the running Marvin through its
// data directory's SQLite store.
TEST_CASE("run --sim: marvin guard off from the command line ends guard mode") {
  marvin::test_support::TempDir dir;
  ChildProcess marvin = start_home(dir.path());
  const std::string data = (dir.path() / "data").string();
  auto cli = [&](const char* verb) {
    ChildProcess c({MARVIN_EXE, "guard", verb, "--data-dir", data});
    CHECK(exit_code(c.finish()) == 0);
    return c.output();
  };
  marvin.wait_for_line("Marvin: Hello, I'm Marvin.");
  CHECK(cli("status") == "guard mode: off (never turned on)\n");
  CHECK(cli("off") == "guard mode is already off; nothing changed\n");
  marvin.send_line("guard the house");
  marvin.wait_for_line_containing("Marvin: OK, I'm guarding the house.");
  CHECK(cli("status").rfind("guard mode: on since ", 0) == 0);
  CHECK(cli("off") == "guard mode: off (a running Marvin stops watching before its next look)\n");
  marvin.wait_for_line("Marvin: Guard mode is off: it was turned off from the command line.");
  CHECK(cli("status") ==
        "guard mode: off (turned off by the command line), 0 alerts in the last "
        "watch\n");
  CHECK(exit_code(marvin.finish()) == 0);
}

namespace {

// The default home with a TV (a box marked "screen": true on the tv stand) showing a
// stranger's face (Sam's photo as a card on it) and the robot 1.7 m in front of it, the TV a
// little left of straight ahead. With `sam_beside_tv`, Sam himself stands right of the TV
// (else in the bedroom, out of view).
std::filesystem::path tv_world(const fs::path& dir, bool sam_beside_tv) {
  const fs::path source = MARVIN_HOME_WORLD;
  nlohmann::json w = nlohmann::json::parse(std::ifstream(source));
  nlohmann::json tv_face;
  for (auto& p : w["people"]) {
    p["photo"] = (source.parent_path() / p["photo"].get<std::string>()).lexically_normal().string();
    if (p["name"] == "Sam") tv_face = p;
  }
  for (auto& o : w["objects"]) {
    o["photo"] = (source.parent_path() / o["photo"].get<std::string>()).lexically_normal().string();
  }
  tv_face["name"] = "face on the tv";
  tv_face["at"] = {1.0, 4.6};
  tv_face["room"] = "living room";
  tv_face["elevation_m"] = 0.6;
  tv_face.erase("owner");
  w["objects"].push_back(tv_face);
  w["furniture"].push_back({{"name", "tv"},
                            {"room", "living room"},
                            {"min", {0.6, 4.45}},
                            {"max", {1.4, 4.75}},
                            {"height_m", 1.1},
                            {"screen", true}});
  if (sam_beside_tv) {
    for (auto& p : w["people"]) {
      if (p["name"] == "Sam") {
        p["at"] = {1.8, 4.29};
        p["room"] = "living room";
      }
    }
  }
  w["robot"]["start"] = {1.0, 2.9};
  w["robot"]["heading_deg"] = 80;
  const fs::path file = dir / "tv.json";
  std::ofstream(file) << w.dump(1);
  return file;
}

ChildProcess start_tv_home(const fs::path& dir, bool sam_beside_tv) {
  fs::create_directories(dir / "skills");
  return ChildProcess({MARVIN_EXE, "run", "--sim", "--world", tv_world(dir, sam_beside_tv).string(),
                       "--data-dir", (dir / "data").string(), "--skills-dir",
                       (dir / "skills").string(), "--speed", "20"});
}

std::string guard_status(const fs::path& dir) {
  ChildProcess c({MARVIN_EXE, "guard", "status", "--data-dir", (dir / "data").string()});
  CHECK(exit_code(c.finish()) == 0);
  return c.output();
}

}  // namespace

// Issue 22: a face on the TV is a picture. The guard watches the TV (a stranger's face on it)
// until it has set that face aside in 40 looks (10 s of robot time; `marvin guard status`
// counts them), and no alert comes; then Sam standing beside the TV is alerted.
TEST_CASE("run --sim: guard mode takes the face on the TV for a picture; Sam beside it alerts") {
  {
    marvin::test_support::TempDir dir;
    ChildProcess marvin = start_tv_home(dir.path(), false);
    marvin.wait_for_line("Marvin: Hello, I'm Marvin.");
    marvin.send_line("guard the house");
    marvin.wait_for_line_containing("Marvin: OK, I'm guarding the house.");
    // The status is stored at the first picture and every 20th: wait for the 40th.
    auto pictures = [](const std::string& status) {
      const auto at = status.find(" alerts, ");
      return at == std::string::npos ? 0 : std::atoi(status.c_str() + at + 9);
    };
    std::string status;
    for (int i = 0; i < 600 && pictures(status) < 40; ++i) status = guard_status(dir.path());
    CHECK(status.find("guard mode: on since ") == 0);
    CHECK(status.find(", 0 alerts, ") != std::string::npos);
    CHECK(status.find(" looks saw only pictures (a TV)") != std::string::npos);
    CHECK(pictures(status) >= 40);
    CHECK(exit_code(marvin.finish()) == 0);
    CHECK(marvin.output().find("Intruder alert") == std::string::npos);
  }
  {
    marvin::test_support::TempDir dir;
    ChildProcess marvin = start_tv_home(dir.path(), true);
    marvin.wait_for_line("Marvin: Hello, I'm Marvin.");
    marvin.send_line("guard the house");
    marvin.wait_for_line(
        "Marvin: Intruder alert! I see someone I don't know in the living room. I took a photo "
        "and told your carer.");
    CHECK(exit_code(marvin.finish()) == 0);
  }
}
