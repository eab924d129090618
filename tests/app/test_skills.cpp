#include "test_skills.h"

#include <unistd.h>

#include <fstream>
#include <sstream>
#include <stdexcept>

#include "store/package.h"
#include "store/util.h"

namespace marvin::app::test {

TempDir::TempDir() {
  std::string pattern = (fs::temp_directory_path() / "marvin_app_test_XXXXXX").string();
  if (!mkdtemp(pattern.data())) throw std::runtime_error("mkdtemp failed");
  path_ = pattern;
}

TempDir::~TempDir() {
  std::error_code ec;
  fs::remove_all(path_, ec);
}

void write_text(const fs::path& p, const std::string& text) {
  fs::create_directories(p.parent_path());
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out << text;
  if (!out) throw std::runtime_error("cannot write " + p.string());
}

std::string read_text(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + p.string());
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

fs::path lua_skill(const fs::path& parent, const std::string& id, const std::string& version,
                   const std::string& answer, const std::string& main_lua,
                   const std::string& host_api, const std::string& permissions) {
  fs::path dir = parent / (id + "-" + version + "-src");
  write_text(
      dir / "skill.json",
      "{\"id\": \"" + id + "\", \"name\": \"" + id + "\", \"version\": \"" + version +
          "\", \"kind\": \"lua\", \"host_api\": " + host_api + ", \"permissions\": " + permissions +
          ", \"intents\": [{\"name\": \"greet\", \"templates\": [\"" + id + " greet\"]}]}\n");
  write_text(dir / "main.lua", main_lua.empty() ? "marvin.on(\"greet\", function() marvin.say(\"" +
                                                      answer + "\") end)\n"
                                                : main_lua);
  return dir;
}

fs::path pack_signed(const fs::path& skill_dir, const fs::path& out_dir,
                     const store::SecretKey& key) {
  store::PackedSkill p = store::pack_skill(skill_dir, &key);
  fs::create_directories(out_dir);
  fs::path file = out_dir / p.file_name();
  store::write_file_atomic(file, p.archive);
  store::write_file_atomic(store::signature_path_for(file), *p.signature);
  return file;
}

std::map<std::string, std::string> snapshot(const fs::path& root) {
  std::map<std::string, std::string> out;
  std::error_code ec;
  if (!fs::exists(fs::symlink_status(root, ec))) return out;
  for (auto it = fs::recursive_directory_iterator(root); it != fs::recursive_directory_iterator();
       ++it) {
    std::string rel = fs::relative(it->path(), root).string();
    if (it->is_symlink()) {
      out[rel] = "link:" + fs::read_symlink(it->path()).string();
    } else if (it->is_directory()) {
      out[rel] = "dir";
    } else {
      out[rel] = "file:" + read_text(it->path());
    }
  }
  return out;
}

}  // namespace marvin::app::test
