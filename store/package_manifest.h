// The few fields of a skill's skill.json the store needs, read and checked on their own.
//
// The store does not link the skill platform (core/skills). It reads only what packing,
// indexing and installing need; the host's full manifest validation (intents, slots,
// templates) plugs into the installer through InstallOptions::validate.
//
// Fields read (all required unless marked):
//   "id":          [a-z0-9][a-z0-9._-]{0,63}, no "..": also the directory name on disk
//   "version":     semantic version (MAJOR.MINOR.PATCH[-pre][+build])
//   "kind":        "native" | "lua"
//   "host_api":    the host's form {"min": "1.0", "max": "1.3"} ("max" optional: same major),
//                  or a range string, e.g. ">=1.0 <2.0" or "^1.0" (see semver.h)
//   "permissions": array of strings (optional, default empty), sorted and de-duplicated
//   "library":     native skills only: file name of the shared library inside the package,
//                  relative, e.g. "libdice.so" (also accepted as "native": {"library": ...})
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "store/semver.h"

namespace marvin::store {

struct PackageManifest {
  std::string id;
  Version version;
  std::string kind;  // "native" or "lua"
  VersionRange host_api;
  std::vector<std::string> permissions;  // sorted, unique
  std::string library;                   // native only

  // "id@version"
  std::string id_at_version() const { return id + "@" + version.text; }
};

// Parses skill.json text. Throws std::runtime_error "<origin>: <field>: <what>".
PackageManifest parse_package_manifest(std::string_view json_text, const std::string& origin);

// True when `id` is a valid skill id (see above).
bool is_valid_skill_id(std::string_view id);

}  // namespace marvin::store
