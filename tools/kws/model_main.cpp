// marvin-kws-model: shows a keyword-spotting model file (the cnn spotter's model or an
// embedding wake word's head) and sets its detection defaults.
//
//   marvin-kws-model models/marvin-kws.bin
//   marvin-kws-model build-kws/run/marvin-kws.bin --threshold 0.9 --smoothing 1 --out
//   models/marvin-kws.bin
//   marvin-kws-model head.bin --threshold 0.5 --consecutive 3 --out
//   models/marvin-embedding-head.bin
//   marvin-kws-model a.bin b.bin c.bin --threshold 0.95 --consecutive 3 --out merged.bin
//
// Several embedding heads are merged into one that scores the sigmoid of their mean logit
// (merge_heads in tools/kws/training/head_trainer.h); the first one's settings are the start.
//
// The weights (and int8 scales) are copied as they are, so a model keeps the accuracy that
// was measured; only the decision settings that marvin-kws-eval chose change.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "kws/training/head_trainer.h"
#include "perception/kws/embedding_head.h"
#include "perception/kws/model_file.h"

namespace kws = marvin::perception::kws;

namespace {

bool is_head_file(const std::string& path) {
  char magic[8] = {};
  std::ifstream in(path, std::ios::binary);
  in.read(magic, 8);
  return in.gcount() == 8 && std::memcmp(magic, "MRVNKWE", 8) == 0;
}

// Embedding heads (one, or several merged into one): threshold, refractory period and
// consecutive steps.
void set_head_defaults(const std::vector<std::string>& paths, std::optional<float> threshold,
                       std::optional<float> refractory, std::optional<int> consecutive,
                       const std::string& out) {
  std::vector<kws::EmbeddingHead> members;
  for (const auto& p : paths) members.push_back(kws::load_head(p));
  kws::EmbeddingHead head = members.size() == 1 ? members.front() : kws::merge_heads(members);
  const std::string path =
      members.size() == 1 ? paths.front() : std::to_string(members.size()) + " heads merged";
  auto show = [&head](const std::string& name) {
    std::printf("%s: embedding head for \"%s\", hidden %d\n", name.c_str(), head.keyword.c_str(),
                head.hidden);
    std::printf("detection: threshold %.3f, %d consecutive steps, refractory %.2f s\n",
                static_cast<double>(head.threshold), head.consecutive,
                static_cast<double>(head.refractory_seconds));
  };
  show(path);
  if (threshold) head.threshold = *threshold;
  if (refractory) head.refractory_seconds = *refractory;
  if (consecutive) head.consecutive = *consecutive;
  if (!out.empty()) {
    kws::save_head(out, head);
    show("wrote " + out);
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Show a keyword-spotting model and set its detection defaults"};
  std::vector<std::string> paths;
  std::string out;
  std::optional<float> threshold, refractory;
  std::optional<int> smoothing, consecutive;
  app.add_option("model", paths,
                 "model file; several embedding heads are merged into one (needs --out)")
      ->required();
  app.add_option("--threshold", threshold, "threshold on the smoothed keyword posterior, (0, 1)");
  app.add_option("--smoothing", smoothing, "keyword posteriors averaged, 1..64 windows");
  app.add_option("--refractory", refractory, "seconds without a second detection, 0..10");
  app.add_option("--consecutive", consecutive,
                 "embedding head: scores in a row over the threshold for a detection, 1..10");
  app.add_option("--out", out, "write the model with these settings here");
  CLI11_PARSE(app, argc, argv);
  try {
    // Every setting is checked before anything is written.
    if (threshold && !(*threshold > 0.0f && *threshold < 1.0f)) {
      throw std::runtime_error("--threshold " + std::to_string(*threshold) +
                               ": expected a value in (0, 1)");
    }
    if (smoothing && (*smoothing < 1 || *smoothing > 64)) {
      throw std::runtime_error("--smoothing " + std::to_string(*smoothing) +
                               ": expected 1..64 windows");
    }
    if (refractory && !(*refractory >= 0.0f && *refractory <= 10.0f)) {
      throw std::runtime_error("--refractory " + std::to_string(*refractory) +
                               ": expected 0..10 s");
    }
    if (consecutive && (*consecutive < 1 || *consecutive > 10)) {
      throw std::runtime_error("--consecutive " + std::to_string(*consecutive) +
                               ": expected 1..10 steps");
    }
    if ((threshold || smoothing || refractory || consecutive) && out.empty()) {
      throw std::runtime_error(
          "--threshold/--smoothing/--refractory/--consecutive need --out (the file to write)");
    }
    const std::string& path = paths.front();
    if (paths.size() > 1) {
      for (const auto& p : paths) {
        // (A missing file is load_head's to report.)
        if (std::filesystem::exists(p) && !is_head_file(p)) {
          throw std::runtime_error(p + ": not an embedding head; only heads can be merged");
        }
      }
      if (out.empty()) throw std::runtime_error("merging heads needs --out (the file to write)");
    }
    if (is_head_file(path)) {
      if (smoothing) {
        throw std::runtime_error(
            "--smoothing is the cnn spotter's; an embedding head takes "
            "--consecutive");
      }
      set_head_defaults(paths, threshold, refractory, consecutive, out);
      return 0;
    }
    if (consecutive) {
      throw std::runtime_error(
          "--consecutive is an embedding head's; the cnn spotter's "
          "model takes --smoothing");
    }
    kws::KwsModel model = kws::load_model(path);
    auto show = [&model](const std::string& name) {
      std::printf("%s: keyword \"%s\", %s weights, %zu parameters\n", name.c_str(),
                  model.keyword.c_str(), model.quantized ? "int8" : "float32",
                  model.network.parameter_count());
      std::printf("detection: threshold %.3f, smoothing %d windows, refractory %.2f s\n",
                  static_cast<double>(model.detection.threshold), model.detection.smoothing_windows,
                  static_cast<double>(model.detection.refractory_seconds));
    };
    show(path);
    if (threshold) model.detection.threshold = *threshold;
    if (smoothing) model.detection.smoothing_windows = *smoothing;
    if (refractory) model.detection.refractory_seconds = *refractory;
    if (!out.empty()) {
      kws::save_model(out, model,
                      model.quantized ? kws::WeightType::int8 : kws::WeightType::float32);
      show("wrote " + out);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "marvin-kws-model: %s\n", e.what());
    return 1;
  }
  return 0;
}
