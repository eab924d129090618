// Helpers for the store tests: skill folders, hand-made (hostile) archives, signed raw
// bytes, package contents. Temporary directories, files, snapshots and signed packages are
// the shared ones (tests/support).
#pragma once

#include <archive_entry.h>
#include <sys/stat.h>

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "store/installer.h"
#include "store/minisign.h"
#include "store/package.h"
#include "support/files.h"
#include "support/signed_package.h"

namespace marvin::store::test {

namespace fs = std::filesystem;

// TempDir, write_text, read_text, snapshot, pack_signed.
using namespace test_support;

// A Lua skill folder with skill.json and main.lua.
fs::path make_skill_dir(const fs::path& parent, const std::string& id, const std::string& version,
                        const std::vector<std::string>& permissions = {},
                        const std::string& host_api = "^1.0", const std::string& extra_file = "");

// A minimal ELF shared-object header for `machine` (64-bit little-endian).
Bytes fake_elf_so(std::uint16_t machine);

// One entry of a hand-made archive.
struct RawEntry {
  std::string path;
  mode_t type = AE_IFREG;
  std::string content;
  std::string link;  // symlink target or hard-link target
};
// A gzip tar holding exactly `entries`, in order, with no checks.
Bytes raw_archive(const std::vector<RawEntry>& entries);

// Writes `bytes` as <dir>/<name> and signs it for `id_at_version` with `key`.
fs::path write_signed(const fs::path& dir, const std::string& name, const Bytes& bytes,
                      const SecretKey& key, const std::string& id_at_version);

// The files of a package, as extracted.
std::map<std::string, std::string> package_files(const fs::path& package);

// Runs a shell command, returns its exit status.
int run(const std::string& command);

}  // namespace marvin::store::test
