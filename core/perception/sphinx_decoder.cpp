#include "perception/sphinx_decoder.h"

#include <filesystem>
#include <mutex>
#include <stdexcept>

namespace marvin::perception::detail {

Decoder make_decoder(const SphinxModel& model,
                     const std::vector<std::pair<std::string, std::string>>& settings) {
  if (!std::filesystem::is_directory(model.acoustic_model)) {
    throw std::runtime_error("pocketsphinx acoustic model not found: " +
                             model.acoustic_model.string() +
                             " (install the pocketsphinx-en-us package)");
  }
  if (!std::filesystem::is_regular_file(model.dictionary)) {
    throw std::runtime_error("pocketsphinx dictionary not found: " + model.dictionary.string());
  }
  // cmd_ln and the log file are process-wide in sphinxbase: create one decoder at a time.
  static std::mutex creation;
  std::lock_guard lock(creation);
  std::vector<std::string> args = {"-hmm", model.acoustic_model.string(), "-dict",
                                   model.dictionary.string(), "-logfn", "/dev/null"};
  for (const auto& [name, value] : settings) {
    args.push_back(name);
    args.push_back(value);
  }
  std::vector<char*> argv;
  for (std::string& arg : args) argv.push_back(arg.data());
  cmd_ln_t* config =
      cmd_ln_parse_r(nullptr, ps_args(), static_cast<int32>(argv.size()), argv.data(), FALSE);
  if (config == nullptr) {
    throw std::runtime_error("pocketsphinx: invalid decoder settings for model " +
                             model.acoustic_model.string());
  }
  Decoder decoder(ps_init(config));
  cmd_ln_free_r(config);  // the decoder keeps its own reference
  if (!decoder) {
    throw std::runtime_error("pocketsphinx: cannot load the model " +
                             model.acoustic_model.string() + " with dictionary " +
                             model.dictionary.string());
  }
  return decoder;
}

}  // namespace marvin::perception::detail
