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
// Skills directories hold two layouts (store/README.md): plain folders
// `<dir>/<name>/skill.json`, and skills installed by the store, `<dir>/<id>/current/skill.json`
// where `current` is a symlink to `versions/<version>`. The symlink is resolved once, when the
// skill loads, and the skill keeps its resolved folder while loaded, so the store swapping
// `current` never changes files under a loaded skill. Names starting with '.' are skipped.
//
// Reloading: unload() removes one skill (its intents, then its instance and context) and
// load_skill() loads one; the host uses them to follow installs, upgrades and removals
// without a restart (core/app/skill_reloader.h).
//
// Threading: every mutation (load_*, add_native, unload) runs on one thread, while nothing
// else reads the registry. In the running host that is the host loop's thread, between
// utterances and only while the manager is idle (Manager::idle()): the manager and the loop
// read the registry on that same thread, and a long task's worker touches only its own
// LoadedSkill, which is never unloaded while the task runs. One-shot commands (`skills
// list`, `skill run`) load and then read on their only thread. Other code reads the registry
// only on the loop thread too (the voice front end rebuilds its grammar from
// HostLoop::on_waiting(kCommand), which the loop calls between utterances); never from the
// reminder scheduler's or a voice thread while the loop runs.
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
  std::filesystem::path dir;     // its files: the plain folder, or the resolved versions/<v>
  std::filesystem::path origin;  // the folder found in the skills directory (<dir>/<name>)
  std::string stamp;             // SkillSource::stamp when it was loaded
  std::unique_ptr<SkillContext> context;    // the skill's marvin_host
  std::unique_ptr<SkillInstance> instance;  // destroyed before its context
};

struct LoadError {
  std::filesystem::path where;  // the skill's folder (or manifest file)
  std::string message;
};

// One skill folder found in a skills directory.
struct SkillSource {
  std::filesystem::path origin;  // <skills-dir>/<name>
  std::filesystem::path dir;     // what is loaded: origin, or origin/current resolved
  bool installed = false;        // the store layout (origin/current -> versions/<version>)
  // Changes when what would be loaded changes: the resolved folder for an installed skill
  // (versions are immutable), the newest modification time and the number of files for a
  // plain folder.
  std::string stamp;
};

// The skills in `skills_dir`, in name order; empty when it is not a directory. A folder with
// `current` (even a dangling one) is an installed skill and is skipped while `current` does
// not resolve to a folder with a skill.json; otherwise a folder with a skill.json is a plain
// skill. Never throws.
std::vector<SkillSource> find_skills(const std::filesystem::path& skills_dir);

// The checks load_skill() makes before running any code: manifest (ManifestError names file
// and JSON path), host API range, templates. Returns the manifest; throws std::runtime_error.
// The store's installer uses it to refuse a package this host would not load.
Manifest check_skill(const std::filesystem::path& skill_dir);

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
  // Loads one skill found by find_skills(); true on success, otherwise the reason is in
  // errors() (with `where` = source.origin). Earlier errors for that origin are dropped.
  bool load_skill(const SkillSource& source);
  // Unloads a skill: its intents leave the interpreter, then its instance (Lua state, timers,
  // library) and context are destroyed. False when no skill has that id. The caller
  // guarantees no request of that skill is running (see Threading above).
  bool unload(const std::string& skill_id);
  // Adds a native skill compiled into this process (tests, benchmarks, the SDK harness).
  // Throws std::runtime_error on a bad manifest or descriptor.
  LoadedSkill& add_native(const Manifest& manifest, const marvin_skill_descriptor* descriptor);

  const std::vector<std::unique_ptr<LoadedSkill>>& skills() const { return skills_; }
  const std::vector<LoadError>& errors() const { return errors_; }
  // Sentences claimed by two skills, one description each.
  std::vector<std::string> conflicts() const { return interpreter_.conflicts(); }
  LoadedSkill* find(const std::string& skill_id) const;
  // The skill loaded from `origin` (SkillSource::origin), or nullptr.
  LoadedSkill* find_origin(const std::filesystem::path& origin) const;
  const interpret::Interpreter& interpreter() const { return interpreter_; }
  HostServices& services() const { return services_; }

 private:
  // Validates, loads with `load_code`, registers intents. Throws on any problem.
  LoadedSkill& install(
      const Manifest& manifest, const std::filesystem::path& dir,
      const std::filesystem::path& origin, const std::string& stamp,
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
