#include "app/skill_watcher.h"

#include <poll.h>
#include <sys/eventfd.h>
#include <sys/inotify.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <map>
#include <stdexcept>
#include <string>
#include <thread>

#include "common/log.h"

namespace marvin::app {
namespace {

namespace fs = std::filesystem;

constexpr std::uint32_t kDirMask = IN_CREATE | IN_DELETE | IN_MOVED_FROM | IN_MOVED_TO |
                                   IN_CLOSE_WRITE | IN_ATTRIB | IN_DELETE_SELF | IN_MOVE_SELF;

enum class Role { kSkills, kStore, kParent };

struct Watch {
  Role role;
  std::size_t dir;  // index into dirs
};

}  // namespace

struct SkillWatcher::Impl {
  std::vector<fs::path> dirs;
  std::function<void()> changed;
  int inotify = -1;
  int stop = -1;  // eventfd: the destructor's "stop"
  std::multimap<int, Watch> watches;
  std::thread thread;

  void add(const fs::path& path, Role role, std::size_t dir) {
    int wd = inotify_add_watch(inotify, path.c_str(), kDirMask | IN_ONLYDIR);
    if (wd < 0) return;  // gone meanwhile, or not a directory: the parent's events tell us
    for (auto [it, end] = watches.equal_range(wd); it != end; ++it) {
      if (it->second.role == role && it->second.dir == dir) return;
    }
    watches.emplace(wd, Watch{role, dir});
  }

  // The directory if it exists (and its .store), else its parent to see it appear.
  void watch_dir(std::size_t i) {
    std::error_code ec;
    if (fs::is_directory(dirs[i], ec)) {
      add(dirs[i], Role::kSkills, i);
      if (fs::is_directory(dirs[i] / ".store", ec)) add(dirs[i] / ".store", Role::kStore, i);
    } else if (dirs[i].has_parent_path()) {
      add(dirs[i].parent_path(), Role::kParent, i);
    }
  }

  void forget(int wd, Role role, std::size_t dir) {
    for (auto [it, end] = watches.equal_range(wd); it != end; ++it) {
      if (it->second.role == role && it->second.dir == dir) {
        watches.erase(it);
        break;
      }
    }
    if (watches.count(wd) == 0) inotify_rm_watch(inotify, wd);
  }

  // True when the event means the skills of a directory may have changed.
  bool handle(const inotify_event& event) {
    bool relevant = false;
    std::string name = event.len > 0 ? std::string(event.name) : std::string();
    std::vector<Watch> targets;
    for (auto [it, end] = watches.equal_range(event.wd); it != end; ++it) {
      targets.push_back(it->second);
    }
    if (event.mask & IN_IGNORED) {
      for (auto [it, end] = watches.equal_range(event.wd); it != end;) it = watches.erase(it);
    }
    for (const Watch& w : targets) {
      switch (w.role) {
        case Role::kSkills:
          if (event.mask & (IN_DELETE_SELF | IN_MOVE_SELF | IN_IGNORED)) {
            forget(event.wd, w.role, w.dir);
            watch_dir(w.dir);  // the parent, to see it come back
            relevant = true;
          } else if (name == ".store") {
            if (event.mask & (IN_CREATE | IN_MOVED_TO)) watch_dir(w.dir);
          } else if (!name.empty() && name.front() != '.') {
            relevant = true;  // a skill folder, or skills.lock
          }
          break;
        case Role::kStore:
          if (name == "reload-request") relevant = true;
          break;
        case Role::kParent:
          if (name == dirs[w.dir].filename().string() && (event.mask & (IN_CREATE | IN_MOVED_TO))) {
            forget(event.wd, w.role, w.dir);
            watch_dir(w.dir);
            relevant = true;
          }
          break;
      }
    }
    return relevant;
  }

  void run() {
    alignas(inotify_event) char buffer[16 * 1024];
    pollfd fds[2] = {{inotify, POLLIN, 0}, {stop, POLLIN, 0}};
    for (;;) {
      if (poll(fds, 2, -1) < 0) {
        if (errno == EINTR) continue;
        log(LogLevel::kError, "skills",
            std::string("skill watcher: poll: ") + std::strerror(errno));
        return;
      }
      if (fds[1].revents != 0) return;
      ssize_t n = read(inotify, buffer, sizeof buffer);
      if (n <= 0) continue;
      bool relevant = false;
      for (char* p = buffer; p < buffer + n;) {
        const auto* event = reinterpret_cast<const inotify_event*>(p);
        if (event->mask & IN_Q_OVERFLOW) relevant = true;  // events lost: check everything
        relevant = handle(*event) || relevant;
        p += sizeof(inotify_event) + event->len;
      }
      if (relevant) changed();
    }
  }
};

SkillWatcher::SkillWatcher(std::vector<fs::path> dirs, std::function<void()> changed)
    : impl_(std::make_unique<Impl>()) {
  impl_->dirs = std::move(dirs);
  impl_->changed = std::move(changed);
  impl_->inotify = inotify_init1(IN_NONBLOCK | IN_CLOEXEC);
  if (impl_->inotify < 0) {
    throw std::runtime_error(std::string("cannot watch the skills directories: inotify_init1: ") +
                             std::strerror(errno));
  }
  impl_->stop = eventfd(0, EFD_CLOEXEC);
  if (impl_->stop < 0) {
    int e = errno;
    close(impl_->inotify);
    throw std::runtime_error(std::string("cannot watch the skills directories: eventfd: ") +
                             std::strerror(e));
  }
  for (std::size_t i = 0; i < impl_->dirs.size(); ++i) impl_->watch_dir(i);
  impl_->thread = std::thread([impl = impl_.get()] { impl->run(); });
}

SkillWatcher::~SkillWatcher() {
  std::uint64_t one = 1;
  [[maybe_unused]] ssize_t n = write(impl_->stop, &one, sizeof one);
  if (impl_->thread.joinable()) impl_->thread.join();
  close(impl_->stop);
  close(impl_->inotify);
}

}  // namespace marvin::app
