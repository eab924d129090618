// The SDK's C++ layer at the C boundary, the MockRobot and the in-process SkillHarness.
#include <doctest/doctest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <marvin/skill.hpp>
#include <marvin/testing/mock_robot.hpp>
#include <marvin/testing/skill_harness.hpp>

using Lines = std::vector<std::string>;

namespace {

class Moody : public marvin::Skill {
 public:
  explicit Moody(marvin::Robot robot) : Skill(robot) {
    if (this->robot().time_zone() == "Refuse/Start") throw std::runtime_error("I refuse to start");
  }
  void handle(const marvin::Request& r) override {
    if (r.intent == "fail") throw std::runtime_error("out of cheese");
    if (r.intent == "missing") throw marvin::Error(MARVIN_ERR_NOT_FOUND, "no such thing");
    if (r.intent == "weird") throw 42;
    if (r.intent == "move") robot().move(MARVIN_FORWARD, 120, std::chrono::milliseconds(1500));
    if (r.intent == "remember") {
      robot().storage_set("colour", r.slots.at("colour").get<std::string>());
      robot().say("I'll remember " + *robot().storage_get("colour") + ".");
    }
    if (r.intent == "remind") {
      nlohmann::json created =
          robot().schedule_add({{"title", "take my pills"}, {"at", r.slots.at("when").at("at")}});
      robot().say("OK, at " + created["at"].get<std::string>().substr(11) + ".");
    }
  }
};

const marvin_skill_descriptor* moody() { return marvin::skill_descriptor<Moody>("moody"); }

struct ManifestFile {
  std::filesystem::path path = std::filesystem::temp_directory_path() /
                               ("marvin_sdk_test_" + std::to_string(::getpid())) / "skill.json";
  ManifestFile() {
    std::filesystem::create_directories(path.parent_path());
    std::ofstream(path) << R"({"id": "moody", "name": "Moody", "version": "0.1.0", "kind": "native",
      "host_api": {"min": "1.0"}, "permissions": ["storage", "schedule"], "intents": [
        {"name": "fail", "templates": ["fail now"]},
        {"name": "move", "templates": ["move along"]},
        {"name": "remember", "templates": ["remember {colour}"],
         "slots": [{"name": "colour", "type": "list", "values": ["red", "green"]}]},
        {"name": "remind", "templates": ["remind me [{when}]"],
         "slots": [{"name": "when", "type": "datetime", "required": true, "question": "When?"}]}]})";
  }
  ~ManifestFile() { std::filesystem::remove_all(path.parent_path()); }
};

std::string text(const marvin_text_out& out) { return std::string(out.data, out.length); }

}  // namespace

TEST_CASE("exceptions become statuses and sentences at the C boundary") {
  marvin::testing::MockRobot robot("moody");
  const marvin_skill_descriptor* d = moody();
  CHECK(d->abi_major == MARVIN_ABI_MAJOR);
  CHECK(d->abi_minor == MARVIN_ABI_MINOR);
  CHECK(std::string(d->skill_id) == "moody");
  char buffer[256];
  marvin_text_out error{buffer, sizeof buffer, 0};
  void* instance = d->create(robot.api(), robot.host(), &error);
  REQUIRE(instance != nullptr);

  auto call = [&](const char* intent) {
    error = {buffer, sizeof buffer, 0};
    marvin_request r{sizeof(marvin_request), intent, "{}", intent};
    return d->handle(instance, &r, &error);
  };
  CHECK(call("fail") == MARVIN_ERR_INTERNAL);
  CHECK(text(error) == "out of cheese");
  CHECK(call("missing") == MARVIN_ERR_NOT_FOUND);
  CHECK(text(error) == "no such thing");
  CHECK(call("weird") == MARVIN_ERR_INTERNAL);
  CHECK(text(error) == "unknown exception in the skill");
  // A Robot API call the skill has no permission for throws, and comes back as its status.
  CHECK(call("move") == MARVIN_ERR_PERMISSION);
  CHECK(text(error) == "permission 'motion' is not granted to skill 'moody'");
  CHECK(robot.actions().empty());

  marvin_request bad{sizeof(marvin_request), "remember", "{not json", ""};
  error = {buffer, sizeof buffer, 0};
  CHECK(d->handle(instance, &bad, &error) == MARVIN_ERR_INTERNAL);
  CHECK(text(error).find("parse error") != std::string::npos);
  d->destroy(instance);
}

TEST_CASE("a constructor that throws refuses the instance with its message") {
  marvin::testing::MockRobot robot("moody");
  robot.set_time_zone("Refuse/Start");
  char buffer[8];  // too small: truncated, with the full length
  marvin_text_out error{buffer, sizeof buffer, 0};
  CHECK(moody()->create(robot.api(), robot.host(), &error) == nullptr);
  CHECK(error.length == std::string("I refuse to start").size());
  CHECK(std::string(buffer) == "I refus");
}

TEST_CASE("MockRobot: permissions, scripted answers, recorded actions") {
  marvin::testing::MockRobot robot("walker", {"motion", "light"});
  marvin::Robot r(robot.api(), robot.host());
  robot.add_answer("the kitchen");
  CHECK(r.ask("Where to?") == "the kitchen");
  r.say("Off I go.");
  r.set_light(MARVIN_LIGHT_EXECUTING);
  r.move(MARVIN_FORWARD, 120, std::chrono::milliseconds(1500));
  r.tilt_head(-20);
  CHECK(robot.said() == Lines{"Where to?", "Off I go."});
  CHECK(robot.asked() == Lines{"Where to?"});
  CHECK(robot.actions() ==
        Lines{"light executing", "move forward speed=120 ms=1500", "tilt_head -20"});

  // No answer left: ask() is cancelled, as if the user said stop.
  try {
    r.ask("Anything else?");
    FAIL("ask() should throw");
  } catch (const marvin::Error& e) {
    CHECK(e.status() == MARVIN_ERR_CANCELLED);
  }
  CHECK_THROWS_WITH_AS(r.storage_set("k", "v"),
                       "permission 'storage' is not granted to skill 'walker'", marvin::Error);
  robot.cancel();
  CHECK(r.cancelled());
  CHECK_THROWS_AS(r.move(MARVIN_FORWARD, 1, std::chrono::milliseconds(1)), marvin::Error);
  CHECK(robot.actions().size() == 3);

  robot.set_permissions({"sensors"});
  robot.set_now(1767603600000);
  robot.set_scan({{0, 1.25, 1767603599000}});
  std::vector<marvin_scan_point> scan = r.obstacle_scan();
  REQUIRE(scan.size() == 1);
  CHECK(scan[0].distance_m == 1.25);
  CHECK(scan[0].time_ms == 1767603599000);
  CHECK(r.now_ms() == 1767603600000);
}

TEST_CASE("SkillHarness with an in-process skill: interpreter, manager and mock together") {
  ManifestFile manifest;
  marvin::testing::SkillHarness harness(manifest.path, moody());
  CHECK(harness.intent_of("remember green") == "moody/remember");
  CHECK(harness.intent_of("forget everything") == "");

  CHECK(harness.say("remember green") == Lines{"I'll remember green."});
  CHECK(harness.robot().stored("colour") == "green");
  CHECK(harness.say("fail now") == Lines{"Sorry, something went wrong with Moody."});

  harness.robot().set_time_zone("Europe/Berlin");
  CHECK(harness.say("remind me", {"at 8 pm"}) == Lines{"When?", "OK, at 20:00."});
  REQUIRE(harness.robot().reminders().size() == 1);
  nlohmann::json reminder = nlohmann::json::parse(harness.robot().reminders()[0]);
  CHECK(reminder["title"] == "take my pills");
  CHECK(reminder["at"] == "2026-01-05T20:00");
  CHECK(reminder["created_by"] == "moody");
}

TEST_CASE("SkillHarness refuses what the robot would refuse, with the robot's message") {
  std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("marvin_sdk_bad_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "skill.json") << R"({"id": "moody", "name": "Moody", "version": "0.1.0",
    "kind": "native", "host_api": {"min": "1.0"}, "intents": [{"name": "x", "templates": ["x"]}]})";
  CHECK_THROWS_WITH(marvin::testing::SkillHarness{dir},
                    ("skill 'moody': library " + (dir / "skill.so").string() +
                     " does not exist (\"entry\" in skill.json)")
                        .c_str());
  std::filesystem::remove_all(dir);
}
