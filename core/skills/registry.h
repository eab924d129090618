// The skill registry: every skill the robot knows, loaded at start from the skills
// directories, and the interpreter that recognises their sentences.
//
// Loading a skill: read and validate its skill.json (ManifestError names file and JSON
// path), check the manifest's host API range against this host's Robot API, check its
// templates, give it a SkillContext (its marvin_host), load its code with the runtime of
// its kind, and register its intents with the interpreter. A skill that fails any step is
// reported in errors() and skipped; the others load. Two skills whose templates claim the
// same sentence are reported in conflicts() (both stay loaded; the interpreter's ranking
// decides).
//
// Threading: load and add skills before sharing the registry; afterwards the registry is
// read-only and its const members may be used from any thread.
#pragma once

#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "interpret/interpreter.h"
#include "skills/host_api.h"
#include "skills/manifest.h"
#include "skills/skill_runtime.h"

namespace marvin::skills {

struct LoadedSkill {
  Manifest manifest;
  std::filesystem::path dir;
  std::unique_ptr<SkillContext> context;    // the skill's marvin_host
  std::unique_ptr<SkillInstance> instance;  // destroyed before its context
};

struct LoadError {
  std::filesystem::path where;  // the skill's folder (or manifest file)
  std::string message;
};

class Registry {
 public:
  // `services` must outlive the registry. A native runtime is always present.
  explicit Registry(HostServices& services);
  ~Registry();
  Registry(const Registry&) = delete;
  Registry& operator=(const Registry&) = delete;

  // Adds a runtime for another kind of skill (e.g. "lua"); replaces one of the same kind.
  void add_runtime(std::unique_ptr<SkillRuntime> runtime);

  // Loads every skill in `skills_dir`: each sub-folder holding a skill.json, in name order.
  // A missing directory is an error in errors(); returns the number of skills loaded.
  std::size_t load_directory(const std::filesystem::path& skills_dir);
  // Loads the skill in `skill_dir`; true on success, otherwise the reason is in errors().
  bool load_skill(const std::filesystem::path& skill_dir);
  // Adds a native skill compiled into this process (tests, benchmarks, the SDK harness).
  // Throws std::runtime_error on a bad manifest or descriptor.
  LoadedSkill& add_native(const Manifest& manifest, const marvin_skill_descriptor* descriptor);

  const std::vector<std::unique_ptr<LoadedSkill>>& skills() const { return skills_; }
  const std::vector<LoadError>& errors() const { return errors_; }
  // Sentences claimed by two skills, one description each.
  std::vector<std::string> conflicts() const { return interpreter_.conflicts(); }
  LoadedSkill* find(const std::string& skill_id) const;
  const interpret::Interpreter& interpreter() const { return interpreter_; }
  HostServices& services() const { return services_; }

 private:
  // Validates, loads with `load_code`, registers intents. Throws on any problem.
  LoadedSkill& install(
      const Manifest& manifest, const std::filesystem::path& dir,
      const std::function<std::unique_ptr<SkillInstance>(LoadedSkill&)>& load_code);

  HostServices& services_;
  std::map<std::string, std::unique_ptr<SkillRuntime>> runtimes_;
  std::vector<std::unique_ptr<LoadedSkill>> skills_;
  std::vector<LoadError> errors_;
  interpret::Interpreter interpreter_;
};

// The IntentSpec the interpreter gets for one intent of a manifest.
interpret::IntentSpec intent_spec(const Manifest& manifest, const IntentDecl& intent);
interpret::SlotSpec slot_spec(const SlotDecl& slot);

}  // namespace marvin::skills
