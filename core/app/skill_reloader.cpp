#include "app/skill_reloader.h"

#include <algorithm>
#include <exception>
#include <optional>

#include "app/installed_skills.h"
#include "common/log.h"
#include "store/installer.h"

namespace marvin::app {
namespace {

namespace fs = std::filesystem;

// `dir` without a trailing separator, so <dir>/<name>.parent_path() compares equal to it.
fs::path normal(const fs::path& dir) {
  fs::path p = dir.lexically_normal();
  if (!p.has_filename() && p.has_parent_path() && p != p.root_path()) p = p.parent_path();
  return p;
}

std::optional<skills::SkillSource> find_source(const fs::path& dir, const fs::path& origin) {
  for (skills::SkillSource& s : skills::find_skills(dir)) {
    if (s.origin == origin) return s;
  }
  return std::nullopt;
}

// "weather 1.1.0" for an installed skill's version folder, else the folder's path.
std::string describe(const skills::SkillSource& source) {
  if (source.installed) {
    return source.origin.filename().string() + " " + source.dir.filename().string();
  }
  return "in " + source.origin.string();
}

}  // namespace

std::vector<std::string> SkillReloader::sync(const fs::path& dir_given) {
  std::vector<std::string> report;
  const fs::path dir = normal(dir_given);
  std::vector<skills::SkillSource> sources = skills::find_skills(dir);

  // Gone: loaded from this directory, no longer there (removed, or `current` dangling).
  std::vector<std::string> gone;
  for (const auto& skill : registry_.skills()) {
    if (skill->origin.parent_path() != dir) continue;
    bool present = std::any_of(sources.begin(), sources.end(),
                               [&](const auto& s) { return s.origin == skill->origin; });
    if (!present) gone.push_back(skill->manifest.id);
  }
  for (const std::string& id : gone) {
    skills::LoadedSkill* skill = registry_.find(id);
    std::string line = "skill " + id + " " + skill->manifest.version.text + " unloaded";
    tried_.erase(skill->origin);
    registry_.unload(id);
    report.push_back(line);
  }
  std::erase_if(tried_, [&](const auto& entry) {
    return entry.first.parent_path() == dir &&
           std::none_of(sources.begin(), sources.end(),
                        [&](const auto& s) { return s.origin == entry.first; });
  });

  // New or changed.
  for (const skills::SkillSource& source : sources) {
    auto tried = tried_.find(source.origin);
    if (tried != tried_.end() && tried->second == source.stamp) continue;
    skills::LoadedSkill* loaded = registry_.find_origin(source.origin);
    if (loaded && loaded->stamp == source.stamp) {
      tried_[source.origin] = source.stamp;
      continue;
    }
    std::string replaced;
    if (loaded) {
      replaced = loaded->manifest.version.text;
      registry_.unload(loaded->manifest.id);
    }
    load(dir, source, replaced, report);
  }
  return report;
}

void SkillReloader::load(const fs::path& dir, const skills::SkillSource& source,
                         const std::string& replaced_version, std::vector<std::string>& report) {
  tried_[source.origin] = source.stamp;
  if (registry_.load_skill(source)) {
    const skills::LoadedSkill& skill = *registry_.find_origin(source.origin);
    report.push_back("skill " + skill.manifest.id + " " + skill.manifest.version.text + " loaded" +
                     (replaced_version.empty() ? "" : " (was " + replaced_version + ")"));
    return;
  }
  const std::string reason =
      registry_.errors().empty() ? std::string("unknown error") : registry_.errors().back().message;
  std::string line = "skill " + describe(source) + " failed to load (" + reason + ")";
  if (!source.installed || !is_store_directory(dir)) {
    report.push_back(line);
    return;
  }
  // An installed version that does not load: make the previous one current again.
  const std::string id = source.origin.filename().string();
  if (const skills::LoadedSkill* other = registry_.find(id);
      other && other->origin != source.origin) {
    report.push_back(line);  // an id clash: the previous version would clash too
    return;
  }
  std::optional<skills::SkillSource> back;
  try {
    store::Installer installer(dir);
    std::optional<store::InstalledSkill> installed = installer.find(id);
    if (!installed || !installed->previous) {
      report.push_back(line + "; no previous version to roll back to");
      return;
    }
    store::InstalledSkill now = installer.rollback(id);
    line += "; rolled back to " + now.version;
    back = find_source(dir, source.origin);
  } catch (const std::exception& e) {
    report.push_back(line + "; cannot roll back: " + e.what());
    return;
  }
  log(LogLevel::kWarning, "skills", line);
  report.push_back(line);
  if (!back) {
    report.push_back("skill " + id + ": the rolled-back version is not in " + dir.string());
    return;
  }
  tried_[back->origin] = back->stamp;
  if (registry_.load_skill(*back)) {
    const skills::LoadedSkill& skill = *registry_.find_origin(back->origin);
    report.push_back("skill " + skill.manifest.id + " " + skill.manifest.version.text + " loaded");
  } else {
    report.push_back("skill " + describe(*back) + " failed to load too (" +
                     registry_.errors().back().message + ")");
  }
}

}  // namespace marvin::app
