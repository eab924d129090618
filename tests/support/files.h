// Files for tests: a temporary directory removed at scope exit, whole files as text, and a
// byte-for-byte snapshot of a directory tree (to check that a refused operation changed
// nothing).
#pragma once

#include <filesystem>
#include <map>
#include <string>

namespace marvin::test_support {

namespace fs = std::filesystem;

// A fresh directory under the system temp dir (mkdtemp), removed with everything in it
// when the object goes.
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

// Writes `text` to `p` (parent folders created, file replaced). Throws when it cannot.
void write_text(const fs::path& p, const std::string& text);
// The whole of `p`. Throws when it cannot be read.
std::string read_text(const fs::path& p);

// Path (relative, '/'-separated) -> ("file:" + content | "link:" + target | "dir") for
// everything under `root`; symbolic links are not followed. Empty when `root` is missing.
std::map<std::string, std::string> snapshot(const fs::path& root);

}  // namespace marvin::test_support
