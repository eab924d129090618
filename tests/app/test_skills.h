// Helpers for the app tests: temporary directories, Lua skill folders in the host's
// manifest format, signed packages, and byte-for-byte snapshots of a directory tree.
#pragma once

#include <filesystem>
#include <map>
#include <string>

#include "store/minisign.h"

namespace marvin::app::test {

namespace fs = std::filesystem;

class TempDir {
 public:
  TempDir();
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const fs::path& path() const { return path_; }
  fs::path operator/(const std::string& s) const { return path_ / s; }

 private:
  fs::path path_;
};

void write_text(const fs::path& p, const std::string& text);
std::string read_text(const fs::path& p);

// A Lua skill folder <parent>/<id>-<version>-src whose intent "greet" ("<id> greet" or
// `sentence`) says `answer`. `main_lua` replaces the whole main.lua when not empty.
// `host_api` is the skill.json value as JSON text.
fs::path lua_skill(const fs::path& parent, const std::string& id, const std::string& version,
                   const std::string& answer, const std::string& main_lua = "",
                   const std::string& host_api = R"({"min": "1.0"})",
                   const std::string& permissions = "[]");

// Packs and signs `skill_dir` into <out_dir>/<id>-<version>.mskill (+ .minisig).
fs::path pack_signed(const fs::path& skill_dir, const fs::path& out_dir,
                     const store::SecretKey& key);

// Path -> ("file:" + content | "link:" + target | "dir") for everything under `root`.
std::map<std::string, std::string> snapshot(const fs::path& root);

}  // namespace marvin::app::test
