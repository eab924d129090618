#include "kws/training/dataset.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <thread>

#include "devices/audio/sound_buffer.h"
#include "devices/audio/sound_file.h"
#include "kws/training/augment.h"
#include "perception/kws/features.h"
#include "perception/speech_synthesizer.h"

namespace marvin::perception::kws {

namespace {

const char* const kTrainBases[] = {"en", "en-us", "en-gb-scotland", "en-gb-x-rp", "en-029"};
const char* const kTrainVariants[] = {
    "",         "m1",     "m2",    "m3",     "m4",      "m5",     "m6",     "f1",    "f2",
    "f3",       "f4",     "klatt", "klatt2", "klatt3",  "Alex",   "Andy",   "Annie", "Denis",
    "Gene",     "Jacky",  "Lee",   "Mario",  "Michael", "Storm",  "adam",   "anika", "belinda",
    "benjamin", "caleb",  "david", "edward", "grandma", "iven",   "john",   "linda", "norbert",
    "paul",     "quincy", "rob",   "robert", "steph",   "travis", "victor", "zac"};
const char* const kHeldoutBases[] = {"en-gb-x-gbclan", "en-gb-x-gbcwmd", "en-us"};
const char* const kHeldoutVariants[] = {"m7",     "f5",    "klatt4", "Alicia", "Andrea",  "Hugo",
                                        "Mike",   "aunty", "boris",  "ed",     "gustave", "max",
                                        "michel", "pablo", "shelby", "steph2", "iven2"};

std::uint64_t mix(std::uint64_t a, std::uint64_t b) {
  std::uint64_t x = a ^ (b + 0x9E3779B97F4A7C15ull + (a << 6) + (a >> 2));
  x ^= x >> 31;
  x *= 0xBF58476D1CE4E5B9ull;
  x ^= x >> 29;
  return x;
}

std::uint64_t hash_string(const std::string& s) {
  std::uint64_t h = 1469598103934665603ull;
  for (unsigned char c : s) h = (h ^ c) * 1099511628211ull;
  return h;
}

// 10:1:2 by a hash: 0 train, 1 test, 2 eval.
int split_of(std::uint64_t h) {
  const std::uint64_t r = h % 13;
  return r < 10 ? 0 : (r < 11 ? 1 : 2);
}

std::vector<float> crop_random(const std::vector<float>& x, std::size_t len, std::mt19937_64& rng) {
  if (x.size() <= len) {
    std::vector<float> out(x);
    out.resize(len, 0.0f);
    return out;
  }
  std::uniform_int_distribution<std::size_t> start(0, x.size() - len);
  const std::size_t s = start(rng);
  return std::vector<float>(x.begin() + static_cast<std::ptrdiff_t>(s),
                            x.begin() + static_cast<std::ptrdiff_t>(s + len));
}

float db(float v) { return std::pow(10.0f, v / 20.0f); }

void clip_to_unit(std::vector<float>& x) {
  for (float& v : x) v = std::clamp(v, -1.0f, 1.0f);
}

AudioClip quiet_clip(int label, const std::vector<std::vector<float>>& pool, std::mt19937_64& rng) {
  constexpr std::size_t len = kWindowSamples;
  AudioClip c;
  c.label = label;
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  if (label == static_cast<int>(KwsClass::silence)) {
    // Room silence: very quiet noise of some colour (and sometimes digital silence).
    const int colour = static_cast<int>(u(rng) * 3.0f) % 3;
    const float level = u(rng) < 0.1f ? 0.0f : db(-90.0f + 40.0f * u(rng));
    c.audio = make_noise(static_cast<NoiseColour>(colour), len, std::max(level, 1e-6f), rng);
    if (level == 0.0f) std::fill(c.audio.begin(), c.audio.end(), 0.0f);
  } else {
    const auto& src = pool[std::uniform_int_distribution<std::size_t>(0, pool.size() - 1)(rng)];
    c.audio = crop_random(src, len, rng);
    const float r = rms(c.audio);
    const float target = db(-45.0f + 37.0f * u(rng));
    if (r > 0.0f) {
      for (float& v : c.audio) v *= target / r;
    }
    clip_to_unit(c.audio);
  }
  return c;
}

}  // namespace

std::vector<std::string> training_voices() {
  std::vector<std::string> v;
  for (const char* b : kTrainBases) {
    for (const char* var : kTrainVariants) v.push_back(*var ? std::string(b) + "+" + var : b);
  }
  return v;
}

std::vector<std::string> training_accents() {
  return {std::begin(kTrainBases), std::end(kTrainBases)};
}

std::vector<std::string> heldout_voices() {
  std::vector<std::string> v;
  for (const char* b : kHeldoutBases) {
    for (const char* var : kHeldoutVariants) v.push_back(std::string(b) + "+" + var);
  }
  return v;
}

const std::vector<std::string>& unknown_words() {
  static const std::vector<std::string> words = {
      "yes",       "no",       "up",        "down",     "left",     "right",   "on",
      "off",       "stop",     "go",        "zero",     "one",      "two",     "three",
      "four",      "five",     "six",       "seven",    "eight",    "nine",    "bed",
      "bird",      "cat",      "dog",       "happy",    "house",    "sheila",  "tree",
      "wow",       "visual",   "forward",   "backward", "follow",   "learn",   "martin",
      "marvel",    "marble",   "margin",    "garden",   "carving",  "morning", "movie",
      "market",    "mountain", "raven",     "heaven",   "vitamin",  "seven",   "marathon",
      "kevin",     "mervyn",   "darwin",    "melvin",   "calvin",   "robot",   "hello",
      "okay",      "please",   "thank you", "water",    "medicine", "kitchen", "remind me",
      "what time", "turn on",  "call",      "help",     "lights",   "music",   "weather",
      "tomorrow",  "evening"};
  return words;
}

const std::vector<std::string>& sentences() {
  static const std::vector<std::string> s = {
      "remind me to take my pills at eight",
      "what time is it right now",
      "could you turn on the lights in the kitchen",
      "please call my daughter this evening",
      "the weather will be sunny tomorrow with a light breeze",
      "I would like a glass of water please",
      "where did I put my glasses this morning",
      "play some music in the living room",
      "the doctor said the appointment is on Tuesday",
      "my favourite program starts at nine o'clock",
      "can you help me find the remote control",
      "there is a package waiting at the front door",
      "set an alarm for half past six",
      "the garden looks lovely after the rain",
      "tell me a story about the sea",
      "how many steps did I walk today",
      "the market opens early on Saturdays",
      "we are having soup and bread for dinner",
      "open the curtains and let the light in",
      "my grandson is visiting next weekend",
      "read me the news headlines",
      "is the oven still switched on",
      "a marvellous view of the mountains from the window",
      "Martin and Kevin went to the marble quarry",
      "the heaven of a quiet afternoon with a good book",
      "please move a little bit closer to the table",
      "I think it is going to snow tonight",
      "turn the volume down a little",
      "the bus to the city leaves every twenty minutes",
      "do not forget to water the plants on the balcony"};
  return s;
}

std::vector<float> synthesize(const std::string& text, const std::string& voice, int rate_wpm,
                              int pitch) {
  SynthesisOptions o;
  o.voice = voice;
  o.rate_wpm = std::clamp(rate_wpm, 80, 450);
  o.pitch = std::clamp(pitch, 0, 100);
  SpeechSynthesizer synth(o);
  const std::vector<std::int16_t> pcm = synth.synthesize(text);
  return trim_silence(audio::to_float(pcm));
}

std::vector<std::vector<float>> make_noise_pool(const std::filesystem::path& noise_folder,
                                                const std::vector<std::string>& voices,
                                                std::mt19937_64& rng) {
  std::vector<std::vector<float>> pool;
  if (!noise_folder.empty()) {
    std::vector<std::filesystem::path> files;
    for (const auto& e : std::filesystem::directory_iterator(noise_folder)) {
      const std::string ext = e.path().extension().string();
      if (e.is_regular_file() && (ext == ".wav" || ext == ".flac" || ext == ".WAV")) {
        files.push_back(e.path());
      }
    }
    std::sort(files.begin(), files.end());
    for (const auto& f : files) pool.push_back(audio::to_float(audio::read_speech_file(f)));
    if (pool.empty()) {
      throw std::runtime_error("kws: noise folder " + noise_folder.string() +
                               " has no .wav or .flac files");
    }
    return pool;
  }
  constexpr std::size_t ten_s = 160000;
  pool.push_back(make_noise(NoiseColour::white, ten_s, 0.1f, rng));
  pool.push_back(make_noise(NoiseColour::pink, ten_s, 0.1f, rng));
  pool.push_back(make_noise(NoiseColour::brown, ten_s, 0.1f, rng));
  // Babble: four streams of sentences in different voices, summed.
  std::vector<float> babble(2 * ten_s, 0.0f);
  std::uniform_int_distribution<std::size_t> pick_voice(0, voices.size() - 1);
  std::uniform_int_distribution<std::size_t> pick_sentence(0, sentences().size() - 1);
  for (int stream = 0; stream < 4; ++stream) {
    std::size_t pos = 0;
    while (pos < babble.size()) {
      const std::vector<float> s =
          synthesize(sentences()[pick_sentence(rng)], voices[pick_voice(rng)], 170, 50);
      for (std::size_t i = 0; i < s.size() && pos < babble.size(); ++i) babble[pos++] += s[i];
      pos += 1600;
    }
  }
  const float r = rms(babble);
  for (float& v : babble) v *= 0.1f / std::max(r, 1e-6f);
  pool.push_back(std::move(babble));
  return pool;
}

const std::vector<std::string>& vocabulary() {
  static const std::vector<std::string> v = {
      "the",       "a",       "my",      "your",     "this",     "that",     "some",    "every",
      "please",    "now",     "today",   "tomorrow", "tonight",  "morning",  "evening", "later",
      "again",     "never",   "always",  "very",     "little",   "big",      "old",     "new",
      "warm",      "cold",    "quiet",   "loud",     "green",    "blue",     "red",     "kitchen",
      "garden",    "bedroom", "window",  "door",     "table",    "chair",    "sofa",    "lamp",
      "radio",     "phone",   "letter",  "doctor",   "nurse",    "daughter", "son",     "friend",
      "neighbour", "husband", "wife",    "cat",      "dog",      "bird",     "tea",     "coffee",
      "water",     "soup",    "bread",   "apple",    "pills",    "glasses",  "keys",    "book",
      "newspaper", "music",   "news",    "weather",  "rain",     "snow",     "sun",     "wind",
      "bus",       "car",     "train",   "shop",     "market",   "church",   "park",    "river",
      "mountain",  "is",      "are",     "was",      "will",     "can",      "could",   "would",
      "should",    "open",    "close",   "bring",    "take",     "call",     "turn",    "switch",
      "play",      "read",    "write",   "find",     "put",      "make",     "cook",    "walk",
      "sit",       "stand",   "sleep",   "wake",     "remember", "forget",   "remind",  "help",
      "tell",      "ask",     "look",    "listen",   "wait",     "stop",     "start",   "go",
      "come",      "leave",   "visit",   "and",      "or",       "but",      "with",    "without",
      "for",       "from",    "to",      "in",       "on",       "at",       "under",   "near",
      "after",     "before",  "because", "where",    "when",     "what",     "who",     "how",
      "why",       "one",     "two",     "three",    "four",     "five",     "six",     "seven",
      "eight",     "nine",    "ten",     "twenty",   "half",     "quarter",  "past",    "o'clock",
      "Monday",    "Tuesday", "Friday",  "Sunday",   "January",  "March",    "May",     "August",
      "marble",    "margin",  "market",  "martian",  "marvel",   "harvest",  "carving", "marching",
      "movie",     "arvo",    "vintage", "heaven",   "raven",    "seven",    "oven",    "muffin",
      "martin",    "melvin",  "kevin",   "gavin",    "darwin",   "garden",   "pardon",  "barton",
      "carbon",    "mountain"};
  return v;
}

std::string random_sentence(std::mt19937_64& rng) {
  const auto& v = vocabulary();
  std::uniform_int_distribution<std::size_t> pick(0, v.size() - 1);
  const int n = std::uniform_int_distribution<int>(3, 9)(rng);
  std::string s;
  for (int i = 0; i < n; ++i) s += (i ? " " : "") + v[pick(rng)];
  return s;
}

const std::vector<std::string>& confusable_words() {
  // No pair of entries may join into the keyword ("mar" + "vin" would), since varied
  // sentences put them next to each other.
  static const std::vector<std::string> w = {
      "marvel",    "marvellous", "marble",   "marbles",   "martin",   "margin",    "margarine",
      "martian",   "marching",   "market",   "marking",   "mark in",  "mark it",   "parking",
      "carving",   "carve in",   "starving", "starve in", "harvest",  "harvey",    "garden",
      "pardon",    "barton",     "carbon",   "moving",    "move in",  "far in",    "are in",
      "car in",    "bar in",     "jar in",   "star in",   "marvis",   "mervyn",    "melvin",
      "calvin",    "kevin",      "gavin",    "darwin",    "marlin",   "marvel in", "arming",
      "farming",   "warming",    "harming",  "morning",   "mourning", "marin",     "martini",
      "marmalade", "margaret",   "heaven",   "raven",     "seven",    "oven",      "vitamin",
      "win",       "been",       "bin",      "fin",       "in",       "far",       "car",
      "are"};
  return w;
}

const std::vector<std::string>& lead_in_words() {
  static const std::vector<std::string> w = {"hey",  "hi",        "hello",        "okay",
                                             "oh",   "ah",        "excuse me",    "please",
                                             "well", "thank you", "good morning", "so"};
  return w;
}

std::string varied_sentence(std::mt19937_64& rng) {
  const auto& v = vocabulary();
  const auto& c = confusable_words();
  std::uniform_int_distribution<std::size_t> pick_v(0, v.size() - 1), pick_c(0, c.size() - 1);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const int n = std::uniform_int_distribution<int>(3, 14)(rng);
  std::string s;
  for (int i = 0; i < n; ++i)
    s += (i ? " " : "") + (u(rng) < 0.2f ? c[pick_c(rng)] : v[pick_v(rng)]);
  return s;
}

std::vector<float> negative_speech(double seconds, const std::vector<std::string>& voices,
                                   const std::vector<std::vector<float>>& noise_pool,
                                   std::mt19937_64& rng) {
  const std::size_t total = static_cast<std::size_t>(std::max(0.0, seconds) * 16000.0);
  std::vector<float> out(total, 0.0f);
  if (total == 0 || voices.empty()) return out;
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::uniform_int_distribution<std::size_t> pick_voice(0, voices.size() - 1);
  if (!noise_pool.empty()) {
    for (std::size_t pos = 0; pos < total;) {
      const auto& n =
          noise_pool[std::uniform_int_distribution<std::size_t>(0, noise_pool.size() - 1)(rng)];
      const float level = db(-50.0f + 15.0f * u(rng)) / std::max(rms(n), 1e-6f);
      for (std::size_t i = 0; i < n.size() && pos < total; ++i) out[pos++] += level * n[i];
    }
  }
  const auto& sents = sentences();
  const auto& conf = confusable_words();
  for (std::size_t pos = static_cast<std::size_t>(1600 + 8000 * u(rng)); pos < total;) {
    const float kind = u(rng);
    std::string text;
    if (kind < 0.25f) {
      text = sents[std::uniform_int_distribution<std::size_t>(0, sents.size() - 1)(rng)];
    } else if (kind < 0.85f) {
      text = varied_sentence(rng);
    } else {
      const int n = std::uniform_int_distribution<int>(1, 4)(rng);
      for (int i = 0; i < n; ++i) {
        text += (i ? ", " : "") +
                conf[std::uniform_int_distribution<std::size_t>(0, conf.size() - 1)(rng)];
      }
    }
    const int rate = 110 + static_cast<int>(120 * u(rng));
    const int pitch = 20 + static_cast<int>(60 * u(rng));
    const std::vector<float> s = synthesize(text, voices[pick_voice(rng)], rate, pitch);
    float peak = 0.0f;
    for (float v : s) peak = std::max(peak, std::fabs(v));
    const float g = db(-18.0f + 14.0f * u(rng)) / std::max(peak, 1e-6f);
    for (std::size_t i = 0; i < s.size() && pos + i < total; ++i) out[pos + i] += g * s[i];
    pos += s.size() + static_cast<std::size_t>(1600 + 22400 * u(rng));
  }
  clip_to_unit(out);
  return out;
}

TrainingSet stream_windows(const std::vector<float>& audio, int hop_frames, int label) {
  TrainingSet set;
  std::vector<std::int16_t> pcm(audio.size());
  audio::float_to_pcm16(audio, pcm);
  LogMelExtractor extractor;
  std::vector<float> frames;
  extractor.push(std::span<const std::int16_t>(pcm), [&](std::span<const float> bins) {
    frames.insert(frames.end(), bins.begin(), bins.end());
  });
  const std::size_t n_frames = frames.size() / kBins;
  const std::size_t hop = static_cast<std::size_t>(std::max(1, hop_frames));
  const Normalisation identity{};
  for (std::size_t end = kWindowFrames; end <= n_frames; end += hop) {
    const std::size_t at = set.inputs.size();
    set.inputs.resize(at + kInputSize);
    window_to_input(
        std::span<const float>(frames).subspan((end - kWindowFrames) * kBins,
                                               static_cast<std::size_t>(kWindowFrames) * kBins),
        identity, std::span<float>(set.inputs).subspan(at, kInputSize));
    set.labels.push_back(label);
  }
  return set;
}

AudioClip place_and_augment(const std::vector<float>& word, int label,
                            const std::vector<std::vector<float>>& noise_pool, bool augment,
                            std::mt19937_64& rng, const std::vector<std::vector<float>>* context,
                            float context_probability) {
  constexpr std::size_t len = kWindowSamples;
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<float> w = word;
  if (augment) {
    const float pick = u(rng);
    if (pick < 0.2f) {
      w = shift_pitch(w, -3.0 + 6.0 * u(rng));
    } else if (pick < 0.4f) {
      w = time_stretch(w, 0.85 + 0.3 * u(rng));
    } else if (pick < 0.6f) {
      w = change_speed_and_pitch(w, 0.9 + 0.2 * u(rng));
    }
    if (u(rng) < 0.1f) {
      const bool keep_harmonic = u(rng) < 0.5f;
      const float other = 0.2f + 0.4f * u(rng);
      w = hpss_remix(w, keep_harmonic ? 1.0f : other, keep_harmonic ? other : 1.0f);
    }
  }
  // Normalise the word's peak, then a gain.
  float peak = 0.0f;
  for (float v : w) peak = std::max(peak, std::fabs(v));
  const float gain = (augment ? db(-20.0f + 18.0f * u(rng)) : db(-6.0f)) / std::max(peak, 1e-6f);
  for (float& v : w) v *= gain;
  AudioClip c;
  c.label = label;
  // Quiet floor, so no frame is digital silence.
  c.audio = make_noise(NoiseColour::white, len, db(-75.0f), rng);
  // Random time shift: anywhere the word fits (a longer word is cut around its middle).
  if (w.size() > len) {
    const std::size_t cut = (w.size() - len) / 2;
    w = std::vector<float>(w.begin() + static_cast<std::ptrdiff_t>(cut),
                           w.begin() + static_cast<std::ptrdiff_t>(cut + len));
  }
  const std::size_t offset = std::uniform_int_distribution<std::size_t>(0, len - w.size())(rng);
  for (std::size_t i = 0; i < w.size(); ++i) c.audio[offset + i] += w[i];
  if (context && !context->empty() && context_probability > 0.0f && u(rng) < context_probability) {
    // Speech before the word (the end of an utterance) and after it (a beginning), each
    // 50..300 ms away, at -6..+3 dB relative to the word.
    std::uniform_int_distribution<std::size_t> pick(0, context->size() - 1);
    const std::size_t gap_before = 800 + static_cast<std::size_t>(4000.0f * u(rng));
    const std::size_t gap_after = 800 + static_cast<std::size_t>(4000.0f * u(rng));
    const float rel = db(-6.0f + 9.0f * u(rng));
    float wpeak = 0.0f;
    for (float v : w) wpeak = std::max(wpeak, std::fabs(v));
    auto put = [&](const std::vector<float>& src, std::size_t dst_begin, std::size_t dst_end,
                   bool tail) {
      if (dst_end <= dst_begin + 1600 || src.empty()) return;
      float sp = 0.0f;
      for (float v : src) sp = std::max(sp, std::fabs(v));
      const float g = rel * wpeak / std::max(sp, 1e-6f);
      const std::size_t n = std::min(src.size(), dst_end - dst_begin);
      const std::size_t src_begin = tail ? src.size() - n : 0;
      const std::size_t dst = tail ? dst_end - n : dst_begin;
      for (std::size_t i = 0; i < n; ++i) c.audio[dst + i] += g * src[src_begin + i];
    };
    if (offset > gap_before) put((*context)[pick(rng)], 0, offset - gap_before, true);
    put((*context)[pick(rng)], std::min(len, offset + w.size() + gap_after), len, false);
  }
  if (augment) {
    const float pick = u(rng);
    if (pick < 0.6f && !noise_pool.empty()) {
      const auto& n =
          noise_pool[std::uniform_int_distribution<std::size_t>(0, noise_pool.size() - 1)(rng)];
      add_noise_at_snr(c.audio, n, -5.0f + 15.0f * u(rng), rng);
    } else if (pick < 0.8f) {
      const std::vector<float> white = make_noise(NoiseColour::white, len, 0.1f, rng);
      add_noise_at_snr(c.audio, white, 5.0f + 25.0f * u(rng), rng);
    }
  }
  clip_to_unit(c.audio);
  return c;
}

SplitClips synthesize_dataset(const DatasetOptions& options) {
  const std::vector<std::string> voices =
      options.voices.empty() ? training_voices() : options.voices;
  auto log = [&](const std::string& s) {
    if (options.log) options.log(s);
  };
  SplitClips out;
  std::mt19937_64 rng(options.seed);
  log("noise pool");
  out.noise_pool = make_noise_pool(options.noise_folder, voices, rng);
  std::uniform_int_distribution<int> rate(110, 230), pitch(20, 80);
  std::uniform_int_distribution<std::size_t> pick_voice(0, voices.size() - 1);
  std::vector<std::vector<float>> context;
  if (options.context_probability > 0.0f) {
    log("context speech");
    for (int i = 0; i < 200; ++i) {
      const std::string text = options.random_sentences && i % 2 == 1
                                   ? random_sentence(rng)
                                   : sentences()[static_cast<std::size_t>(i) % sentences().size()];
      context.push_back(synthesize(text, voices[pick_voice(rng)], rate(rng), pitch(rng)));
    }
  }
  auto add = [&](const std::vector<float>& word, int label, std::uint64_t item, bool with_context) {
    const int split = split_of(mix(options.seed, item));
    std::vector<AudioClip>& dst = split == 0 ? out.train : (split == 1 ? out.test : out.eval);
    const int copies = split == 0 ? std::max(1, options.augmented_copies) : 1;
    for (int k = 0; k < copies; ++k) {
      dst.push_back(place_and_augment(word, label, out.noise_pool, true, rng,
                                      with_context ? &context : nullptr,
                                      options.context_probability));
    }
  };
  const std::string cap =
      options.keyword.empty()
          ? options.keyword
          : static_cast<char>(std::toupper(static_cast<unsigned char>(options.keyword[0]))) +
                options.keyword.substr(1);
  for (int i = 0; i < options.keyword_clips; ++i) {
    if (i % 100 == 0)
      log("keyword " + std::to_string(i) + "/" + std::to_string(options.keyword_clips));
    const std::string& text = (i % 3 == 0) ? cap + "!" : (i % 3 == 1 ? options.keyword : cap + ".");
    std::vector<float> w = synthesize(text, voices[pick_voice(rng)], rate(rng), pitch(rng));
    if (w.empty()) continue;
    add(w, static_cast<int>(KwsClass::keyword), static_cast<std::uint64_t>(i), true);
  }
  const auto& words = unknown_words();
  const auto& sents = sentences();
  std::uniform_int_distribution<std::size_t> pick_word(0, words.size() - 1),
      pick_sent(0, sents.size() - 1);
  for (int i = 0; i < options.unknown_clips; ++i) {
    if (i % 100 == 0)
      log("unknown " + std::to_string(i) + "/" + std::to_string(options.unknown_clips));
    std::vector<float> w;
    const bool single_word = i % 2 == 0;
    if (single_word) {
      w = synthesize(words[pick_word(rng)], voices[pick_voice(rng)], rate(rng), pitch(rng));
    } else {
      if (options.random_sentences && i % 4 == 3) {
        const std::string text = random_sentence(rng);
        w = crop_random(synthesize(text, voices[pick_voice(rng)], rate(rng), pitch(rng)),
                        kWindowSamples - std::uniform_int_distribution<std::size_t>(0, 4000)(rng),
                        rng);
      } else {
        w = crop_random(
            synthesize(sents[pick_sent(rng)], voices[pick_voice(rng)], rate(rng), pitch(rng)),
            kWindowSamples - std::uniform_int_distribution<std::size_t>(0, 4000)(rng), rng);
      }
      w = trim_silence(w, 50.0f);
    }
    if (w.empty()) continue;
    add(w, static_cast<int>(KwsClass::unknown), 1'000'000u + static_cast<std::uint64_t>(i),
        single_word);
  }
  log("silence and noise");
  for (int i = 0; i < options.silence_clips + options.noise_clips; ++i) {
    const int label = i < options.silence_clips ? static_cast<int>(KwsClass::silence)
                                                : static_cast<int>(KwsClass::noise);
    const int split = split_of(mix(options.seed, 2'000'000u + static_cast<std::uint64_t>(i)));
    std::vector<AudioClip>& dst = split == 0 ? out.train : (split == 1 ? out.test : out.eval);
    const int copies = split == 0 ? std::max(1, options.augmented_copies) : 1;
    for (int k = 0; k < copies; ++k) dst.push_back(quiet_clip(label, out.noise_pool, rng));
  }
  return out;
}

SplitClips read_speech_commands(const std::filesystem::path& folder, const DatasetOptions& options,
                                int max_per_word) {
  if (!std::filesystem::is_directory(folder)) {
    throw std::runtime_error("kws: dataset folder " + folder.string() + " does not exist");
  }
  SplitClips out;
  std::mt19937_64 rng(options.seed);
  const auto noise_dir = folder / "_background_noise_";
  out.noise_pool = make_noise_pool(
      !options.noise_folder.empty()
          ? options.noise_folder
          : (std::filesystem::is_directory(noise_dir) ? noise_dir : std::filesystem::path()),
      training_voices(), rng);
  std::vector<std::filesystem::path> words;
  for (const auto& e : std::filesystem::directory_iterator(folder)) {
    const std::string name = e.path().filename().string();
    if (e.is_directory() && !name.empty() && name[0] != '_' && name[0] != '.')
      words.push_back(e.path());
  }
  std::sort(words.begin(), words.end());
  bool have_keyword = false;
  for (const auto& dir : words) {
    const std::string word = dir.filename().string();
    const int label = word == options.keyword ? static_cast<int>(KwsClass::keyword)
                                              : static_cast<int>(KwsClass::unknown);
    have_keyword = have_keyword || label == 0;
    std::vector<std::filesystem::path> files;
    for (const auto& e : std::filesystem::directory_iterator(dir)) {
      if (e.is_regular_file() && e.path().extension() == ".wav") files.push_back(e.path());
    }
    std::sort(files.begin(), files.end());
    if (max_per_word > 0 && files.size() > static_cast<std::size_t>(max_per_word)) {
      files.resize(static_cast<std::size_t>(max_per_word));
    }
    if (options.log) options.log(word + ": " + std::to_string(files.size()) + " files");
    for (const auto& f : files) {
      const std::vector<float> w = trim_silence(audio::to_float(audio::read_speech_file(f)), 50.0f);
      if (w.empty()) continue;
      const std::string key = word + "/" + f.filename().string();
      const int split = split_of(mix(options.seed, hash_string(key)));
      std::vector<AudioClip>& dst = split == 0 ? out.train : (split == 1 ? out.test : out.eval);
      const int copies = split == 0 ? std::max(1, options.augmented_copies) : 1;
      for (int k = 0; k < copies; ++k)
        dst.push_back(place_and_augment(w, label, out.noise_pool, true, rng));
    }
  }
  if (!have_keyword) {
    throw std::runtime_error("kws: dataset folder " + folder.string() + " has no folder named \"" +
                             options.keyword + "\" (the keyword's recordings)");
  }
  // Silence and noise: a sixth of the word clips each, cut from the noise pool.
  const std::size_t words_total = out.train.size() + out.test.size() + out.eval.size();
  const int extra = static_cast<int>(words_total / 6);
  for (int i = 0; i < 2 * extra; ++i) {
    const int label =
        i < extra ? static_cast<int>(KwsClass::silence) : static_cast<int>(KwsClass::noise);
    const int split = split_of(mix(options.seed, 2'000'000u + static_cast<std::uint64_t>(i)));
    (split == 0 ? out.train : (split == 1 ? out.test : out.eval))
        .push_back(quiet_clip(label, out.noise_pool, rng));
  }
  return out;
}

TrainingSet clips_to_inputs(const std::vector<AudioClip>& clips, int threads) {
  TrainingSet set;
  set.labels.resize(clips.size());
  set.inputs.resize(clips.size() * kInputSize);
  const int n = std::max(1, threads);
  auto work = [&](int t) {
    LogMelExtractor extractor;
    std::vector<float> frames;
    const Normalisation identity{};
    std::vector<std::int16_t> pcm(static_cast<std::size_t>(kWindowSamples));
    for (std::size_t i = static_cast<std::size_t>(t); i < clips.size();
         i += static_cast<std::size_t>(n)) {
      const auto& a = clips[i].audio;
      pcm.assign(a.size(), 0);
      audio::float_to_pcm16(a, pcm);
      clip_frames(extractor, pcm, frames);
      window_to_input(frames, identity,
                      std::span<float>(set.inputs).subspan(i * kInputSize, kInputSize));
      set.labels[i] = clips[i].label;
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < n; ++t) pool.emplace_back(work, t);
  work(0);
  for (auto& th : pool) th.join();
  return set;
}

Normalisation compute_normalisation(const TrainingSet& set) {
  Normalisation norm;
  if (set.size() == 0) return norm;
  std::array<double, kBins> sum{};
  double sq = 0.0;
  const double count = static_cast<double>(set.size()) * kInputFrames;
  for (std::size_t i = 0; i < set.size(); ++i) {
    auto x = set.input(i);
    for (int t = 0; t < kInputFrames; ++t) {
      for (int b = 0; b < kBins; ++b)
        sum[static_cast<std::size_t>(b)] += x[static_cast<std::size_t>(t * kBins + b)];
    }
  }
  for (int b = 0; b < kBins; ++b)
    norm.mean[static_cast<std::size_t>(b)] =
        static_cast<float>(sum[static_cast<std::size_t>(b)] / count);
  for (std::size_t i = 0; i < set.size(); ++i) {
    auto x = set.input(i);
    for (int t = 0; t < kInputFrames; ++t) {
      for (int b = 0; b < kBins; ++b) {
        const double d =
            x[static_cast<std::size_t>(t * kBins + b)] - norm.mean[static_cast<std::size_t>(b)];
        sq += d * d;
      }
    }
  }
  const double sd = std::sqrt(sq / (count * kBins));
  norm.inv_std = static_cast<float>(1.0 / std::max(sd, 1e-6));
  return norm;
}

void normalise(TrainingSet& set, const Normalisation& norm) {
  for (std::size_t i = 0; i < set.size(); ++i) {
    float* x = set.inputs.data() + i * kInputSize;
    for (int t = 0; t < kInputFrames; ++t) {
      for (int b = 0; b < kBins; ++b) {
        float& v = x[t * kBins + b];
        v = (v - norm.mean[static_cast<std::size_t>(b)]) * norm.inv_std;
      }
    }
  }
}

}  // namespace marvin::perception::kws
