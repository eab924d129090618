// Tells the running host when a skills directory changed, so it can reload without a
// restart: `marvin skill install|upgrade|rollback|remove` in another process (the store
// replaces <dir>/skills.lock by rename after every change), a plain skill folder added or
// removed, or `marvin skills reload` (which rewrites <dir>/.store/reload-request).
//
// Linux inotify, on its own thread. Watches each directory itself (not its sub-folders:
// the store always rewrites skills.lock, so that is enough), its .store folder for the
// reload request, and, while a directory does not exist yet, its parent, so the installed-
// skills directory made by the first install is picked up too.
//
// The callback runs on the watcher's thread, possibly many times for one change (a change
// is several file operations): it should only post a request (Host::request_reload()).
#pragma once

#include <filesystem>
#include <functional>
#include <memory>
#include <vector>

namespace marvin::app {

class SkillWatcher {
 public:
  // Starts watching. Throws std::runtime_error naming the directory when inotify fails.
  SkillWatcher(std::vector<std::filesystem::path> dirs, std::function<void()> changed);
  ~SkillWatcher();  // stops the thread; `changed` is not called afterwards
  SkillWatcher(const SkillWatcher&) = delete;
  SkillWatcher& operator=(const SkillWatcher&) = delete;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace marvin::app
