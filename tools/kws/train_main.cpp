// marvin-kws-train: trains the cnn-trad-fpool3 keyword spotter and writes the int8 model.
//
//   marvin-kws-train --out models/marvin-kws.bin                 (synthesised with espeak-ng)
//   marvin-kws-train --data speech_commands_v0.02 --keyword marvin --out my.bin
//
// Steps: data (folder or synthesis) -> augmentation -> 10:1:2 split -> log-mel inputs ->
// normalisation -> mini-batch Adam on cross-entropy (progress bar with loss and accuracy per
// epoch, test accuracy after each) -> the epoch with the best test accuracy is kept ->
// activation calibration -> int8 per-channel quantisation -> float and int8 accuracy on the
// eval split -> model file(s).
#include <CLI/CLI.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <optional>

#include "perception/kws/dataset.h"
#include "perception/kws/model_file.h"
#include "perception/kws/trainer.h"

namespace kws = marvin::perception::kws;

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

void print_accuracy(const char* name, const kws::Accuracy& a) {
  std::printf("%-12s overall %6.2f%%  keyword %6.2f%%  unknown %6.2f%%  silence %6.2f%%  noise %6.2f%%\n",
              name, 100.0 * a.overall, 100.0 * a.per_class(0), 100.0 * a.per_class(1),
              100.0 * a.per_class(2), 100.0 * a.per_class(3));
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Train Marvin's neural keyword spotter (cnn-trad-fpool3, int8)"};
  std::string data_dir, noise_dir, out = "models/marvin-kws.bin", float_out, init;
  kws::DatasetOptions dopt;
  kws::TrainOptions topt;
  int epochs = 12, max_per_word = 0;
  float threshold = 0.6f;
  int smoothing = 3;
  app.add_option("--data", data_dir, "Speech Commands-style folder (one folder of WAVs per word, "
                                     "_background_noise_); synthesised with espeak-ng if absent");
  app.add_option("--noise", noise_dir, "folder of background-noise WAVs (else generated)");
  app.add_option("--out", out, "int8 model file to write")->capture_default_str();
  app.add_option("--float-out", float_out, "also write the float model here");
  app.add_option("--keyword", dopt.keyword, "keyword (folder name with --data)")->capture_default_str();
  app.add_option("--seed", dopt.seed, "seed for data, initialisation and order")->capture_default_str();
  app.add_option("--keyword-clips", dopt.keyword_clips, "synthesised keyword utterances")->capture_default_str();
  app.add_option("--unknown-clips", dopt.unknown_clips, "synthesised other words / sentence pieces")->capture_default_str();
  app.add_option("--silence-clips", dopt.silence_clips)->capture_default_str();
  app.add_option("--noise-clips", dopt.noise_clips)->capture_default_str();
  app.add_option("--copies", dopt.augmented_copies, "augmented training examples per training clip")->capture_default_str();
  app.add_option("--max-per-word", max_per_word, "with --data: at most this many files per word (0 = all)");
  app.add_option("--epochs", epochs)->capture_default_str();
  app.add_option("--batch", topt.batch_size)->capture_default_str();
  app.add_option("--lr", topt.learning_rate, "Adam learning rate (cosine-decayed to 5%)")->capture_default_str();
  app.add_option("--weight-decay", topt.weight_decay)->capture_default_str();
  app.add_option("--threads", topt.threads)->capture_default_str();
  app.add_option("--threshold", threshold, "detection threshold stored in the model")->capture_default_str();
  app.add_option("--smoothing", smoothing, "posterior smoothing windows stored in the model")->capture_default_str();
  app.add_option("--context", dopt.context_probability,
                 "probability of speech around a word in its window")->capture_default_str();
  app.add_flag("--random-sentences", dopt.random_sentences,
               "half the sentence pieces from random word sequences");
  app.add_option("--init", init, "start from this float model's weights and normalisation "
                                 "(fine-tuning) instead of random weights");
  CLI11_PARSE(app, argc, argv);

  try {
    const auto start = Clock::now();
    dopt.noise_folder = noise_dir;
    dopt.log = [&](const std::string& s) {
      std::fprintf(stderr, "[%6.1fs] data: %s\n", seconds_since(start), s.c_str());
    };
    kws::SplitClips clips = data_dir.empty() ? kws::synthesize_dataset(dopt)
                                             : kws::read_speech_commands(data_dir, dopt, max_per_word);
    std::printf("clips: train %zu (augmented x%d), test %zu, eval %zu; %.1f s\n", clips.train.size(),
                dopt.augmented_copies, clips.test.size(), clips.eval.size(), seconds_since(start));
    kws::TrainingSet train = kws::clips_to_inputs(clips.train, topt.threads);
    kws::TrainingSet test = kws::clips_to_inputs(clips.test, topt.threads);
    kws::TrainingSet eval = kws::clips_to_inputs(clips.eval, topt.threads);
    clips = {};
    std::optional<kws::KwsModel> start_model;
    if (!init.empty()) start_model = kws::load_model(init);
    const kws::Normalisation norm = start_model ? start_model->normalisation : kws::compute_normalisation(train);
    kws::normalise(train, norm);
    kws::normalise(test, norm);
    kws::normalise(eval, norm);
    std::printf("features: %.1f s\n", seconds_since(start));
    std::fflush(stdout);

    kws::FloatNetwork net = start_model ? start_model->network : kws::make_initialised_network(dopt.seed);
    std::printf("network: %zu parameters\n", net.parameter_count());
    kws::Trainer trainer(net, topt);
    std::mt19937_64 order_rng(dopt.seed ^ 0x5DEECE66Dull);
    kws::FloatNetwork best = net;
    double best_test = -1.0;
    for (int e = 0; e < epochs; ++e) {
      const float lr = topt.learning_rate *
                       (0.05f + 0.95f * 0.5f * (1.0f + std::cos(3.14159265f * static_cast<float>(e) /
                                                                static_cast<float>(std::max(1, epochs)))));
      trainer.set_learning_rate(lr);
      const auto epoch_start = Clock::now();
      int last_pct = -1;
      const kws::EpochStats s = trainer.train_epoch(
          train, order_rng, [&](std::size_t done, std::size_t total, double loss, double acc) {
            const int pct = static_cast<int>(100 * done / total);
            if (pct == last_pct && done != total) return;
            last_pct = pct;
            constexpr int width = 30;
            const int fill = pct * width / 100;
            std::fprintf(stderr, "\repoch %2d/%d [%.*s%*s] %3d%% loss %.4f acc %6.2f%% %5.0fs", e + 1,
                         epochs, fill, "##############################", width - fill, "", pct, loss,
                         100.0 * acc, seconds_since(epoch_start));
          });
      const kws::Accuracy t = kws::evaluate_float(net, test);
      std::fprintf(stderr, "\n");
      std::printf("epoch %2d/%d  lr %.2e  loss %.4f  train acc %6.2f%%  test acc %6.2f%%  (%.0f s, total %.0f s)\n",
                  e + 1, epochs, static_cast<double>(lr), s.loss, 100.0 * s.accuracy, 100.0 * t.overall,
                  seconds_since(epoch_start), seconds_since(start));
      std::fflush(stdout);
      if (t.overall > best_test) {
        best_test = t.overall;
        best = net;
      }
    }
    net = best;

    kws::KwsModel model;
    model.keyword = dopt.keyword;
    model.normalisation = norm;
    model.network = net;
    model.detection.threshold = threshold;
    model.detection.smoothing_windows = smoothing;
    model.scales = kws::calibrate(net, train);
    const kws::QuantizedNetwork q = model.int8_network();
    const kws::Accuracy fa = kws::evaluate_float(net, eval);
    const kws::Accuracy ia = kws::evaluate_int8(q, eval);
    std::printf("eval split (%zu clips, training voices):\n", eval.size());
    print_accuracy("float", fa);
    print_accuracy("int8", ia);
    std::printf("int8 - float: %+.2f points\n", 100.0 * (ia.overall - fa.overall));
    kws::save_model(out, model, kws::WeightType::int8);
    std::printf("wrote %s (int8)\n", out.c_str());
    if (!float_out.empty()) {
      kws::save_model(float_out, model, kws::WeightType::float32);
      std::printf("wrote %s (float)\n", float_out.c_str());
    }
    std::printf("total %.1f s\n", seconds_since(start));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "marvin-kws-train: %s\n", e.what());
    return 1;
  }
  return 0;
}
