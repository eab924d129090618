#include "skills/registry.h"

#include <algorithm>
#include <cstdint>
#include <limits>
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
  spec.examples = intent.examples;
  spec.synonyms = intent.synonyms;
  for (const SlotDecl& slot : intent.slots) spec.slots.push_back(slot_spec(slot));
  return spec;
}

namespace {

namespace fs = std::filesystem;

// Host API range and templates. Templates are compiled on a scratch interpreter so a bad one
// leaves the real interpreter untouched; returns the specs to register.
std::vector<interpret::IntentSpec> checked_intents(const Manifest& manifest) {
  const std::string who = "skill '" + manifest.id + "' (" + manifest.file.string() + ")";
  ApiVersion host{MARVIN_ROBOT_API_MAJOR, MARVIN_ROBOT_API_MINOR};
  if (!manifest.accepts_host_api(host)) {
    throw std::runtime_error(
        who + ": needs Robot API " + std::to_string(manifest.host_api_min.major) + "." +
        std::to_string(manifest.host_api_min.minor) + " to " +
        std::to_string(manifest.host_api_max.major) + "." +
        std::to_string(manifest.host_api_max.minor) + " (\"host_api\") but this host has " +
        std::to_string(host.major) + "." + std::to_string(host.minor));
  }
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
  return specs;
}

// Newest modification time and number of files under a plain skill folder: editing any file
// (main.lua, skill.json) changes it. Bounded, so a huge folder cannot stall the host loop.
std::string plain_stamp(const fs::path& dir) {
  std::error_code ec;
  // file_clock's epoch is implementation-defined: counts may be negative.
  std::int64_t newest = std::numeric_limits<std::int64_t>::min();
  std::size_t files = 0;
  auto it = fs::recursive_directory_iterator(
      dir, fs::directory_options::skip_permission_denied, ec);
  for (; !ec && it != fs::recursive_directory_iterator() && files < 4096; it.increment(ec)) {
    std::error_code file_ec;
    if (!it->is_regular_file(file_ec)) continue;
    ++files;
    auto time = fs::last_write_time(it->path(), file_ec);
    if (!file_ec) newest = std::max<std::int64_t>(newest, time.time_since_epoch().count());
  }
  return "plain:" + std::to_string(newest) + ":" + std::to_string(files);
}

}  // namespace

std::vector<SkillSource> find_skills(const std::filesystem::path& skills_dir) {
  std::vector<SkillSource> found;
  std::error_code ec;
  if (!fs::is_directory(skills_dir, ec)) return found;
  std::vector<fs::path> entries;
  for (auto it = fs::directory_iterator(skills_dir, ec);
       !ec && it != fs::directory_iterator(); it.increment(ec)) {
    entries.push_back(it->path());
  }
  std::sort(entries.begin(), entries.end());
  for (const fs::path& entry : entries) {
    std::string name = entry.filename().string();
    if (name.empty() || name.front() == '.' || !fs::is_directory(entry, ec)) continue;
    fs::path current = entry / "current";
    if (fs::is_symlink(fs::symlink_status(current, ec)) || fs::exists(current, ec)) {
      // The store layout: load what `current` names now, by its resolved path.
      fs::path resolved = fs::canonical(current, ec);
      if (ec || !fs::exists(resolved / "skill.json", ec)) continue;
      found.push_back({entry, resolved, true, resolved.string()});
    } else if (fs::exists(entry / "skill.json", ec)) {
      found.push_back({entry, entry, false, plain_stamp(entry)});
    }
  }
  return found;
}

Manifest check_skill(const std::filesystem::path& skill_dir) {
  Manifest manifest = load_manifest(skill_dir / "skill.json");
  checked_intents(manifest);
  return manifest;
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
  std::size_t loaded = 0;
  for (const SkillSource& source : find_skills(skills_dir)) loaded += load_skill(source) ? 1 : 0;
  return loaded;
}

bool Registry::load_skill(const std::filesystem::path& skill_dir) {
  return load_skill(SkillSource{skill_dir, skill_dir, false, {}});
}

bool Registry::load_skill(const SkillSource& source) {
  std::erase_if(errors_, [&](const LoadError& e) { return e.where == source.origin; });
  try {
    Manifest manifest = load_manifest(source.dir / "skill.json");
    auto runtime = runtimes_.find(manifest.kind);
    if (runtime == runtimes_.end()) {
      throw std::runtime_error("skill '" + manifest.id + "': no runtime for kind \"" +
                               manifest.kind + "\" in this host");
    }
    SkillRuntime& rt = *runtime->second;
    install(manifest, source.dir, source.origin, source.stamp, [&](LoadedSkill& skill) {
      return rt.load(skill.manifest, source.dir, host_robot_api(), skill.context->host());
    });
    return true;
  } catch (const std::exception& e) {
    errors_.push_back({source.origin, e.what()});
    log(LogLevel::kError, "skills",
        std::string("skipped ") + source.dir.string() + ": " + e.what());
    return false;
  }
}

bool Registry::unload(const std::string& skill_id) {
  auto it = std::find_if(skills_.begin(), skills_.end(),
                         [&](const auto& skill) { return skill->manifest.id == skill_id; });
  if (it == skills_.end()) return false;
  // Intents first, so nothing can be matched to a skill that is going; then the instance
  // (it may call back into its context while shutting down), then the context.
  interpreter_.remove_skill(skill_id);
  std::unique_ptr<LoadedSkill> skill = std::move(*it);
  skills_.erase(it);
  skill->instance.reset();
  log(LogLevel::kInfo, "skills",
      "unloaded " + skill->manifest.id + " " + skill->manifest.version.text);
  return true;
}

LoadedSkill& Registry::add_native(const Manifest& manifest,
                                  const marvin_skill_descriptor* descriptor) {
  return install(manifest, manifest.file.parent_path(), manifest.file.parent_path(), {},
                 [&](LoadedSkill& skill) {
    return make_native_instance(descriptor, skill.manifest, host_robot_api(),
                                skill.context->host());
  });
}

LoadedSkill& Registry::install(
    const Manifest& manifest, const std::filesystem::path& dir,
    const std::filesystem::path& origin, const std::string& stamp,
    const std::function<std::unique_ptr<SkillInstance>(LoadedSkill&)>& load_code) {
  const std::string who = "skill '" + manifest.id + "' (" + manifest.file.string() + ")";
  if (find(manifest.id)) {
    throw std::runtime_error(who + ": a skill with this id is already loaded from " +
                             find(manifest.id)->dir.string());
  }
  std::vector<interpret::IntentSpec> specs = checked_intents(manifest);
  auto skill = std::make_unique<LoadedSkill>();
  skill->manifest = manifest;
  skill->dir = dir;
  skill->origin = origin;
  skill->stamp = stamp;
  skill->context = std::make_unique<SkillContext>(manifest.id, manifest.permissions, services_);
  skill->instance = load_code(*skill);
  for (const auto& spec : specs) interpreter_.add(spec);
  skills_.push_back(std::move(skill));
  log(LogLevel::kInfo, "skills",
      "loaded " + manifest.id + " " + manifest.version.text + " (" + manifest.kind + ")");
  return *skills_.back();
}

LoadedSkill* Registry::find_origin(const std::filesystem::path& origin) const {
  for (const auto& skill : skills_) {
    if (skill->origin == origin) return skill.get();
  }
  return nullptr;
}

LoadedSkill* Registry::find(const std::string& skill_id) const {
  for (const auto& skill : skills_) {
    if (skill->manifest.id == skill_id) return skill.get();
  }
  return nullptr;
}

}  // namespace marvin::skills
