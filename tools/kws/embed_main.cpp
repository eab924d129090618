// marvin-kws-embed: runs Marvin's mel front end and speech embedding (speech_embedding.h) on
// sound files and writes what they computed as raw float32 files, for tools/kws/check-embedding
// to compare with onnxruntime running the original ONNX graphs. Also prints the cost per
// second of audio of the streaming path.
//
//   marvin-kws-embed [--models DIR] --out DIR FILE...
//
// For each FILE (any format libsndfile reads; converted to 16 kHz mono) it writes into --out:
//   NAME.samples.f32  the samples in int16 units (the mel graph's input)
//   NAME.mel.f32      the mel front end on the whole file: frames x 32 (the graph's output)
//   NAME.windows.f32  the embedding inputs: every 8th 76-frame window of that mel, x / 10 + 2
//   NAME.emb.f32      the embedding of each window: windows x 96
#include <cstdio>
#include <ctime>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "devices/audio/sound_file.h"
#include "perception/kws/speech_embedding.h"

namespace kws = marvin::perception::kws;

namespace {

void write_floats(const std::filesystem::path& file, const std::vector<float>& values) {
  std::ofstream out(file, std::ios::binary);
  out.write(reinterpret_cast<const char*>(values.data()),
            static_cast<std::streamsize>(values.size() * sizeof(float)));
  if (!out) throw std::runtime_error(file.string() + ": cannot write");
}

// CPU time of this thread (not wall clock: the machine may be busy with other work).
double thread_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + static_cast<double>(t.tv_nsec) * 1e-9;
}

}  // namespace

int main(int argc, char** argv) {
  std::filesystem::path models = kws::embedding_model_dir();
  std::filesystem::path out_dir;
  std::vector<std::filesystem::path> files;
  for (int k = 1; k < argc; ++k) {
    const std::string arg = argv[k];
    if (arg == "--models" && k + 1 < argc)
      models = argv[++k];
    else if (arg == "--out" && k + 1 < argc)
      out_dir = argv[++k];
    else if (arg == "--help" || arg == "-h") {
      std::cout << "usage: marvin-kws-embed [--models DIR] --out DIR FILE...\n";
      return 0;
    } else
      files.emplace_back(arg);
  }
  if (out_dir.empty() || files.empty()) {
    std::cerr << "usage: marvin-kws-embed [--models DIR] --out DIR FILE...\n";
    return 2;
  }
  try {
    const auto loaded = kws::EmbeddingModels::load(models);
    std::filesystem::create_directories(out_dir);
    double audio_seconds = 0.0, stream_seconds = 0.0;
    for (const auto& file : files) {
      const std::vector<std::int16_t> pcm = marvin::audio::read_speech_file(file);
      std::vector<float> samples(pcm.begin(), pcm.end());
      const std::string name = file.stem().stem().string();
      write_floats(out_dir / (name + ".samples.f32"), samples);
      const std::vector<float> mel = loaded->mel.compute(samples);
      write_floats(out_dir / (name + ".mel.f32"), mel);
      const std::size_t frames = mel.size() / kws::kMelBins;
      std::vector<float> windows, embeddings;
      for (std::size_t first = 0; first + kws::kEmbeddingFrames <= frames; first += 8) {
        std::vector<float> window(
            mel.begin() + static_cast<std::ptrdiff_t>(first * kws::kMelBins),
            mel.begin() +
                static_cast<std::ptrdiff_t>((first + kws::kEmbeddingFrames) * kws::kMelBins));
        for (float& v : window) v = v / 10.0f + 2.0f;
        const kws::Embedding e = loaded->embedding.embed(window);
        windows.insert(windows.end(), window.begin(), window.end());
        embeddings.insert(embeddings.end(), e.begin(), e.end());
      }
      write_floats(out_dir / (name + ".windows.f32"), windows);
      write_floats(out_dir / (name + ".emb.f32"), embeddings);
      // The streaming path as the wake word runs it, timed.
      kws::EmbeddingStream stream(loaded);
      std::vector<kws::Embedding> streamed;
      const double start = thread_cpu_seconds();
      stream.push(samples, streamed);
      stream_seconds += thread_cpu_seconds() - start;
      audio_seconds += static_cast<double>(samples.size()) / 16000.0;
      std::printf("%s: %zu samples, %zu mel frames, %zu embeddings\n", name.c_str(), samples.size(),
                  frames, embeddings.size() / kws::kEmbeddingSize);
    }
    std::printf(
        "streaming cost: %.3f s of CPU for %.1f s of audio = %.2f%% of one core "
        "(%.2f M multiply-accumulates per embedding)\n",
        stream_seconds, audio_seconds, 100.0 * stream_seconds / audio_seconds,
        static_cast<double>(loaded->embedding.macs()) / 1e6);
  } catch (const std::exception& e) {
    std::cerr << "marvin-kws-embed: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
