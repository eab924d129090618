// Training data for the keyword spotter: a Speech Commands-style folder, or speech made with
// espeak-ng when there are no recordings; augmentation; the 10:1:2 train/test/eval split;
// and the step from audio clips to network inputs.
//
// Every clip is one window (15600 samples at 16 kHz, about 1 s) labelled keyword, unknown,
// silence or noise. Everything random is drawn from generators seeded by DatasetOptions::seed,
// so the same options give the same data.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "kws/training/trainer.h"

namespace marvin::perception::kws {

struct AudioClip {
  std::vector<float> audio;  // kWindowSamples samples
  int label = 0;             // KwsClass
};

struct DatasetOptions {
  std::uint64_t seed = 1;
  std::string keyword = "marvin";
  // Synthesised set sizes (source clips before the split).
  int keyword_clips = 1500;
  int unknown_clips = 1500;  // half single words, half 1 s pieces of sentences
  int silence_clips = 300;
  int noise_clips = 500;
  int augmented_copies = 2;                     // training examples made from each training clip
  std::vector<std::string> voices;              // espeak-ng voices; empty = training_voices()
  std::filesystem::path noise_folder;           // WAVs used as background noise (else generated)
  std::function<void(const std::string&)> log;  // progress lines (may be empty)
  // Probability that a word (keyword or other) gets speech right before and after it in its
  // window, as in "marvin, what time is it" (0: isolated words only).
  float context_probability = 0.0f;
  // Half of the sentence pieces come from random word sequences over vocabulary() instead of
  // sentences(), for more lexical variety.
  bool random_sentences = false;
};

// espeak-ng voice names ("base+variant"); the two lists share no variant and no voice.
std::vector<std::string> training_voices();
// The language/accent voices training_voices() combines with its variants ("en", "en-us", ...).
std::vector<std::string> training_accents();
std::vector<std::string> heldout_voices();
// Words that are not the keyword (Speech Commands' words and some that sound like "marvin"),
// and sentences without the keyword.
const std::vector<std::string>& unknown_words();
const std::vector<std::string>& sentences();
// Everyday words random sentences are made of (no keyword).
const std::vector<std::string>& vocabulary();
std::string random_sentence(std::mt19937_64& rng);
// Words that sound like the keyword or make it across a word boundary ("marvel", "carving",
// "far in"); never the keyword itself.
const std::vector<std::string>& confusable_words();
// What people say run together before a name they call ("hey", "okay", "excuse me"): the
// lead-ins of marvin-kws-train --lead-ins.
const std::vector<std::string>& lead_in_words();
// 3..14 words: mostly vocabulary(), about one in five from confusable_words(), so a 1 s
// window of it is often a keyword-like piece in the middle of other speech.
std::string varied_sentence(std::mt19937_64& rng);

// `seconds` of speech without the keyword, as a microphone hears a conversation: utterances
// (sentences(), varied_sentence(), runs of confusable words) in random `voices`, rates and
// pitches, at -18..-4 dB peak, 0.1..1.5 s apart, over continuous background from
// `noise_pool` at -50..-35 dBFS. Used for hard-negative mining (training voices only).
std::vector<float> negative_speech(double seconds, const std::vector<std::string>& voices,
                                   const std::vector<std::vector<float>>& noise_pool,
                                   std::mt19937_64& rng);

// The unnormalised network inputs of the windows a streaming spotter sees on `audio` (one
// every `hop_frames` log-mel frames, as KeywordSpotter), all labelled `label`.
TrainingSet stream_windows(const std::vector<float>& audio, int hop_frames, int label);

// Speech from espeak-ng, 16 kHz float, leading and trailing silence trimmed.
std::vector<float> synthesize(const std::string& text, const std::string& voice, int rate_wpm,
                              int pitch);

// A background noise pool: `noise_folder`'s WAV/FLAC files if given, else white, pink and
// brown noise and babble (several synthetic voices talking at once).
std::vector<std::vector<float>> make_noise_pool(const std::filesystem::path& noise_folder,
                                                const std::vector<std::string>& voices,
                                                std::mt19937_64& rng);

// The source clips of each split (10:1:2) before augmentation.
struct SplitClips {
  std::vector<AudioClip> train, test, eval;
  std::vector<std::vector<float>> noise_pool;
};

// Synthesised dataset (no recordings).
SplitClips synthesize_dataset(const DatasetOptions& options);

// Speech Commands layout: <folder>/<word>/*.wav, the keyword's folder gives keyword clips,
// every other word unknown clips, <folder>/_background_noise_ the noise pool (silence and
// noise clips are cut from it). At most `max_per_word` files per word (0 = all). Files are
// assigned to splits by a hash of their name, so adding files does not move the others.
SplitClips read_speech_commands(const std::filesystem::path& folder, const DatasetOptions& options,
                                int max_per_word);

// Puts a word into a window at a random position over a quiet floor; applies the augmentations
// (pitch, speed, pitch+speed, harmonic-percussive remix, gain, white noise, background noise
// at an SNR drawn from [-5, 10] dB) each with its own probability.
// With `context` and a positive `context_probability`, that often the rest of the window
// before and after the word is filled with other speech (ends of `context` utterances).
AudioClip place_and_augment(const std::vector<float>& word, int label,
                            const std::vector<std::vector<float>>& noise_pool, bool augment,
                            std::mt19937_64& rng,
                            const std::vector<std::vector<float>>* context = nullptr,
                            float context_probability = 0.0f);

// Clips -> network inputs, unnormalised (Normalisation{}), on `threads` threads.
TrainingSet clips_to_inputs(const std::vector<AudioClip>& clips, int threads);

// Per-bin mean and global inverse standard deviation of a set's (unnormalised) inputs.
Normalisation compute_normalisation(const TrainingSet& set);
// Applies a normalisation to unnormalised inputs in place.
void normalise(TrainingSet& set, const Normalisation& norm);

}  // namespace marvin::perception::kws
