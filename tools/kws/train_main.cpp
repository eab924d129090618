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
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "kws/training/dataset.h"
#include "kws/training/generated_voices.h"
#include "kws/training/trainer.h"
#include "perception/kws/model_file.h"
#include "train_embedding.h"

namespace kws = marvin::perception::kws;

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

void print_accuracy(const char* name, const kws::Accuracy& a) {
  std::printf(
      "%-12s overall %6.2f%%  keyword %6.2f%%  unknown %6.2f%%  silence %6.2f%%  noise %6.2f%%\n",
      name, 100.0 * a.overall, 100.0 * a.per_class(0), 100.0 * a.per_class(1),
      100.0 * a.per_class(2), 100.0 * a.per_class(3));
}

}  // namespace

int main(int argc, char** argv) {
  // --embedding: the embedding wake word's head instead (train_embedding.cpp).
  for (int k = 1; k < argc; ++k) {
    if (std::string(argv[k]) == "--embedding") return train_embedding_main(argc, argv);
  }
  CLI::App app{"Train Marvin's neural keyword spotter (cnn-trad-fpool3, int8)"};
  std::string data_dir, noise_dir, out = "models/marvin-kws.bin", float_out, init;
  kws::DatasetOptions dopt;
  kws::TrainOptions topt;
  int epochs = 12, max_per_word = 0;
  float threshold = 0.6f;
  int smoothing = 3;
  app.add_option("--data", data_dir,
                 "Speech Commands-style folder (one folder of WAVs per word, "
                 "_background_noise_); synthesised with espeak-ng if absent");
  app.add_option("--noise", noise_dir, "folder of background-noise WAVs (else generated)");
  app.add_option("--out", out, "int8 model file to write")->capture_default_str();
  app.add_option("--float-out", float_out, "also write the float model here");
  app.add_option("--keyword", dopt.keyword, "keyword (folder name with --data)")
      ->capture_default_str();
  app.add_option("--seed", dopt.seed, "seed for data, initialisation and order")
      ->capture_default_str();
  app.add_option("--keyword-clips", dopt.keyword_clips, "synthesised keyword utterances")
      ->capture_default_str();
  app.add_option("--unknown-clips", dopt.unknown_clips, "synthesised other words / sentence pieces")
      ->capture_default_str();
  app.add_option("--silence-clips", dopt.silence_clips)->capture_default_str();
  app.add_option("--noise-clips", dopt.noise_clips)->capture_default_str();
  app.add_option("--copies", dopt.augmented_copies, "augmented training examples per training clip")
      ->capture_default_str();
  app.add_option("--max-per-word", max_per_word,
                 "with --data: at most this many files per word (0 = all)");
  app.add_option("--epochs", epochs)->capture_default_str();
  app.add_option("--batch", topt.batch_size)->capture_default_str();
  app.add_option("--lr", topt.learning_rate, "Adam learning rate (cosine-decayed to 5%)")
      ->capture_default_str();
  app.add_option("--weight-decay", topt.weight_decay)->capture_default_str();
  app.add_option("--freq-mask", topt.freq_mask_bins,
                 "SpecAugment: each example, every epoch, loses a band of up to this many mel bins")
      ->capture_default_str();
  app.add_option("--time-mask", topt.time_mask_frames,
                 "SpecAugment: ... and a span of up to this many input frames (30 ms each)")
      ->capture_default_str();
  app.add_option("--freq-warp", topt.freq_warp,
                 "vocal tract length perturbation: each example, every epoch, has its mel axis "
                 "warped by a factor in [1/(1+W), 1+W]")
      ->check(CLI::Range(0.0f, 1.0f))
      ->capture_default_str();
  app.add_option("--threads", topt.threads)->capture_default_str();
  app.add_option("--threshold", threshold, "detection threshold stored in the model")
      ->capture_default_str();
  app.add_option("--smoothing", smoothing, "posterior smoothing windows stored in the model")
      ->capture_default_str();
  app.add_option("--context", dopt.context_probability,
                 "probability of speech around a word in its window")
      ->capture_default_str();
  app.add_flag("--random-sentences", dopt.random_sentences,
               "half the sentence pieces from random word sequences");
  app.add_option("--init", init,
                 "start from this float model's weights and normalisation "
                 "(fine-tuning) instead of random weights");
  double mine_minutes = 0.0;
  float mine_floor = 0.05f, mine_keep = 0.02f;
  int mine_copies = 2;
  app.add_option("--mine-minutes", mine_minutes,
                 "hard-negative mining (needs --init): this much keyword-free speech in training "
                 "voices, cut into streaming windows, scored by the --init model")
      ->capture_default_str();
  app.add_option("--mine-floor", mine_floor,
                 "mined windows whose keyword posterior reaches this join the unknown class")
      ->capture_default_str();
  app.add_option("--mine-keep", mine_keep, "fraction of the other mined windows that join it too")
      ->capture_default_str();
  app.add_option("--mine-copies", mine_copies, "copies of each hard mined window")
      ->capture_default_str();
  int generated_voices = 0;
  std::string voices_dir;
  app.add_option("--generated-voices", generated_voices,
                 "also train (and mine) on this many random espeak-ng variants (formants, pitch, "
                 "voicing) of each training accent; none of them is a held-out voice")
      ->capture_default_str();
  app.add_option("--voices-dir", voices_dir,
                 "with --generated-voices: where the private espeak-ng data goes (must not exist; "
                 "default: a temporary directory, removed at exit)");
  CLI11_PARSE(app, argc, argv);

  try {
    // Checked before the minutes of synthesis, not after.
    if (mine_minutes > 0.0 && init.empty()) {
      throw std::runtime_error("--mine-minutes needs --init (the model that scores the windows)");
    }
    if (mine_minutes < 0.0 || !(mine_floor > 0.0f && mine_floor <= 1.0f) || mine_keep < 0.0f ||
        mine_keep > 1.0f || mine_copies < 1) {
      throw std::runtime_error(
          "--mine-minutes must be >= 0, --mine-floor in (0, 1], --mine-keep in "
          "[0, 1], --mine-copies >= 1");
    }
    std::unique_ptr<kws::GeneratedVoiceSet> generated;
    if (generated_voices > 0) {
      if (!data_dir.empty())
        throw std::runtime_error("--generated-voices is for synthesised data, not --data");
      generated = std::make_unique<kws::GeneratedVoiceSet>(generated_voices, dopt.seed, voices_dir);
      dopt.voices = generated->voices();
      std::printf("voices: %zu (%d generated variants x %zu accents added)\n", dopt.voices.size(),
                  generated_voices, kws::training_accents().size());
    }
    const auto start = Clock::now();
    dopt.noise_folder = noise_dir;
    dopt.log = [&](const std::string& s) {
      std::fprintf(stderr, "[%6.1fs] data: %s\n", seconds_since(start), s.c_str());
    };
    kws::SplitClips clips = data_dir.empty()
                                ? kws::synthesize_dataset(dopt)
                                : kws::read_speech_commands(data_dir, dopt, max_per_word);
    std::printf("clips: train %zu (augmented x%d), test %zu, eval %zu; %.1f s\n",
                clips.train.size(), dopt.augmented_copies, clips.test.size(), clips.eval.size(),
                seconds_since(start));
    kws::TrainingSet train = kws::clips_to_inputs(clips.train, topt.threads);
    kws::TrainingSet test = kws::clips_to_inputs(clips.test, topt.threads);
    kws::TrainingSet eval = kws::clips_to_inputs(clips.eval, topt.threads);
    const std::vector<std::vector<float>> noise_pool = std::move(clips.noise_pool);
    clips = {};
    std::optional<kws::KwsModel> start_model;
    if (!init.empty()) start_model = kws::load_model(init);
    const kws::Normalisation norm =
        start_model ? start_model->normalisation : kws::compute_normalisation(train);
    kws::normalise(train, norm);
    kws::normalise(test, norm);
    kws::normalise(eval, norm);
    std::printf("features: %.1f s\n", seconds_since(start));
    if (mine_minutes > 0.0) {
      // Hard negatives: the windows of keyword-free speech the starting model takes for the
      // keyword (what fires in a stream), plus a few ordinary ones so the rest stays known.
      std::mt19937_64 mine_rng(dopt.seed ^ 0x4D494E45ull);
      const std::vector<std::string> voices =
          dopt.voices.empty() ? kws::training_voices() : dopt.voices;
      const std::vector<float> speech =
          kws::negative_speech(mine_minutes * 60.0, voices, noise_pool, mine_rng);
      kws::TrainingSet windows = kws::stream_windows(speech, start_model->features.hop_frames,
                                                     static_cast<int>(kws::KwsClass::unknown));
      kws::normalise(windows, norm);
      kws::FloatInference scorer(start_model->network);
      std::uniform_real_distribution<float> u(0.0f, 1.0f);
      std::size_t hard = 0, over_half = 0, kept = 0;
      float probs[kws::kClasses];
      for (std::size_t i = 0; i < windows.size(); ++i) {
        scorer.run(windows.input(i), probs);
        const bool is_hard = probs[0] >= mine_floor;
        hard += is_hard;
        over_half += probs[0] >= 0.5f;
        const int copies = is_hard ? std::max(1, mine_copies) : (u(mine_rng) < mine_keep ? 1 : 0);
        for (int k = 0; k < copies; ++k) {
          train.inputs.insert(train.inputs.end(), windows.input(i).begin(), windows.input(i).end());
          train.labels.push_back(windows.labels[i]);
          ++kept;
        }
      }
      std::printf(
          "mined %.1f min of speech: %zu windows, %zu with keyword posterior >= %.2f (%zu >= 0.5), "
          "%zu examples added; %.1f s\n",
          mine_minutes, windows.size(), hard, static_cast<double>(mine_floor), over_half, kept,
          seconds_since(start));
      std::fflush(stdout);
    }
    std::fflush(stdout);

    kws::FloatNetwork net =
        start_model ? start_model->network : kws::make_initialised_network(dopt.seed);
    std::printf("network: %zu parameters\n", net.parameter_count());
    kws::Trainer trainer(net, topt);
    std::mt19937_64 order_rng(dopt.seed ^ 0x5DEECE66Dull);
    kws::FloatNetwork best = net;
    double best_test = -1.0;
    for (int e = 0; e < epochs; ++e) {
      const float lr = topt.learning_rate *
                       (0.05f + 0.95f * 0.5f *
                                    (1.0f + std::cos(3.14159265f * static_cast<float>(e) /
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
            std::fprintf(stderr, "\repoch %2d/%d [%.*s%*s] %3d%% loss %.4f acc %6.2f%% %5.0fs",
                         e + 1, epochs, fill, "##############################", width - fill, "",
                         pct, loss, 100.0 * acc, seconds_since(epoch_start));
          });
      const kws::Accuracy t = kws::evaluate_float(net, test);
      std::fprintf(stderr, "\n");
      std::printf(
          "epoch %2d/%d  lr %.2e  loss %.4f  train acc %6.2f%%  test acc %6.2f%%  (%.0f s, total "
          "%.0f s)\n",
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
