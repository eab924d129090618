// A skill's manifest (skill.json): who the skill is, what it may do, and which sentences
// it answers.
//
// Format (every field is checked; unknown fields are ignored so newer manifests still load):
//
//   {
//     "id": "dice",                       // [a-z0-9][a-z0-9._-]*, unique on the robot
//     "name": "Dice",                     // shown to the carer
//     "version": "1.2.0",                 // semver MAJOR.MINOR.PATCH[-pre][+build]
//     "kind": "native",                   // "native" (a shared library) or "lua"
//     "entry": "skill.so",                // optional; default "skill.so" (native), "main.lua"
//     (lua) "host_api": {"min": "1.0", "max": "1.9"},  // Robot API versions the skill works with;
//                                         // "max" optional (default: any minor of min's major)
//     "permissions": ["speech", "motion"],// see sdk/include/marvin/robot.h
//     "intents": [{
//       "name": "roll",
//       "templates": ["roll [a] (die|dice)", "roll {count} dice"],
//       "slots": [{"name": "count", "type": "number", "required": false,
//                  "question": "How many dice?"}],
//       "examples": ["could you throw a die for me", ...],  // optional; natural sentences
//                                         // (no template syntax) that train the intent model
//       "synonyms": {"die": ["cube"]},    // optional; template word -> words said instead
//       "description": "a dice roll",     // optional; named in "Did you want ... or ...?"
//       "confirm": false,                 // optional; ask "confirm_question" before acting
//       "confirm_question": "Shall I roll {count} dice?",  // optional; {slot} = words heard
//       "stopped": "All right, I stopped looking.",  // optional; said when "stop"/"no" ends
//                                         // this intent's task (default "OK, I stopped.")
//       "execution": "short",             // optional; "short" (host loop) or "long" (worker)
//       "time_limit_s": 60                // optional; long intents only
//     }]
//   }
//
// Slot types: number, duration, datetime, contact, list (with "values": [...]), text.
// A required slot needs a "question" (asked when the user did not say it).
#pragma once

#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

namespace marvin::skills {

// A manifest that cannot be used. what() reads "<file>: <json path>: <problem>", e.g.
// "skills/dice/skill.json: $.intents[0].slots[1].type: expected one of number, duration,
// datetime, contact, list, text; got \"colour\"".
class ManifestError : public std::runtime_error {
 public:
  ManifestError(const std::string& file, const std::string& json_path, const std::string& problem);
  const std::string& file() const { return file_; }
  const std::string& json_path() const { return json_path_; }

 private:
  std::string file_;
  std::string json_path_;
};

struct SemVer {
  int major = 0;
  int minor = 0;
  int patch = 0;
  std::string text;  // as written, e.g. "1.2.0-beta"
};

// MAJOR.MINOR of the Robot API (marvin/robot.h).
struct ApiVersion {
  int major = 0;
  int minor = 0;
};

enum class SlotKind { kNumber, kDuration, kDateTime, kContact, kList, kText };
const char* to_string(SlotKind kind);

struct SlotDecl {
  std::string name;
  SlotKind kind = SlotKind::kText;
  std::vector<std::string> values;  // kList: the items the user may say
  bool required = false;
  std::string question;  // asked when a required slot is missing
};

enum class Execution { kShort, kLong };

struct IntentDecl {
  std::string name;
  std::vector<std::string> templates;
  std::vector<SlotDecl> slots;
  std::string description;  // "a reminder": how to name it in "Did you want ...?" (optional)
  std::vector<std::string> examples;  // natural sentences for the intent model (optional)
  // word in the templates -> words people say instead ("reminder": ["alarm"]) (optional)
  std::vector<std::pair<std::string, std::vector<std::string>>> synonyms;
  bool confirm = false;
  std::string confirm_question;  // default "Shall I go ahead?"
  std::string stopped;  // said when "stop" ends this task; "" = "OK, I stopped." (optional)
  // Said while another task runs or asks, a request of this intent (word for word) stops
  // that task and runs at once: a call for help must not wait for a search to end.
  bool urgent = false;
  Execution execution = Execution::kShort;
  std::int64_t time_limit_ms = 60'000;

  const SlotDecl* slot(const std::string& slot_name) const;
};

struct Manifest {
  std::filesystem::path file;  // where it was read from ("" when parsed from text)
  std::string id;
  std::string name;
  SemVer version;
  std::string kind;   // "native" or "lua"
  std::string entry;  // file name relative to the skill's folder
  ApiVersion host_api_min;
  ApiVersion host_api_max;  // inclusive
  std::vector<std::string> permissions;
  std::vector<IntentDecl> intents;
  nlohmann::json raw;  // the whole document, for runtimes that read extra fields

  bool has_permission(const std::string& permission) const;
  const IntentDecl* intent(const std::string& intent_name) const;
  // True when the host's Robot API version lies in [host_api_min, host_api_max].
  bool accepts_host_api(ApiVersion host) const;
};

// Parses and validates a manifest. `file` is used in error messages only.
// Throws ManifestError on the first problem found.
Manifest parse_manifest(const nlohmann::json& document, const std::string& file);
// Reads `path` (JSON syntax errors are reported with the file and byte offset) and parses it.
Manifest load_manifest(const std::filesystem::path& path);

// The permissions a manifest may ask for.
const std::vector<std::string>& known_permissions();

}  // namespace marvin::skills
