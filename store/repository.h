// A skill repository: a directory (local path or mounted share) holding packages and a
// signed index.
//
//   <repo>/index.json           the index (below)
//   <repo>/index.json.minisig   its minisign signature; trusted comment
//                               "marvin-index <name> sequence=<n>"
//   <repo>/<id>-<version>.mskill and .mskill.minisig
//
// index.json:
//   { "format": "marvin-index/1", "name": "demo", "sequence": 7,
//     "skills": { "<id>": { "versions": { "<version>": {
//         "file": "dice-1.0.0.mskill", "digest": "sha256:...", "size": 1234,
//         "kind": "lua", "permissions": ["speech"], "host_api": "^1.0" } } } } }
//
// The sequence grows with each publication. The client remembers, per repository name,
// the highest sequence (and that index's digest) it has accepted, and refuses an index
// with a lower sequence, or the same sequence with other content: a stale or replayed
// index cannot hide a newer version or bring back a withdrawn one.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "store/minisign.h"
#include "store/semver.h"

namespace marvin::store {

struct IndexEntry {
  std::string id;
  Version version;
  std::string file;  // plain file name inside the repository
  std::string digest;
  std::uint64_t size = 0;
  std::string kind;
  std::vector<std::string> permissions;
  std::string host_api;
};

struct RepositoryIndex {
  std::string name;
  std::uint64_t sequence = 0;
  std::string digest;  // of index.json
  std::map<std::string, std::vector<IndexEntry>> skills;  // versions ascending

  // The entry for `id` at `version`, or the highest version when `version` is empty.
  const IndexEntry* find(const std::string& id, const std::string& version = {}) const;
};

// Parses index.json (already verified). Throws naming `origin` and the JSON path.
RepositoryIndex parse_index(const std::string& text, const std::string& origin);

// Verifies the signature (trusted keys only; trusted comment must match the name and
// sequence inside) and parses. Throws naming the file and field.
RepositoryIndex verify_index(const std::string& index_text, const std::string& signature_text,
                             const std::vector<PublicKey>& trusted, const std::string& origin);

// What the client remembers about indexes it accepted, in a JSON file it owns
// (the installer keeps it at <skills-dir>/.store/seen-indexes.json).
class SeenIndexes {
 public:
  explicit SeenIndexes(std::filesystem::path file) : file_(std::move(file)) {}
  // Throws when `index` is older than (or a different index with the same sequence as)
  // the one already accepted for its name. Otherwise records it (durably).
  void check_and_record(const RepositoryIndex& index, const std::string& origin);

 private:
  std::filesystem::path file_;
};

struct RepositoryConfig {
  std::string name;  // local name ("demo")
  std::filesystem::path path;
  std::vector<PublicKey> trusted_keys;
};

// Opens <config.path>/index.json, verifies it and checks it against `seen` (null: no
// replay check). The result knows where the packages are.
struct Repository {
  RepositoryConfig config;
  RepositoryIndex index;
  std::filesystem::path package_path(const IndexEntry& e) const { return config.path / e.file; }
};
Repository open_repository(const RepositoryConfig& config, SeenIndexes* seen);

// Builds (or rebuilds) <dir>/index.json from every signed *.mskill in `dir` and signs it.
// Each package's signature is checked against `key`'s public key plus `extra_trusted`.
// `sequence` 0 means one more than the existing index's (or 1). Returns the index.
RepositoryIndex build_repository_index(const std::filesystem::path& dir, const std::string& name,
                                       const SecretKey& key, std::uint64_t sequence = 0,
                                       const std::vector<PublicKey>& extra_trusted = {});

}  // namespace marvin::store
