// Keeps the registry's skills in line with skills directories while the host runs: loads
// skills that appeared, reloads those whose `current` version (or, for a plain folder, whose
// files) changed, unloads those that are gone, and leaves every other skill's instance (its
// Lua state, its timers) alone. An installed skill that fails to load is rolled back with
// store::Installer::rollback() and its previous version loaded: the automatic rollback of
// store/README.md "Host wiring".
//
// Threading: sync() mutates the registry, so it runs where the registry may be changed (see
// skills/registry.h): the host loop's thread, between utterances, while the manager is idle.
#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "skills/registry.h"

namespace marvin::app {

class SkillReloader {
 public:
  // `registry` must outlive the reloader.
  explicit SkillReloader(skills::Registry& registry) : registry_(registry) {}

  // Brings the skills loaded from `dir` in line with what it holds now. Returns one line per
  // change, e.g. "skill hello 1.1.0 loaded (was 1.0.0)", "skill hello 1.0.0 unloaded",
  // "skill weather 1.1.0 failed to load (<reason>); rolled back to 1.0.0". A folder that
  // failed to load is tried again only once it changes. A missing `dir` unloads what came
  // from it. Never throws.
  std::vector<std::string> sync(const std::filesystem::path& dir);

 private:
  // Loads `source` and reports; rolls an installed skill back when it fails.
  void load(const std::filesystem::path& dir, const skills::SkillSource& source,
            const std::string& replaced_version, std::vector<std::string>& report);

  skills::Registry& registry_;
  std::map<std::filesystem::path, std::string> tried_;  // origin -> stamp last tried
};

}  // namespace marvin::app
