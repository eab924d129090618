// marvin-kws-model: shows a keyword-spotting model file and sets its detection defaults.
//
//   marvin-kws-model models/marvin-kws.bin
//   marvin-kws-model build-kws/run/marvin-kws.bin --threshold 0.9 --smoothing 1 --out
//   models/marvin-kws.bin
//
// The weights (and int8 scales) are copied as they are, so a model keeps the accuracy that
// was measured; only the decision settings that marvin-kws-eval chose change.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <optional>
#include <stdexcept>
#include <string>

#include "perception/kws/model_file.h"

namespace kws = marvin::perception::kws;

int main(int argc, char** argv) {
  CLI::App app{"Show a keyword-spotting model and set its detection defaults"};
  std::string path, out;
  std::optional<float> threshold, refractory;
  std::optional<int> smoothing;
  app.add_option("model", path, "model file")->required();
  app.add_option("--threshold", threshold, "threshold on the smoothed keyword posterior, (0, 1)");
  app.add_option("--smoothing", smoothing, "keyword posteriors averaged, 1..64 windows");
  app.add_option("--refractory", refractory, "seconds without a second detection, 0..10");
  app.add_option("--out", out, "write the model with these settings here");
  CLI11_PARSE(app, argc, argv);
  try {
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
    if (threshold) {
      if (!(*threshold > 0.0f && *threshold < 1.0f)) {
        throw std::runtime_error("--threshold " + std::to_string(*threshold) +
                                 ": expected a value in (0, 1)");
      }
      model.detection.threshold = *threshold;
    }
    if (smoothing) {
      if (*smoothing < 1 || *smoothing > 64) {
        throw std::runtime_error("--smoothing " + std::to_string(*smoothing) +
                                 ": expected 1..64 windows");
      }
      model.detection.smoothing_windows = *smoothing;
    }
    if (refractory) {
      if (!(*refractory >= 0.0f && *refractory <= 10.0f)) {
        throw std::runtime_error("--refractory " + std::to_string(*refractory) +
                                 ": expected 0..10 s");
      }
      model.detection.refractory_seconds = *refractory;
    }
    if ((threshold || smoothing || refractory) && out.empty()) {
      throw std::runtime_error(
          "--threshold/--smoothing/--refractory need --out (the file to write)");
    }
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
