// A .mskill package: the archive (archive.h) holding skill.json and the skill's files,
// with a detached minisign signature next to it (<file>.minisig).
//
// The signature's trusted comment binds it to one package:
//     marvin-skill <id>@<version> sha256:<digest of the .mskill file>
// so it cannot be moved to another skill, another version, or other bytes.
#pragma once

#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "store/archive.h"
#include "store/minisign.h"
#include "store/package_manifest.h"

namespace marvin::store {

struct PackedSkill {
  Bytes archive;                         // the .mskill bytes
  PackageManifest manifest;
  std::string digest;                    // sha256:...
  std::optional<std::string> signature;  // .minisig content when signed
  std::string file_name() const;         // "<id>-<version>.mskill"
};

// Packs the skill folder `dir` (which must hold a valid skill.json) reproducibly, and
// signs it with `key` when given. Throws naming the file or field at fault.
PackedSkill pack_skill(const std::filesystem::path& dir, const SecretKey* key = nullptr);

// What a verified signature vouches for.
struct PackageClaim {
  std::string id;
  std::string version;
  std::string digest;
  std::string id_at_version() const { return id + "@" + version; }
};

std::string package_trusted_comment(const std::string& id_at_version, const std::string& digest);
// Throws naming `origin` when the trusted comment is not "marvin-skill <id>@<version> <digest>".
PackageClaim parse_package_trusted_comment(const std::string& comment, const std::string& origin);

// Verifies `signature_text` over `package` with `trusted` keys, and that the signature
// vouches for exactly these bytes (digest in the trusted comment). Returns the claim.
PackageClaim verify_package_signature(std::span<const std::uint8_t> package,
                                      const std::string& signature_text,
                                      const std::vector<PublicKey>& trusted,
                                      const std::string& origin);

// The signature file that belongs to `package`: "<package>.minisig".
std::filesystem::path signature_path_for(const std::filesystem::path& package);

}  // namespace marvin::store
