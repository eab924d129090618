// The recipe (tools/kws/README.md): every example is 2.08 s of audio run through a fresh
// EmbeddingStream (as the detector hears it after a pause), of which the head sees the last 16
// embeddings (1.28 s):
// - positives: the keyword (espeak-ng, training voices, rate 110..230 wpm, pitch 20..80, half
//   the time with its speed changed by 0.9..1.1) ending 0..240 ms before the example's end
//   (--keyword-tail); half the time the end of another utterance 0.1..0.5 s before it, and in
//   a share --keyword-after the start of one 0.1..0.3 s after it;
// - late keywords (negatives): the keyword ended 0.21..0.96 s before the positives' latest end;
// - near misses (negatives, --near-misses): made as the positives are, with a word that sounds
//   like the keyword in its place;
// - with --lead-ins, a share of the keyword, near-miss and other-speech utterances start with
//   a lead-in word said in the same breath ("hey marvin");
// - negatives: the same with other words / sentence pieces / words that sound like the keyword
//   in place of the keyword, and real recordings of other words (--negatives-dir, each file
//   `--real-copies` times), ending 0..240 ms before the example's end (--negative-tail); the
//   keyword-free conversation of negative_speech(), cut into every second window of 16
//   embeddings; pure background noise;
// - everything over background noise (the noise pool) at an SNR in [-5, 10] dB (80 %; see
//   --quiet-share), else a quiet floor or digital silence, at a peak level of -18..-2 dBFS.
// Synthesis runs on one thread (espeak-ng keeps global state); embedding on --threads.
#include "train_embedding.h"

#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <random>
#include <thread>

#include "devices/audio/sound_file.h"
#include "kws/training/augment.h"
#include "kws/training/dataset.h"
#include "kws/training/festival_voices.h"
#include "kws/training/flite_voices.h"
#include "kws/training/generated_voices.h"
#include "kws/training/head_trainer.h"
#include "perception/kws/speech_embedding.h"

namespace kws = marvin::perception::kws;

namespace {

constexpr std::size_t kExampleHops = 26;
constexpr std::size_t kExampleSamples = kExampleHops * kws::kEmbeddingHop;

struct RawExample {
  std::vector<float> audio;  // kExampleSamples, float [-1, 1]
  float label = 0.0f;
};

float level_gain(const std::vector<float>& x, float peak_db) {
  float peak = 0.0f;
  for (float v : x) peak = std::max(peak, std::fabs(v));
  return std::pow(10.0f, peak_db / 20.0f) / std::max(peak, 1e-6f);
}

// Words in examples end 0..kDefaultTailS seconds before the window's end (the keyword's own
// range is --keyword-tail); late keywords end kLateKeywordFromS..kLateKeywordToS further back.
constexpr float kDefaultTailS = 0.24f;
constexpr float kLateKeywordFromS = 0.21f, kLateKeywordToS = 0.96f;

// Places `word` to end `tail` samples before the end of an example, with optional context
// before it, over noise.
RawExample place(const std::vector<float>& word, const std::vector<float>* context, float label,
                 const std::vector<std::vector<float>>& noise_pool, float quiet_share,
                 std::mt19937_64& rng, float tail_min_s = 0.0f, float tail_max_s = kDefaultTailS,
                 const std::vector<float>* after = nullptr) {
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  RawExample ex;
  ex.label = label;
  ex.audio.assign(kExampleSamples, 0.0f);
  const float peak_db = -18.0f + 16.0f * u(rng);
  const auto tail =
      static_cast<std::size_t>((tail_min_s + (tail_max_s - tail_min_s) * u(rng)) * 16000.0f);
  if (after != nullptr && !after->empty()) {
    // Speech after the word ("marvin, what time is it"), from 0.1..0.3 s after it; none when
    // the word ends closer than that to the window's end.
    const auto gap = static_cast<std::size_t>((0.1f + 0.2f * u(rng)) * 16000.0f);
    if (tail > gap) {
      const std::size_t begin = kExampleSamples - tail + gap;
      const float ga = level_gain(*after, peak_db - 4.0f + 6.0f * u(rng));
      for (std::size_t i = 0; begin + i < kExampleSamples && i < after->size(); ++i)
        ex.audio[begin + i] += ga * (*after)[i];
    }
  }
  const std::size_t len = std::min(word.size(), kExampleSamples - tail - 1);
  const std::size_t start = kExampleSamples - tail - len;
  const float g = level_gain(word, peak_db);
  for (std::size_t i = 0; i < len; ++i) ex.audio[start + i] += g * word[word.size() - len + i];
  if (context != nullptr && !context->empty()) {
    const auto gap = static_cast<std::size_t>((0.1f + 0.4f * u(rng)) * 16000.0f);
    if (start > gap) {
      const std::size_t end = start - gap;
      const std::size_t n = std::min(end, context->size());
      const float gc = level_gain(*context, peak_db - 6.0f + 8.0f * u(rng));
      for (std::size_t i = 0; i < n; ++i)
        ex.audio[end - n + i] += gc * (*context)[context->size() - n + i];
    }
  }
  const auto& noise =
      noise_pool[std::uniform_int_distribution<std::size_t>(0, noise_pool.size() - 1)(rng)];
  if (u(rng) >= quiet_share) {
    kws::add_noise_at_snr(ex.audio, noise, -5.0f + 15.0f * u(rng), rng);
  } else if (u(rng) < 0.25f) {
    // Digital silence around the words (a synthesised or edited recording).
  } else {
    const float floor =
        std::pow(10.0f, (-60.0f + 15.0f * u(rng)) / 20.0f) / std::max(kws::rms(noise), 1e-6f);
    const std::size_t off =
        noise.size() > kExampleSamples
            ? std::uniform_int_distribution<std::size_t>(0, noise.size() - kExampleSamples)(rng)
            : 0;
    for (std::size_t i = 0; i < kExampleSamples && off + i < noise.size(); ++i)
      ex.audio[i] += floor * noise[off + i];
  }
  for (float& v : ex.audio) v = std::clamp(v, -1.0f, 1.0f);
  return ex;
}

// The last 16 embeddings of each example, on `threads` threads (each example its own stream).
kws::HeadSet embed_examples(const std::vector<RawExample>& examples,
                            const std::shared_ptr<const kws::EmbeddingModels>& models,
                            int threads) {
  std::vector<std::vector<float>> inputs(examples.size());
  std::vector<std::thread> pool;
  for (int t = 0; t < threads; ++t) {
    pool.emplace_back([&, t] {
      kws::EmbeddingStream stream(models);
      std::vector<kws::Embedding> out;
      std::vector<float> scaled(kExampleSamples);
      for (std::size_t k = static_cast<std::size_t>(t); k < examples.size();
           k += static_cast<std::size_t>(threads)) {
        stream.reset();
        stream.skip_embeddings(kExampleHops - kws::kHeadEmbeddings);
        out.clear();
        for (std::size_t i = 0; i < kExampleSamples; ++i)
          scaled[i] = examples[k].audio[i] * 32768.0f;
        stream.push(scaled, out);
        auto& in = inputs[k];
        in.reserve(kws::kHeadInputs);
        for (std::size_t e = out.size() - kws::kHeadEmbeddings; e < out.size(); ++e) {
          in.insert(in.end(), out[e].begin(), out[e].end());
        }
      }
    });
  }
  for (auto& th : pool) th.join();
  kws::HeadSet set;
  for (std::size_t k = 0; k < examples.size(); ++k) set.add(inputs[k], examples[k].label);
  return set;
}

// Windows of 16 consecutive embeddings of a long keyword-free stream, every `stride`-th.
kws::HeadSet stream_negatives(const std::vector<float>& audio,
                              const std::shared_ptr<const kws::EmbeddingModels>& models,
                              int stride) {
  kws::EmbeddingStream stream(models);
  std::vector<kws::Embedding> out;
  std::vector<float> scaled(audio.size());
  for (std::size_t i = 0; i < audio.size(); ++i) scaled[i] = audio[i] * 32768.0f;
  stream.push(scaled, out);
  kws::HeadSet set;
  std::vector<float> in(kws::kHeadInputs);
  // Skip the first 10 embeddings (the mel buffer still holds its initial ones).
  for (std::size_t end = 10 + kws::kHeadEmbeddings; end <= out.size();
       end += static_cast<std::size_t>(stride)) {
    for (std::size_t e = 0; e < static_cast<std::size_t>(kws::kHeadEmbeddings); ++e) {
      std::copy(out[end - kws::kHeadEmbeddings + e].begin(),
                out[end - kws::kHeadEmbeddings + e].end(),
                in.begin() + static_cast<std::ptrdiff_t>(e * kws::kEmbeddingSize));
    }
    set.add(in, 0.0f);
  }
  return set;
}

struct MineResult {
  kws::HeadSet set;
  std::size_t windows = 0, over_half = 0;
};

// Every window of 16 embeddings of `audio` (keyword-free) that `head` scores >= floor.
MineResult mine_stream(const std::vector<float>& audio,
                       const std::shared_ptr<const kws::EmbeddingModels>& models,
                       const kws::EmbeddingHead& head, float floor) {
  kws::EmbeddingStream stream(models);
  std::vector<kws::Embedding> out;
  std::vector<float> scaled(audio.size());
  for (std::size_t i = 0; i < audio.size(); ++i) scaled[i] = audio[i] * 32768.0f;
  stream.push(scaled, out);
  MineResult r;
  std::vector<float> in(kws::kHeadInputs);
  for (std::size_t end = 10 + kws::kHeadEmbeddings; end <= out.size(); ++end) {
    for (std::size_t e = 0; e < static_cast<std::size_t>(kws::kHeadEmbeddings); ++e) {
      std::copy(out[end - kws::kHeadEmbeddings + e].begin(),
                out[end - kws::kHeadEmbeddings + e].end(),
                in.begin() + static_cast<std::ptrdiff_t>(e * kws::kEmbeddingSize));
    }
    ++r.windows;
    const float s = head.score(in);
    if (s >= floor) r.set.add(in, 0.0f);
    if (s >= 0.5f) ++r.over_half;
  }
  return r;
}

// A room (RT60 0.15..0.6 s, tail -12..0 dB) with probability `reverb_share`, then a cheap
// microphone (high-pass 80..400 Hz, low-pass 3..7.5 kHz) with probability `band_share`: what
// real recordings have and espeak-ng and flite have not.
void room_and_microphone(std::vector<float>& x, float reverb_share, float band_share,
                         std::mt19937_64& rng) {
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  if (u(rng) < reverb_share)
    x = kws::add_reverb(x, 0.15f + 0.45f * u(rng), -12.0f + 12.0f * u(rng), rng);
  if (u(rng) < band_share) kws::band_limit(x, 80.0f + 320.0f * u(rng), 3000.0f + 4500.0f * u(rng));
}

// What is done to real recordings before mining them: `variants` renditions of each (the first
// as recorded, the others with speed and pitch changed by 0.85..1.15, as another speaker's
// voice), each with the room and microphone of the synthetic examples at the same shares.
struct RealVariants {
  int variants = 1;
  float reverb_share = 0.0f, band_share = 0.0f, dropout_share = 0.0f;
};

// With probability `share`, one or two stretches of dropped audio (drop_out) in the last
// 1.3 s of `x`, where an example's keyword is. No random draw at share 0, so recipes without
// dropouts make the examples they always made.
void maybe_drop_out(std::vector<float>& x, float share, std::mt19937_64& rng) {
  if (share <= 0.0f) return;
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  if (u(rng) >= share) return;
  const std::size_t last = 20800;
  kws::drop_out(x, x.size() > last ? x.size() - last : 0, u(rng) < 0.3f ? 2 : 1, rng);
}

// Recordings one after another, 0.2..1.5 s apart, over background noise at an SNR in
// [-5, 10] dB (80 % of the time) or quiet, each at -18..-2 dBFS peak.
std::vector<float> real_stream(const std::vector<std::vector<float>>& recordings,
                               const std::vector<std::vector<float>>& noise_pool,
                               const RealVariants& how, std::mt19937_64& rng) {
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<float> audio;
  for (int variant = 0; variant < how.variants; ++variant) {
    for (const auto& recording : recordings) {
      std::vector<float> r = recording;
      if (variant > 0) {
        r = kws::change_speed_and_pitch(r, 0.85 + 0.3 * u(rng));
        room_and_microphone(r, how.reverb_share, how.band_share, rng);
        maybe_drop_out(r, how.dropout_share, rng);
      }
      std::vector<float> piece(static_cast<std::size_t>((0.2f + 1.3f * u(rng)) * 16000.0f), 0.0f);
      const float g = level_gain(r, -18.0f + 16.0f * u(rng));
      for (float v : r) piece.push_back(g * v);
      const auto& noise =
          noise_pool[std::uniform_int_distribution<std::size_t>(0, noise_pool.size() - 1)(rng)];
      if (u(rng) < 0.8f) kws::add_noise_at_snr(piece, noise, -5.0f + 15.0f * u(rng), rng);
      for (float& v : piece) v = std::clamp(v, -1.0f, 1.0f);
      audio.insert(audio.end(), piece.begin(), piece.end());
    }
  }
  return audio;
}

double head_seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

}  // namespace

std::vector<std::filesystem::path> sound_folder_files(const std::filesystem::path& folder,
                                                      std::size_t limit) {
  std::vector<std::filesystem::path> files;
  for (const auto& e : std::filesystem::directory_iterator(folder)) {
    const std::string ext = e.path().extension().string();
    if (e.is_regular_file() && (ext == ".wav" || ext == ".flac" || ext == ".ogg" || ext == ".WAV" ||
                                ext == ".FLAC" || ext == ".OGG")) {
      files.push_back(e.path());
    }
  }
  std::sort(files.begin(), files.end());
  if (limit > 0 && files.size() > limit) files.resize(limit);
  return files;
}

std::vector<float> read_recording(const std::filesystem::path& file) {
  marvin::audio::FlacDamage damage;
  const std::vector<std::int16_t> pcm = marvin::audio::read_speech_file(file, &damage);
  if (damage.errors > 0) {
    std::fprintf(stderr,
                 "%s: %d error(s) in the FLAC stream; %lld samples from sample %lld read as "
                 "silence, the rest kept\n",
                 file.c_str(), damage.errors, static_cast<long long>(damage.silenced_frames),
                 static_cast<long long>(damage.first_frame));
  }
  std::vector<float> x(pcm.size());
  for (std::size_t i = 0; i < pcm.size(); ++i) x[i] = static_cast<float>(pcm[i]) / 32768.0f;
  return kws::trim_silence(x);
}

std::vector<std::vector<float>> read_sound_folder(const std::filesystem::path& folder,
                                                  std::size_t limit) {
  std::vector<std::vector<float>> out;
  for (const auto& f : sound_folder_files(folder, limit)) out.push_back(read_recording(f));
  return out;
}

int train_embedding_main(int argc, char** argv) {
  CLI::App app{"Train the head of Marvin's embedding wake word (speech embedding + small MLP)"};
  std::string keyword = "marvin", out = "models/marvin-embedding-head.bin", noise_dir;
  std::vector<std::string> negative_dirs, spellings, near_miss_texts;
  std::uint64_t seed = 1;
  int positives = 1500, negatives = 1500, noise_examples = 200, real_copies = 1, threads = 2;
  int late_keywords = 1000, conversation_stride = 1, near_misses = 0;
  float keyword_tail = kDefaultTailS, keyword_after = 0.0f, negative_tail = kDefaultTailS,
        lead_in_share = 0.0f;
  double negative_minutes = 10.0;
  float threshold = 0.5f, refractory = 2.0f;
  int consecutive = 1;
  bool embedding = true;
  kws::HeadTrainOptions topt;
  std::vector<std::string> feature_files, mine_dirs;
  std::string save_features, mine_head_path;
  double mine_minutes = 0.0;
  float mine_floor = 0.1f;
  int mine_copies = 1;
  float flite_share = 0.0f, festival_share = 0.0f, reverb_share = 0.0f, band_share = 0.0f,
        dropout_share = 0.0f;
  int generated_voices = 0, real_variants = 1;
  float quiet_share = 0.2f;
  std::string voices_dir;
  bool wide_variants = false;
  topt.epochs = 30;
  app.add_flag("--embedding", embedding, "train the embedding wake word's head (this recipe)");
  app.add_option("--keyword", keyword, "what is said (lower case)")->capture_default_str();
  app.add_option("--out", out, "head file to write")->capture_default_str();
  app.add_option("--spelling", spellings,
                 "texts the synthesisers say for the keyword, one picked per example (default: "
                 "the keyword; e.g. \"alexa\" \"alexa?\" \"ah lexa\" for other stresses and "
                 "intonations)");
  app.add_option("--seed", seed)->capture_default_str();
  app.add_option("--positives", positives, "synthesised keyword examples")->capture_default_str();
  app.add_option("--negatives", negatives, "synthesised other-speech examples")
      ->capture_default_str();
  app.add_option("--negative-minutes", negative_minutes,
                 "minutes of keyword-free synthetic conversation, cut into windows")
      ->capture_default_str();
  app.add_option("--keyword-tail", keyword_tail,
                 "keyword examples end 0..S seconds before the window's end (how long after "
                 "the word the head must still say yes)")
      ->check(CLI::Range(0.0f, 0.6f))
      ->capture_default_str();
  app.add_option("--keyword-after", keyword_after,
                 "share of the keyword examples with other speech 0.1..0.3 s after the word "
                 "(\"marvin, what time is it\")")
      ->check(CLI::Range(0.0f, 1.0f))
      ->capture_default_str();
  app.add_option("--negative-tail", negative_tail,
                 "other words and the real recordings end 0..S seconds before the window's end "
                 "(--keyword-tail's value makes a word's distance from the end no cue)")
      ->check(CLI::Range(0.0f, 0.6f))
      ->capture_default_str();
  app.add_option("--late-keywords", late_keywords,
                 "negatives where the keyword ended 0.21..0.96 s longer ago than --keyword-tail "
                 "allows (0.45..1.2 s before the window's end at the default tail)")
      ->capture_default_str();
  app.add_option("--lead-ins", lead_in_share,
                 "share of the keyword examples, near misses and other-speech negatives said run "
                 "together after a lead-in word (\"hey marvin\", \"okay marvin\"; "
                 "lead_in_words())")
      ->check(CLI::Range(0.0f, 1.0f))
      ->capture_default_str();
  app.add_option("--near-misses", near_misses,
                 "negatives made exactly as the keyword examples are (context, tail, speech "
                 "after) with a word that sounds like the keyword in its place")
      ->check(CLI::Range(0, 1000000))
      ->capture_default_str();
  app.add_option("--near-miss", near_miss_texts,
                 "texts the --near-misses say, one picked per example (default: the words that "
                 "sound like \"marvin\" of confusable_words(); give your own for another keyword)");
  app.add_option("--conversation-stride", conversation_stride,
                 "take every N-th window of the conversation")
      ->capture_default_str();
  app.add_option("--negatives-dir", negative_dirs,
                 "folders of real recordings of other words (negatives)");
  app.add_option("--real-copies", real_copies, "examples made from each real recording")
      ->capture_default_str();
  app.add_option("--flite", flite_share,
                 "share of the synthesised utterances said by flite's voices instead of espeak-ng")
      ->capture_default_str();
  app.add_option(
         "--festival", festival_share,
         "share of the synthesised utterances said by festival's voices (festival_voices.h); "
         "--flite's share is taken of the rest")
      ->capture_default_str();
  app.add_option("--generated-voices", generated_voices,
                 "also speak with this many random espeak-ng variants of each training accent")
      ->capture_default_str();
  app.add_flag("--wide-variants", wide_variants,
               "draw the generated variants from the wider space the shipped training variants "
               "span (single formants moved, consonants, tilt, breath, echo, Klatt sources)");
  app.add_option("--voices-dir", voices_dir,
                 "with --generated-voices: where the private espeak-ng data goes (must not "
                 "exist; default: a temporary directory, removed at exit)");
  app.add_option("--quiet-share", quiet_share,
                 "share of the examples without background noise at [-5, 10] dB SNR: a faint "
                 "floor, a quarter of them digital silence")
      ->capture_default_str();
  app.add_option("--reverb", reverb_share,
                 "share of the synthesised examples heard in a room (RT60 0.15..0.6 s)")
      ->capture_default_str();
  app.add_option("--band-limit", band_share,
                 "share of the synthesised examples heard through a cheap microphone")
      ->capture_default_str();
  app.add_option("--dropouts", dropout_share,
                 "share of the synthesised examples (and of the faster/slower --mine-dir "
                 "renditions) with 50..300 ms of dropped audio (digital silence) in the word")
      ->capture_default_str();
  app.add_option("--noise-examples", noise_examples, "background-noise-only examples")
      ->capture_default_str();
  app.add_option("--noise", noise_dir, "folder of background-noise recordings (else generated)");
  app.add_option("--hidden", topt.hidden)->capture_default_str();
  app.add_option("--epochs", topt.epochs)->capture_default_str();
  app.add_option("--batch", topt.batch)->capture_default_str();
  app.add_option("--lr", topt.learning_rate)->capture_default_str();
  app.add_option("--positive-weight", topt.positive_weight)->capture_default_str();
  app.add_option("--threshold", threshold, "detection threshold stored in the head")
      ->capture_default_str();
  app.add_option("--refractory", refractory, "seconds without a second detection")
      ->capture_default_str();
  app.add_option("--consecutive", consecutive,
                 "scores in a row over the threshold for a detection (stored in the head)")
      ->check(CLI::Range(1, 10))
      ->capture_default_str();
  app.add_option("--threads", threads, "threads for the embeddings")->capture_default_str();
  app.add_option("--final-negative-weight", topt.final_negative_weight,
                 "negatives' loss weight in the last epoch (linear from 1)")
      ->capture_default_str();
  app.add_option("--features", feature_files,
                 "train from these feature files (--save-features) instead of synthesising");
  app.add_option("--save-features", save_features,
                 "write every example's 16 embeddings (after mining) to this file");
  app.add_option("--mine-head", mine_head_path,
                 "hard-negative mining: windows this head scores >= --mine-floor become negatives");
  app.add_option("--mine-minutes", mine_minutes,
                 "minutes of keyword-free synthetic conversation (training voices) to mine")
      ->capture_default_str();
  app.add_option("--mine-dir", mine_dirs, "folders of real recordings of other words to mine");
  app.add_option("--mine-variants", real_variants,
                 "renditions of each --mine-dir recording: as recorded, then faster or slower "
                 "(speed and pitch 0.85..1.15) with --reverb and --band-limit")
      ->capture_default_str();
  app.add_option("--mine-floor", mine_floor)->capture_default_str();
  app.add_option("--mine-copies", mine_copies)->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  try {
    const auto start = std::chrono::steady_clock::now();
    const auto models = kws::EmbeddingModels::load();
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::unique_ptr<kws::GeneratedVoiceSet> generated;
    if (generated_voices > 0)
      generated = std::make_unique<kws::GeneratedVoiceSet>(
          generated_voices, seed, voices_dir,
          wide_variants ? kws::VariantSpace::kWide : kws::VariantSpace::kNarrow);
    const std::vector<std::string> voices =
        generated ? generated->voices() : kws::training_voices();
    std::uniform_int_distribution<std::size_t> pick_voice(0, voices.size() - 1);
    std::uniform_int_distribution<int> rate(110, 230), pitch(20, 80);
    const auto noise_pool = kws::make_noise_pool(noise_dir, voices, rng);
    const auto& flite = kws::flite_voices();
    const auto& festival = kws::festival_voices();
    auto say = [&](const std::string& text) {
      std::vector<float> w;
      // Drawn only when asked for, so that recipes without festival draw as they did.
      if (festival_share > 0.0f && u(rng) < festival_share) {
        const std::string& v =
            festival[std::uniform_int_distribution<std::size_t>(0, festival.size() - 1)(rng)];
        w = kws::synthesize_festival(text, v, 0.8f + 0.45f * u(rng));
      } else if (flite_share > 0.0f && u(rng) < flite_share) {
        const std::string& v =
            flite[std::uniform_int_distribution<std::size_t>(0, flite.size() - 1)(rng)];
        const float f0 = v == "slt" ? 150.0f + 100.0f * u(rng) : 80.0f + 70.0f * u(rng);
        w = kws::synthesize_flite(text, v, 0.8f + 0.45f * u(rng), f0);
      } else {
        w = kws::synthesize(text, voices[pick_voice(rng)], rate(rng), pitch(rng));
      }
      if (u(rng) < 0.5f) w = kws::change_speed_and_pitch(w, 0.9 + 0.2 * u(rng));
      return w;
    };
    std::vector<std::string> others = kws::unknown_words();
    const auto& conf = kws::confusable_words();
    others.insert(others.end(), conf.begin(), conf.end());
    others.erase(std::remove(others.begin(), others.end(), keyword), others.end());
    auto other_text = [&]() -> std::string {
      const float r = u(rng);
      if (r < 0.4f)
        return others[std::uniform_int_distribution<std::size_t>(0, others.size() - 1)(rng)];
      if (r < 0.7f) return kws::varied_sentence(rng);
      return kws::random_sentence(rng);
    };
    // "hey marvin" in one breath: the lead-in runs into the word, unlike the context before
    // it, which is another utterance. Drawn only when asked for, so that recipes without
    // lead-ins draw as they did.
    const auto& leads = kws::lead_in_words();
    auto with_lead_in = [&](const std::string& text) {
      if (lead_in_share <= 0.0f || u(rng) >= lead_in_share) return text;
      return leads[std::uniform_int_distribution<std::size_t>(0, leads.size() - 1)(rng)] + " " +
             text;
    };
    kws::HeadSet all;
    std::size_t real = 0;
    for (const auto& f : feature_files) {
      all.append(kws::load_head_set(f));
      std::printf("%s: %zu cached examples\n", f.c_str(), all.size());
    }
    if (feature_files.empty()) {
      std::vector<RawExample> raw;
      if (spellings.empty()) spellings.push_back(keyword);
      auto say_keyword = [&] {
        return say(with_lead_in(
            spellings[std::uniform_int_distribution<std::size_t>(0, spellings.size() - 1)(rng)]));
      };
      for (int k = 0; k < positives; ++k) {
        const std::vector<float> w = say_keyword();
        const std::vector<float> ctx = u(rng) < 0.5f ? say(other_text()) : std::vector<float>{};
        // Drawn only when asked for, so that the default recipe's random draws stay as they were.
        const std::vector<float> after = keyword_after > 0.0f && u(rng) < keyword_after
                                             ? say(other_text())
                                             : std::vector<float>{};
        raw.push_back(
            place(w, &ctx, 1.0f, noise_pool, quiet_share, rng, 0.0f, keyword_tail, &after));
      }
      // The keyword heard too long ago (it ended 0.21..0.96 s before the positives' latest end),
      // alone or followed by a command: not a detection now, or a keyword followed by speech
      // fires twice.
      for (int k = 0; k < late_keywords; ++k) {
        const std::vector<float> w = say_keyword();
        const std::vector<float> after = u(rng) < 0.7f ? say(other_text()) : std::vector<float>{};
        raw.push_back(place(w, nullptr, 0.0f, noise_pool, quiet_share, rng,
                            keyword_tail + kLateKeywordFromS, keyword_tail + kLateKeywordToS,
                            &after));
      }
      // Minimal pairs: the keyword's examples with the keyword swapped for a word that sounds
      // like it ("marvellous weather", "Marvel comics"), so that the word itself, not where it
      // sits or what surrounds it, is what tells the two apart.
      if (near_miss_texts.empty()) near_miss_texts = conf;
      near_miss_texts.erase(std::remove(near_miss_texts.begin(), near_miss_texts.end(), keyword),
                            near_miss_texts.end());
      for (int k = 0; k < near_misses && !near_miss_texts.empty(); ++k) {
        const std::vector<float> w =
            say(with_lead_in(near_miss_texts[std::uniform_int_distribution<std::size_t>(
                0, near_miss_texts.size() - 1)(rng)]));
        const std::vector<float> ctx = u(rng) < 0.5f ? say(other_text()) : std::vector<float>{};
        const std::vector<float> after =
            u(rng) < keyword_after ? say(other_text()) : std::vector<float>{};
        raw.push_back(
            place(w, &ctx, 0.0f, noise_pool, quiet_share, rng, 0.0f, keyword_tail, &after));
      }
      std::printf(
          "%d keyword examples, %d late-keyword examples, %d near misses synthesised (%.0f s)\n",
          positives, late_keywords, near_misses, head_seconds_since(start));
      std::fflush(stdout);
      for (int k = 0; k < negatives; ++k) {
        std::vector<float> w = say(with_lead_in(other_text()));
        // A sentence ending, or a 0.5..1.5 s piece from its middle.
        if (w.size() > 24000 && u(rng) < 0.5f) {
          const auto n = static_cast<std::size_t>((0.5f + u(rng)) * 16000.0f);
          const auto at = std::uniform_int_distribution<std::size_t>(0, w.size() - n)(rng);
          w = std::vector<float>(w.begin() + static_cast<std::ptrdiff_t>(at),
                                 w.begin() + static_cast<std::ptrdiff_t>(at + n));
        }
        const std::vector<float> ctx = u(rng) < 0.5f ? say(other_text()) : std::vector<float>{};
        raw.push_back(place(w, &ctx, 0.0f, noise_pool, quiet_share, rng, 0.0f, negative_tail));
      }
      for (int k = 0; k < noise_examples; ++k)
        raw.push_back(place({}, nullptr, 0.0f, noise_pool, quiet_share, rng));
      std::printf("%d other-speech and %d noise examples synthesised (%.0f s)\n", negatives,
                  noise_examples, head_seconds_since(start));
      // The room, the microphone and dropped audio, for keyword and other speech alike (so
      // that none of them becomes a cue).
      for (RawExample& ex : raw) {
        room_and_microphone(ex.audio, reverb_share, band_share, rng);
        for (float& v : ex.audio) v = std::clamp(v, -1.0f, 1.0f);
        maybe_drop_out(ex.audio, dropout_share, rng);
      }
      for (const auto& dir : negative_dirs) {
        const auto recordings = read_sound_folder(dir, 0);
        for (int c = 0; c < real_copies; ++c) {
          for (const auto& r : recordings)
            raw.push_back(
                place(r, nullptr, 0.0f, noise_pool, quiet_share, rng, 0.0f, negative_tail));
        }
        real += recordings.size() * static_cast<std::size_t>(real_copies);
        std::printf("%zu real recordings from %s\n", recordings.size(), dir.c_str());
      }
      const std::vector<float> conversation =
          negative_minutes > 0.0
              ? kws::negative_speech(negative_minutes * 60.0, voices, noise_pool, rng)
              : std::vector<float>{};
      std::printf("%.1f min of keyword-free conversation synthesised (%.0f s)\n", negative_minutes,
                  head_seconds_since(start));
      std::fflush(stdout);
      all = embed_examples(raw, models, threads);
      if (!conversation.empty())
        all.append(stream_negatives(conversation, models, conversation_stride));
    }
    if (!mine_head_path.empty()) {
      // Hard negatives: every window of keyword-free speech the previous head scores at or
      // over the floor (openWakeWord's recipe), from synthetic conversation in training
      // voices and from real recordings of other words.
      const kws::EmbeddingHead mine_head = kws::load_head(mine_head_path);
      std::vector<std::pair<std::string, std::vector<float>>> streams;
      if (mine_minutes > 0.0) {
        streams.emplace_back("synthetic conversation",
                             kws::negative_speech(mine_minutes * 60.0, voices, noise_pool, rng));
      }
      for (const auto& dir : mine_dirs) {
        streams.emplace_back(
            dir, real_stream(read_sound_folder(dir, 0), noise_pool,
                             {real_variants, reverb_share, band_share, dropout_share}, rng));
      }
      for (const auto& [name, audio] : streams) {
        const MineResult m = mine_stream(audio, models, mine_head, mine_floor);
        for (int c = 0; c < mine_copies; ++c) all.append(m.set);
        std::printf("mined %s: %.1f min, %zu windows, %zu scored >= %.2f (%zu >= 0.5) (%.0f s)\n",
                    name.c_str(), static_cast<double>(audio.size()) / 16000.0 / 60.0, m.windows,
                    m.set.size(), static_cast<double>(mine_floor), m.over_half,
                    head_seconds_since(start));
        std::fflush(stdout);
      }
    }
    if (!save_features.empty()) {
      kws::save_head_set(save_features, all);
      std::printf("saved %zu examples to %s\n", all.size(), save_features.c_str());
    }
    std::size_t pos = 0;
    for (float l : all.labels) pos += l > 0.5f ? 1 : 0;
    std::printf("embedded: %zu examples, %zu positive, %zu negative (%zu real) (%.0f s)\n",
                all.size(), pos, all.size() - pos, real, head_seconds_since(start));
    // Split 9:1 by a seeded shuffle for the held-back accuracy.
    std::vector<std::size_t> order(all.size());
    for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
    std::shuffle(order.begin(), order.end(), rng);
    kws::HeadSet train, test;
    for (std::size_t k = 0; k < order.size(); ++k) {
      (k % 10 == 0 ? test : train)
          .add(std::span<const float>(all.inputs)
                   .subspan(order[k] * kws::kHeadInputs, kws::kHeadInputs),
               all.labels[order[k]]);
    }
    topt.seed = seed;
    int last_pct = -1;
    const bool tty = isatty(2) != 0;  // a log file gets one line per epoch
    topt.progress = [&](int epoch, std::size_t done, std::size_t total, double loss) {
      const int pct = static_cast<int>(100 * done / total);
      if ((pct == last_pct || !tty) && done != total) return;
      last_pct = pct;
      const int fill = pct * 30 / 100;
      std::fprintf(stderr, "\repoch %2d/%d [%.*s%*s] %3d%% loss %.4f", epoch + 1, topt.epochs, fill,
                   "##############################", 30 - fill, "", pct, loss);
      if (done == total) std::fprintf(stderr, "\n");
    };
    kws::EmbeddingHead head = kws::train_head(train, topt);
    head.keyword = keyword;
    head.threshold = threshold;
    head.refractory_seconds = refractory;
    head.consecutive = consecutive;
    for (float th : {0.5f, 0.8f, 0.9f, 0.95f}) {
      const kws::HeadAccuracy a = kws::head_accuracy(head, test, th);
      std::printf(
          "held-back tenth (%zu examples), threshold %.2f: keyword %.2f%% detected, others %.2f%% "
          "rejected\n",
          test.size(), static_cast<double>(th), 100.0 * a.positives, 100.0 * a.negatives);
    }
    kws::save_head(out, head);
    std::printf("wrote %s (%ju bytes, keyword \"%s\", threshold %.2f) in %.0f s\n", out.c_str(),
                static_cast<std::uintmax_t>(std::filesystem::file_size(out)), keyword.c_str(),
                static_cast<double>(threshold), head_seconds_since(start));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "marvin-kws-train: %s\n", e.what());
    return 1;
  }
  return 0;
}
