#include "vision/model_files.h"

#include <cstdlib>
#include <system_error>

namespace marvin::vision {

std::vector<std::filesystem::path> model_search_path() {
  std::vector<std::filesystem::path> dirs;
  if (const char* env = std::getenv("MARVIN_VISION_MODELS"); env && *env) dirs.emplace_back(env);
#ifdef MARVIN_BUILD_MODELS_DIR
  dirs.emplace_back(MARVIN_BUILD_MODELS_DIR);
#endif
  // The user data directory, as core/data resolves it (without depending on that library).
  if (const char* d = std::getenv("MARVIN_DATA_DIR"); d && *d) {
    dirs.emplace_back(std::filesystem::path(d) / "models/vision");
  } else if (const char* x = std::getenv("XDG_DATA_HOME"); x && *x) {
    dirs.emplace_back(std::filesystem::path(x) / "marvin/models/vision");
  } else if (const char* h = std::getenv("HOME"); h && *h) {
    dirs.emplace_back(std::filesystem::path(h) / ".local/share/marvin/models/vision");
  }
  return dirs;
}

std::filesystem::path find_model(const std::string& name) {
  std::string looked;
  for (const auto& dir : model_search_path()) {
    std::error_code ec;
    const auto path = dir / name;
    if (std::filesystem::is_regular_file(path, ec)) return path;
    looked += (looked.empty() ? "" : ", ") + path.string();
  }
  throw ModelError("vision model " + name + " not found (looked in " + looked +
                   "): run scripts/setup, then build, to fetch and convert the models");
}

}  // namespace marvin::vision
