// The installer: puts verified skill packages into a skills directory so that an
// interruption at any point (crash, kill, power cut) leaves either the old or the new
// version active, never a mix. The on-disk layout and the order of steps are described in
// store/README.md.
//
// Thread and process safety: every mutating call takes an exclusive flock() on
// <skills-dir>/.store/lock, so two installers (two `marvin` processes) never interleave.
// An Installer object itself is not meant to be shared between threads.
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "store/archive.h"
#include "store/elf_arch.h"
#include "store/minisign.h"
#include "store/package_manifest.h"
#include "store/repository.h"
#include "store/semver.h"

namespace marvin::store {

// One installed skill, as recorded in the lock file <skills-dir>/skills.lock.
struct InstalledSkill {
  std::string id;
  std::string version;
  std::string digest;
  std::string kind;
  std::vector<std::string> permissions;
  std::string source;                   // "repo:<name>" or "file:<path>"
  std::optional<std::string> previous;  // the version `rollback` returns to
  std::filesystem::path path;           // <skills-dir>/<id>/current (what the host loads)
};

// Asked before activation when the user must approve permissions: on a first install with
// any permission, or on an upgrade that adds permissions.
struct ApprovalRequest {
  std::string id;
  std::string version;
  std::optional<std::string> installed_version;
  std::vector<std::string> permissions;        // all the new version asks for
  std::vector<std::string> added_permissions;  // not granted to the installed version
};

// Told after the `current` pointer of a skill changed (the hook the running host uses to
// reload the skill; see README.md "Host wiring").
struct SkillChange {
  enum class Kind { kInstalled, kUpgraded, kDowngraded, kRolledBack, kRemoved };
  Kind kind;
  std::string id;
  std::optional<std::string> from_version;
  std::optional<std::string> to_version;
  std::filesystem::path path;  // <skills-dir>/<id>/current; gone when removed
};

struct InstallOptions {
  // Approve permissions without asking (`--yes`).
  bool assume_yes = false;
  // Accept a version lower than the installed one (`--allow-downgrade`).
  bool allow_downgrade = false;
  // Asked when permissions need approval and assume_yes is false. Returns true to
  // approve. Unset: the install is refused ("needs approval").
  std::function<bool(const ApprovalRequest&)> approve;
  // The host's full manifest validation: called with the staged skill directory before
  // activation; throws std::runtime_error to refuse. Unset: only the store's checks.
  std::function<void(const std::filesystem::path& staged_dir)> validate;
  // Called after each activation, rollback or removal, after the lock file is written.
  std::function<void(const SkillChange&)> on_change;
  // The host API version ranges are checked against. Default: the SDK's ABI major.minor.
  Version host_api = default_host_api();
  // The CPU a native library must be built for. Default: this program's.
  ElfArch host_arch = host_elf_arch();
  ArchiveLimits limits;
  // fsync files and directories so every step is durable (off only in benchmarks).
  bool durable = true;
  // Tests: called at every step of an install, rollback or removal with the step's name,
  // so a test can kill the process there.
  StepHook step_hook;

  static Version default_host_api();
};

// Where a package comes from and what it must be.
struct PackageSource {
  std::filesystem::path package;    // the .mskill file
  std::filesystem::path signature;  // empty: <package>.minisig
  std::vector<PublicKey> trusted_keys;
  // When installing from a repository: the index entry the package must match (digest,
  // size, id, version).
  std::optional<IndexEntry> expected;
  std::string source_label;  // recorded in the lock file
};

struct InstallResult {
  enum class Outcome { kInstalled, kUpgraded, kDowngraded, kAlreadyInstalled };
  Outcome outcome;
  InstalledSkill skill;
  std::optional<std::string> replaced_version;
};

class Installer {
 public:
  // Creates the skills directory (and .store/) if missing. Does not take the lock.
  Installer(std::filesystem::path skills_dir, InstallOptions options = {});

  // Verifies and activates one package. Order: size and digest against the index entry,
  // signature and trusted comment, downgrade rule, extraction into a staging directory
  // under the limits, manifest (id and version must equal the signed ones and the index),
  // host API range, architecture of a native library, options.validate, permission
  // approval, then activation. Any refusal throws std::runtime_error naming the file, entry
  // or field, and leaves the installed skills and the lock file unchanged.
  InstallResult install(const PackageSource& source);

  // Makes the previous version current again (instant: a pointer swap). The version
  // rolled back from becomes the previous one, so a second rollback undoes the first.
  // Throws when the skill is not installed or has no previous version.
  InstalledSkill rollback(const std::string& id);

  // Deactivates and deletes every version of `id`. Throws when it is not installed.
  void remove(const std::string& id);

  // The installed skills, from the lock file, sorted by id.
  std::vector<InstalledSkill> list() const;
  std::optional<InstalledSkill> find(const std::string& id) const;

  // Finishes or undoes whatever an interrupted operation left (staging directories,
  // half-made pointers, versions no pointer names) and makes the lock file agree with the
  // `current` pointers. Every mutating call does this first; a host may call it at start.
  void recover();

  const std::filesystem::path& skills_dir() const { return dir_; }
  std::filesystem::path store_dir() const { return dir_ / ".store"; }
  std::filesystem::path lock_file() const { return dir_ / "skills.lock"; }

 private:
  class Lock;
  void step(std::string_view name) const;
  void recover_locked();
  void write_lock_file();

  std::filesystem::path dir_;
  InstallOptions options_;
};

}  // namespace marvin::store
