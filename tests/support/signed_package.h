// Skill packages for tests: a skill folder packed and signed the way `marvin skill pack
// --sign` does, through the store library.
#pragma once

#include <filesystem>

#include "store/minisign.h"

namespace marvin::test_support {

// Packs and signs `skill_dir` into <out_dir>/<id>-<version>.mskill (+ .minisig next to it);
// returns the package's path. Throws what the store throws for a bad skill folder.
std::filesystem::path pack_signed(const std::filesystem::path& skill_dir,
                                  const std::filesystem::path& out_dir,
                                  const store::SecretKey& key);

}  // namespace marvin::test_support
