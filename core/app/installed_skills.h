// Where the store installs skills, and the host's side of the store's contract
// (store/README.md "Host wiring"): the default installed-skills directory shared by
// `marvin skill ...` and `marvin run`, the host's check of a package before activation, and
// the file `marvin skills reload` writes to ask running hosts to reload.
#pragma once

#include <filesystem>
#include <optional>
#include <vector>

#include "store/minisign.h"

namespace marvin::app {

// $MARVIN_SKILLS_DIR, else $XDG_DATA_HOME/marvin/skills, else ~/.local/share/marvin/skills;
// nullopt when none of these variables is set. Not created here.
std::optional<std::filesystem::path> default_installed_skills_dir();

// True when `dir` is managed by the store (it has skills.lock or .store/lock), so the
// installer's recover() and rollback() may touch it. Plain skill folders are not.
bool is_store_directory(const std::filesystem::path& dir);

// The host's full manifest validation of a staged package folder (for
// store::InstallOptions::validate): the manifest, host API range and templates, exactly as
// the registry checks them before loading. Throws std::runtime_error naming the file and
// JSON field.
void validate_skill_for_host(const std::filesystem::path& staged_dir);

// <dir>/.store/reload-request: `marvin skills reload` rewrites it; a running host watching
// `dir` reloads what changed there.
std::filesystem::path reload_request_file(const std::filesystem::path& dir);

// The keys a package file installed into `dir` may be signed with: those of the
// repositories configured there (<dir>/.store/repositories.json, `marvin skill repo-add`).
// Used by `marvin skill install FILE` and the web page's upload alike. Throws naming the file
// when it is not valid.
std::vector<store::PublicKey> repository_keys(const std::filesystem::path& dir);

}  // namespace marvin::app
