// Where the pocketsphinx acoustic model and pronunciation dictionary live.
#pragma once

#include <filesystem>

namespace marvin::perception {

struct SphinxModel {
  // Debian's pocketsphinx-en-us package.
  std::filesystem::path acoustic_model = "/usr/share/pocketsphinx/model/en-us/en-us";
  std::filesystem::path dictionary = "/usr/share/pocketsphinx/model/en-us/cmudict-en-us.dict";
};

}  // namespace marvin::perception
