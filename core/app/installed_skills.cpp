#include "app/installed_skills.h"

#include <cstdlib>
#include <stdexcept>
#include <string>
#include <system_error>

#include <nlohmann/json.hpp>

#include "skills/registry.h"
#include "store/util.h"

namespace marvin::app {

namespace fs = std::filesystem;

std::optional<fs::path> default_installed_skills_dir() {
  if (const char* env = std::getenv("MARVIN_SKILLS_DIR"); env && *env) return fs::path(env);
  if (const char* xdg = std::getenv("XDG_DATA_HOME"); xdg && *xdg) {
    return fs::path(xdg) / "marvin" / "skills";
  }
  if (const char* home = std::getenv("HOME"); home && *home) {
    return fs::path(home) / ".local/share/marvin/skills";
  }
  return std::nullopt;
}

bool is_store_directory(const fs::path& dir) {
  std::error_code ec;
  return fs::exists(dir / "skills.lock", ec) || fs::exists(dir / ".store" / "lock", ec);
}

void validate_skill_for_host(const fs::path& staged_dir) {
  try {
    skills::check_skill(staged_dir);
  } catch (const std::exception& e) {
    // Name files inside the package ("skill.json: $.host_api: ..."), not the staging folder
    // the user never sees.
    std::string message = e.what();
    const std::string prefix = (staged_dir / "").string();
    for (std::size_t at; (at = message.find(prefix)) != std::string::npos;) {
      message.erase(at, prefix.size());
    }
    throw std::runtime_error(message);
  }
}

fs::path reload_request_file(const fs::path& dir) { return dir / ".store" / "reload-request"; }

std::vector<store::PublicKey> repository_keys(const std::filesystem::path& dir) {
  std::vector<store::PublicKey> keys;
  const std::filesystem::path file = dir / ".store" / "repositories.json";
  if (!std::filesystem::exists(file)) return keys;
  const nlohmann::json repos = nlohmann::json::parse(store::read_text_file(file));
  for (auto it = repos.begin(); it != repos.end(); ++it) {
    for (const auto& k : it->at("keys"))
      keys.push_back(store::parse_public_key(k.get<std::string>(), "repositories.json"));
  }
  return keys;
}

}  // namespace marvin::app
