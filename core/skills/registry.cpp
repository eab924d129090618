#include "skills/registry.h"

#include <algorithm>
#include <stdexcept>

#include "common/log.h"
#include "skills/native_runtime.h"

namespace marvin::skills {

interpret::SlotSpec slot_spec(const SlotDecl& slot) {
  interpret::SlotSpec spec;
  spec.name = slot.name;
  switch (slot.kind) {
    case SlotKind::kNumber:
      spec.type = interpret::SlotType::kNumber;
      break;
    case SlotKind::kDuration:
      spec.type = interpret::SlotType::kDuration;
      break;
    case SlotKind::kDateTime:
      spec.type = interpret::SlotType::kDateTime;
      break;
    case SlotKind::kContact:
      spec.type = interpret::SlotType::kContact;
      break;
    case SlotKind::kList:
      spec.type = interpret::SlotType::kList;
      break;
    case SlotKind::kText:
      spec.type = interpret::SlotType::kText;
      break;
  }
  spec.values = slot.values;
  return spec;
}

interpret::IntentSpec intent_spec(const Manifest& manifest, const IntentDecl& intent) {
  interpret::IntentSpec spec;
  spec.skill_id = manifest.id;
  spec.intent = intent.name;
  spec.templates = intent.templates;
  for (const SlotDecl& slot : intent.slots) spec.slots.push_back(slot_spec(slot));
  return spec;
}

Registry::Registry(HostServices& services) : services_(services) {
  add_runtime(std::make_unique<NativeRuntime>());
}

Registry::~Registry() {
  // Instances first (they may call back into their context while shutting down), then the
  // contexts; a library is closed once its last instance is gone.
  for (auto& skill : skills_) skill->instance.reset();
}

void Registry::add_runtime(std::unique_ptr<SkillRuntime> runtime) {
  std::string kind = runtime->kind();
  runtimes_[kind] = std::move(runtime);
}

std::size_t Registry::load_directory(const std::filesystem::path& skills_dir) {
  std::error_code ec;
  if (!std::filesystem::is_directory(skills_dir, ec)) {
    errors_.push_back({skills_dir, "skills directory " + skills_dir.string() + " does not exist"});
    log(LogLevel::kWarning, "skills", errors_.back().message);
    return 0;
  }
  std::vector<std::filesystem::path> dirs;
  for (const auto& entry : std::filesystem::directory_iterator(skills_dir, ec)) {
    if (entry.is_directory() && std::filesystem::exists(entry.path() / "skill.json")) {
      dirs.push_back(entry.path());
    }
  }
  std::sort(dirs.begin(), dirs.end());
  std::size_t loaded = 0;
  for (const auto& dir : dirs) loaded += load_skill(dir) ? 1 : 0;
  return loaded;
}

bool Registry::load_skill(const std::filesystem::path& skill_dir) {
  try {
    Manifest manifest = load_manifest(skill_dir / "skill.json");
    auto runtime = runtimes_.find(manifest.kind);
    if (runtime == runtimes_.end()) {
      throw std::runtime_error("skill '" + manifest.id + "': no runtime for kind \"" +
                               manifest.kind + "\" in this host");
    }
    SkillRuntime& rt = *runtime->second;
    install(manifest, skill_dir, [&](LoadedSkill& skill) {
      return rt.load(skill.manifest, skill_dir, host_robot_api(), skill.context->host());
    });
    return true;
  } catch (const std::exception& e) {
    errors_.push_back({skill_dir, e.what()});
    log(LogLevel::kError, "skills", std::string("skipped ") + skill_dir.string() + ": " + e.what());
    return false;
  }
}

LoadedSkill& Registry::add_native(const Manifest& manifest,
                                  const marvin_skill_descriptor* descriptor) {
  return install(manifest, manifest.file.parent_path(), [&](LoadedSkill& skill) {
    return make_native_instance(descriptor, skill.manifest, host_robot_api(),
                                skill.context->host());
  });
}

LoadedSkill& Registry::install(
    const Manifest& manifest, const std::filesystem::path& dir,
    const std::function<std::unique_ptr<SkillInstance>(LoadedSkill&)>& load_code) {
  const std::string who = "skill '" + manifest.id + "' (" + manifest.file.string() + ")";
  if (find(manifest.id)) {
    throw std::runtime_error(who + ": a skill with this id is already loaded from " +
                             find(manifest.id)->dir.string());
  }
  ApiVersion host{MARVIN_ROBOT_API_MAJOR, MARVIN_ROBOT_API_MINOR};
  if (!manifest.accepts_host_api(host)) {
    throw std::runtime_error(
        who + ": needs Robot API " + std::to_string(manifest.host_api_min.major) + "." +
        std::to_string(manifest.host_api_min.minor) + " to " +
        std::to_string(manifest.host_api_max.major) + "." +
        std::to_string(manifest.host_api_max.minor) + " (\"host_api\") but this host has " +
        std::to_string(host.major) + "." + std::to_string(host.minor));
  }
  // Templates are compiled on a scratch interpreter first so a bad one leaves the real
  // interpreter untouched.
  std::vector<interpret::IntentSpec> specs;
  interpret::Interpreter scratch;
  for (const IntentDecl& intent : manifest.intents) {
    specs.push_back(intent_spec(manifest, intent));
    try {
      scratch.add(specs.back());
    } catch (const std::exception& e) {
      throw std::runtime_error(manifest.file.string() + ": " + e.what());
    }
  }
  auto skill = std::make_unique<LoadedSkill>();
  skill->manifest = manifest;
  skill->dir = dir;
  skill->context = std::make_unique<SkillContext>(manifest.id, manifest.permissions, services_);
  skill->instance = load_code(*skill);
  for (const auto& spec : specs) interpreter_.add(spec);
  skills_.push_back(std::move(skill));
  log(LogLevel::kInfo, "skills",
      "loaded " + manifest.id + " " + manifest.version.text + " (" + manifest.kind + ")");
  return *skills_.back();
}

LoadedSkill* Registry::find(const std::string& skill_id) const {
  for (const auto& skill : skills_) {
    if (skill->manifest.id == skill_id) return skill.get();
  }
  return nullptr;
}

}  // namespace marvin::skills
