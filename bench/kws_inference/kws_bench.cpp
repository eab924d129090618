// kws_bench [MODEL [FLOAT_MODEL]]: the neural keyword spotter's costs, measured in one run.
//
//   1. One window through the float network and through the int8 network with every int8
//      kernel this CPU has (portable, AVX2, AVX-512 VNNI; the same model, the float path with
//      the int8 weights dequantised, so all do the same work), timed alternately in blocks;
//      median per window in thread CPU time (what one core spends, whatever else the machine
//      runs) and wall clock; ratio against the portable loops of the same run; which kernel
//      the robot uses here (the fastest). A CPU with VNNI thus also shows the AVX2 path.
//   2. Model file size.
//   3. Listening CPU share: 60 s of noise and speech through NeuralWakeWord::process (log-mel
//      features + a window every 250 ms), CPU time / audio time; with the fastest kernel and,
//      on a CPU with VNNI, with AVX2 forced.
//   4. int8 accuracy vs float on clips from held-out voices (against FLOAT_MODEL if given,
//      else against the dequantised float path, which isolates activation quantisation).
// Figures only; never fails on time.
#include <algorithm>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <random>
#include <vector>

#include "devices/audio/sound_buffer.h"
#include "kws/training/augment.h"
#include "kws/training/dataset.h"
#include "perception/kws/neural_wake_word.h"

namespace kws = marvin::perception::kws;

namespace {

double thread_cpu_us() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) * 1e6 + static_cast<double>(ts.tv_nsec) / 1e3;
}

double wall_us() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<double>(ts.tv_sec) * 1e6 + static_cast<double>(ts.tv_nsec) / 1e3;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  const std::filesystem::path model_path = argc > 1 ? std::filesystem::path(argv[1]) : kws::default_model_path();
  const kws::KwsModel model = kws::load_model(model_path);
  const kws::QuantizedNetwork q = model.int8_network();
  kws::FloatInference float_net(model.network);
  std::printf("kws_bench: %s (keyword \"%s\")\n", model_path.c_str(), model.keyword.c_str());

  // 1. Per-window inference: float, then every int8 kernel this CPU has (the robot runs the
  // fastest; the others are what a CPU without it would run), timed in interleaved blocks.
  std::mt19937_64 rng(1);
  std::normal_distribution<float> g(0.0f, 1.0f);
  std::vector<float> input(kws::kInputSize), probs(kws::kClasses);
  for (float& v : input) v = g(rng);
  std::vector<kws::Int8Kernel> kernels;
  for (kws::Int8Kernel k :
       {kws::Int8Kernel::portable, kws::Int8Kernel::avx2, kws::Int8Kernel::avx512_vnni}) {
    if (kws::kernel_available(k)) kernels.push_back(k);
  }
  std::vector<kws::Int8Inference> nets(kernels.size(), kws::Int8Inference(q));
  for (std::size_t k = 0; k < kernels.size(); ++k) nets[k].set_kernel(kernels[k]);
  constexpr int kBlocks = 20, kPerBlock = 50;
  std::vector<double> f_cpu, f_wall;
  std::vector<std::vector<double>> q_cpu(kernels.size()), q_wall(kernels.size());
  for (int i = 0; i < 20; ++i) {  // warm up
    float_net.run(input, probs);
    for (auto& n : nets) n.run(input, probs);
  }
  for (int b = 0; b < kBlocks; ++b) {
    double c0 = thread_cpu_us(), w0 = wall_us();
    for (int i = 0; i < kPerBlock; ++i) float_net.run(input, probs);
    f_cpu.push_back((thread_cpu_us() - c0) / kPerBlock);
    f_wall.push_back((wall_us() - w0) / kPerBlock);
    for (std::size_t k = 0; k < nets.size(); ++k) {
      c0 = thread_cpu_us();
      w0 = wall_us();
      for (int i = 0; i < kPerBlock; ++i) nets[k].run(input, probs);
      q_cpu[k].push_back((thread_cpu_us() - c0) / kPerBlock);
      q_wall[k].push_back((wall_us() - w0) / kPerBlock);
    }
  }
  const double macs = 9.70e6;
  const double portable_cpu = median(q_cpu[0]);
  std::printf("\nper window (median of %d blocks of %d)  CPU time   wall clock  speed-up  GMAC/s\n",
              kBlocks, kPerBlock);
  std::printf("  float (Eigen)                      %8.1f us %8.1f us  %6.1f x\n", median(f_cpu),
              median(f_wall), portable_cpu / median(f_cpu));
  for (std::size_t k = 0; k < nets.size(); ++k) {
    const double cpu = median(q_cpu[k]);
    std::printf("  int8 %-13s%s                %8.1f us %8.1f us  %6.1f x  %6.1f%s\n",
                kws::kernel_name(kernels[k]), kernels[k] == kws::best_int8_kernel() ? "*" : " ",
                cpu, median(q_wall[k]), portable_cpu / cpu, macs / cpu / 1e3,
                kernels[k] == kws::Int8Kernel::avx2 ? "   goal < 300 us" : "");
  }
  std::printf("  (speed-up: the portable int8 loops' time / this one's, same run; * the kernel the\n"
              "   robot uses here; 9.7 M multiply-accumulates per window)\n");

  // 2. Size.
  const auto size = std::filesystem::file_size(model_path);
  std::printf("\nmodel file: %ju bytes (%.1f KB)   goal < 300 KB\n", static_cast<std::uintmax_t>(size), static_cast<double>(size) / 1024.0);

  // 3. Listening: 60 s of babble-free room noise with a few sentences.
  std::vector<float> audio = kws::make_noise(kws::NoiseColour::pink, 60 * 16000, 0.01f, rng);
  for (int k = 0; k < 6; ++k) {
    const std::vector<float> s = kws::synthesize(kws::sentences()[static_cast<std::size_t>(k)], "en-us", 160, 50);
    for (std::size_t i = 0; i < s.size() && static_cast<std::size_t>(k) * 160000 + 8000 + i < audio.size(); ++i) {
      audio[static_cast<std::size_t>(k) * 160000 + 8000 + i] += 0.3f * s[i];
    }
  }
  const std::vector<std::int16_t> pcm = marvin::audio::to_pcm16(audio);
  // With the fastest kernel (what the robot spends here), then with AVX2 forced when the CPU
  // has something faster (what a CPU without VNNI spends).
  std::vector<kws::Int8Kernel> listen_kernels = {kws::best_int8_kernel()};
  if (kws::best_int8_kernel() == kws::Int8Kernel::avx512_vnni) {
    listen_kernels.push_back(kws::Int8Kernel::avx2);
  }
  std::printf("\n");
  for (kws::Int8Kernel kernel : listen_kernels) {
    kws::NeuralWakeWord detector(model, 0.5f, kws::Precision::int8);
    detector.spotter().set_int8_kernel(kernel);
    std::vector<marvin::perception::WakeWordDetection> det;
    const double c0 = thread_cpu_us();
    for (std::size_t i = 0; i < pcm.size(); i += 1600) {
      detector.process(std::span<const std::int16_t>(pcm).subspan(i, std::min<std::size_t>(1600, pcm.size() - i)), det);
    }
    const double cpu_s = (thread_cpu_us() - c0) / 1e6;
    std::printf("listening (%s): 60 s of audio in %.3f s CPU -> %.2f%% of one core (%lld windows, %zu "
                "detections)   goal < 2%%\n",
                kws::kernel_name(kernel), cpu_s, 100.0 * cpu_s / 60.0,
                static_cast<long long>(detector.spotter().windows_run()), det.size());
  }

  // 4. Accuracy, int8 vs float, held-out voices.
  kws::DatasetOptions o;
  o.seed = 4242;
  o.voices = kws::heldout_voices();
  o.keyword = model.keyword;
  o.keyword_clips = 120;
  o.unknown_clips = 120;
  o.silence_clips = 30;
  o.noise_clips = 30;
  o.augmented_copies = 1;
  kws::SplitClips split = kws::synthesize_dataset(o);
  std::vector<kws::AudioClip> clips = std::move(split.train);
  clips.insert(clips.end(), split.test.begin(), split.test.end());
  clips.insert(clips.end(), split.eval.begin(), split.eval.end());
  kws::TrainingSet set = kws::clips_to_inputs(clips, 1);
  kws::normalise(set, model.normalisation);
  const bool have_float = argc > 2;
  const kws::FloatNetwork reference = have_float ? kws::load_model(argv[2]).network : model.network;
  const kws::Accuracy fa = kws::evaluate_float(reference, set);
  const kws::Accuracy ia = kws::evaluate_int8(q, set);
  std::printf("\naccuracy on %zu held-out clips: float %.2f%% (%s), int8 %.2f%% -> int8 - float %+.2f points   goal within 1\n",
              set.size(), 100.0 * fa.overall, have_float ? "trained float weights" : "dequantised weights",
              100.0 * ia.overall, 100.0 * (ia.overall - fa.overall));
  return 0;
}
