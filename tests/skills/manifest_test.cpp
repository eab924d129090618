// skill.json validation: every error names the file and the JSON path of the bad field.
#include "skills/manifest.h"

#include <doctest/doctest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

using marvin::skills::Manifest;
using marvin::skills::ManifestError;
using marvin::skills::parse_manifest;
using nlohmann::json;

namespace {

json valid() {
  return json::parse(R"json({
    "id": "dice", "name": "Dice", "version": "1.2.3-beta+7", "kind": "native",
    "host_api": {"min": "1.0", "max": "1.4"},
    "permissions": ["storage", "motion"],
    "intents": [
      {"name": "roll", "templates": ["roll [a] (die|dice)", "roll {count} dice"],
       "slots": [{"name": "count", "type": "number", "required": true, "question": "How many?"}],
       "confirm": true, "confirm_question": "Roll {count}?", "execution": "long", "time_limit_s": 5,
       "stopped": "All right, I stopped rolling.", "urgent": true},
      {"name": "pick", "templates": ["pick the {colour} one"],
       "slots": [{"name": "colour", "type": "list", "values": ["red", "light blue"]}]}
    ]})json");
}

// The message of the ManifestError thrown for `document`.
std::string error_of(const json& document) {
  try {
    parse_manifest(document, "skills/dice/skill.json");
  } catch (const ManifestError& e) {
    return e.what();
  }
  return "(no error)";
}

}  // namespace

TEST_CASE("a valid manifest: every field read, defaults filled in") {
  Manifest m = parse_manifest(valid(), "skills/dice/skill.json");
  CHECK(m.id == "dice");
  CHECK(m.version.major == 1);
  CHECK(m.version.minor == 2);
  CHECK(m.version.patch == 3);
  CHECK(m.version.text == "1.2.3-beta+7");
  CHECK(m.kind == "native");
  CHECK(m.entry == "skill.so");
  CHECK(m.has_permission("storage"));
  CHECK(m.has_permission("speech"));  // implicit
  CHECK_FALSE(m.has_permission("phone"));
  REQUIRE(m.intents.size() == 2);
  const auto& roll = m.intents[0];
  CHECK(roll.templates.size() == 2);
  REQUIRE(roll.slots.size() == 1);
  CHECK(roll.slots[0].kind == marvin::skills::SlotKind::kNumber);
  CHECK(roll.slots[0].required);
  CHECK(roll.slots[0].question == "How many?");
  CHECK(roll.confirm);
  CHECK(roll.execution == marvin::skills::Execution::kLong);
  CHECK(roll.time_limit_ms == 5000);
  CHECK(m.intents[1].slots[0].values == std::vector<std::string>{"red", "light blue"});
  CHECK(m.intents[1].execution == marvin::skills::Execution::kShort);
  CHECK_FALSE(m.intents[1].confirm);
  CHECK(roll.stopped == "All right, I stopped rolling.");
  CHECK(m.intents[1].stopped.empty());  // the manager then says "OK, I stopped."
  CHECK(roll.urgent);
  CHECK_FALSE(m.intents[1].urgent);

  CHECK(m.accepts_host_api({1, 0}));
  CHECK(m.accepts_host_api({1, 4}));
  CHECK_FALSE(m.accepts_host_api({1, 5}));
  CHECK_FALSE(m.accepts_host_api({2, 0}));
}

TEST_CASE("without host_api.max any minor of the same major is accepted") {
  json d = valid();
  d["host_api"].erase("max");
  Manifest m = parse_manifest(d, "x");
  CHECK(m.accepts_host_api({1, 99}));
  CHECK_FALSE(m.accepts_host_api({2, 0}));
  CHECK_FALSE(m.accepts_host_api({0, 9}));
}

TEST_CASE("missing fields are named with their path") {
  json d = valid();
  d.erase("id");
  CHECK(error_of(d) == "skills/dice/skill.json: $.id: missing required field (a string)");

  d = valid();
  d["host_api"].erase("min");
  CHECK(error_of(d) == "skills/dice/skill.json: $.host_api.min: missing required field (a string)");

  d = valid();
  d["intents"][1].erase("templates");
  CHECK(error_of(d) ==
        "skills/dice/skill.json: $.intents[1].templates: missing required field (an array of "
        "strings)");

  d = valid();
  d["intents"][0]["slots"][0].erase("question");
  CHECK(error_of(d) ==
        "skills/dice/skill.json: $.intents[0].slots[0].question: a required slot "
        "needs the question to ask when it is missing");
}

TEST_CASE("wrong types and values are named with their path") {
  json d = valid();
  d["intents"][0]["stopped"] = true;
  CHECK(error_of(d) ==
        "skills/dice/skill.json: $.intents[0].stopped: expected a string, got a boolean");

  d = valid();
  d["intents"][0]["urgent"] = "yes";
  CHECK(error_of(d) ==
        "skills/dice/skill.json: $.intents[0].urgent: expected true or false, got a string");

  d = valid();
  d["version"] = 1;
  CHECK(error_of(d) == "skills/dice/skill.json: $.version: expected a string, got an integer");

  d = valid();
  d["version"] = "1.2";
  CHECK(error_of(d) ==
        "skills/dice/skill.json: $.version: expected a semantic version "
        "MAJOR.MINOR.PATCH such as \"1.0.0\", got \"1.2\"");

  d = valid();
  d["kind"] = "python";
  CHECK(error_of(d) ==
        "skills/dice/skill.json: $.kind: expected \"native\" or \"lua\", got \"python\"");

  d = valid();
  d["intents"][0]["slots"][0]["required"] = "yes";
  CHECK(error_of(d) ==
        "skills/dice/skill.json: $.intents[0].slots[0].required: expected true or false, got a "
        "string");

  d = valid();
  d["intents"][1]["slots"][0]["type"] = "colour";
  CHECK(error_of(d) ==
        "skills/dice/skill.json: $.intents[1].slots[0].type: expected one of number, "
        "duration, datetime, contact, list, text; got \"colour\"");

  d = valid();
  d["permissions"][1] = "teleport";
  CHECK(error_of(d).rfind(
            "skills/dice/skill.json: $.permissions[1]: unknown permission \"teleport\"", 0) == 0);

  d = valid();
  d["intents"] = json::object();
  CHECK(error_of(d) == "skills/dice/skill.json: $.intents: expected an array, got an object");

  d = valid();
  d["host_api"]["max"] = "0.9";
  CHECK(error_of(d) == "skills/dice/skill.json: $.host_api.max: is older than \"min\"");

  d = valid();
  d["entry"] = "../../evil.so";
  CHECK(error_of(d).find("$.entry: expected a file name inside the skill's folder") !=
        std::string::npos);
}

TEST_CASE("bad templates: the path, the template and the position") {
  json d = valid();
  d["intents"][0]["templates"][0] = "roll (a|b die";
  CHECK(error_of(d) ==
        "skills/dice/skill.json: $.intents[0].templates[0]: template \"roll (a|b die\" "
        "at position 6: '(' is never closed");

  d = valid();
  d["intents"][0]["templates"][1] = "roll {number} dice";
  CHECK(error_of(d) ==
        "skills/dice/skill.json: $.intents[0].templates[1]: template \"roll {number} "
        "dice\" at position 6: slot {number} is not declared in this intent's \"slots\"");

  d = valid();
  d["intents"][1]["templates"][0] = "pick] it";
  CHECK(error_of(d) ==
        "skills/dice/skill.json: $.intents[1].templates[0]: template \"pick] it\" at "
        "position 5: ']' closes nothing");

  d = valid();
  d["intents"][1]["templates"][0] = "pick (a||b) {colour}";
  CHECK(error_of(d).find("at position 9: empty alternative") != std::string::npos);

  d = valid();
  d["intents"][1]["templates"][0] = "[ ]";
  CHECK(error_of(d) ==
        "skills/dice/skill.json: $.intents[1].templates[0]: template \"[ ]\" has no words");
}

TEST_CASE("load_manifest: unreadable files and JSON syntax errors name the file") {
  namespace fs = std::filesystem;
  fs::path dir = fs::temp_directory_path() / ("marvin_manifest_test_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  fs::path file = dir / "skill.json";
  {
    std::ofstream out(file);
    out << "{\"id\": \"dice\",\n \"name\": }";
  }
  try {
    marvin::skills::load_manifest(file);
    FAIL("expected a ManifestError");
  } catch (const ManifestError& e) {
    CHECK(e.file() == file.string());
    CHECK(std::string(e.what()).rfind(file.string() + ": $: not valid JSON at byte 25", 0) == 0);
  }
  CHECK_THROWS_WITH_AS(marvin::skills::load_manifest(dir / "missing.json"),
                       ((dir / "missing.json").string() + ": $: cannot read the file").c_str(),
                       ManifestError);
  fs::remove_all(dir);
}
