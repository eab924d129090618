// marvin-kws-eval: evaluates a keyword-spotting model on speech from voices the training
// never used (tools/kws/README.md has the commands).
//
// 1. Clips: keyword / unknown / silence / noise windows made with the held-out voices
//    (heldout_voices()), per-class accuracy of the int8 model (and the float model if given).
// 2. Streaming: a long track of held-out sentences (some not in the training sentences),
//    pauses and background noise with the keyword inserted at known places, some followed by
//    a command. The neural detector runs over it once, recording each window's posterior;
//    the decision (smoothing, threshold, refractory period) is replayed at each threshold.
//    pocketsphinx keyphrase spotting runs over the same audio at several sensitivities.
//    A detection counts as a hit when it ends between the keyword's start and 1.25 s after
//    its end; every other detection (including a second one for the same keyword) is a false
//    accept.
// 3. Real recordings (--positives, --negatives): a track of them instead of 1 and 2, the cnn
//    spotter, the embedding head (if given) and pocketsphinx side by side, scored the same way.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <future>
#include <map>
#include <random>
#include <stdexcept>

#include "devices/audio/sound_buffer.h"
#include "devices/audio/sound_file.h"
#include "kws/training/augment.h"
#include "kws/training/dataset.h"
#include "perception/kws/embedding_wake_word.h"
#include "perception/kws/features.h"
#include "perception/kws/keyword_spotter.h"
#include "perception/kws/neural_wake_word.h"
#include "perception/pocketsphinx_wake_word.h"
#include "train_embedding.h"

namespace kws = marvin::perception::kws;
namespace perception = marvin::perception;

namespace {

using Clock = std::chrono::steady_clock;

// Sentences the training never saw (the training ones are used as well).
const std::vector<std::string>& eval_sentences() {
  static const std::vector<std::string> s = {"the kettle has boiled so we can make some tea",
                                             "my knees hurt a little when it is cold outside",
                                             "could you bring me the blue blanket from the bedroom",
                                             "the postman came early today with two letters",
                                             "I need to call the pharmacy before they close",
                                             "the cat is sleeping on the windowsill again",
                                             "marvellous weather for a walk along the river",
                                             "Marvel comics and a martini by the fireplace",
                                             "Kevin will drive us to the hospital on Monday",
                                             "she is learning to play the violin at seventy",
                                             "remind me to buy carrots potatoes and marmalade",
                                             "the carving on the old oak door is beautiful",
                                             "how far is it to the nearest supermarket",
                                             "switch off the radio in the garden shed",
                                             "the movie starts at a quarter to eight",
                                             "we should invite Mervyn and Margaret for lunch",
                                             "the heating makes a strange noise at night",
                                             "turn left at the church and then go straight on",
                                             "a glass of orange juice and a slice of toast",
                                             "the grandchildren are coming for the holidays"};
  return s;
}

// What was said where: the keyword or a sentence, in which voice.
struct Segment {
  std::int64_t begin, end;  // samples
  std::string text, voice;
};

struct Track {
  std::vector<float> audio;
  std::vector<Segment> keywords;   // in time order
  std::vector<Segment> sentences;  // the other speech, in time order
};

float db(float v) { return std::pow(10.0f, v / 20.0f); }

void mix_in(std::vector<float>& dst, std::size_t at, const std::vector<float>& src, float peak_db) {
  float peak = 0.0f;
  for (float v : src) peak = std::max(peak, std::fabs(v));
  const float g = db(peak_db) / std::max(peak, 1e-6f);
  for (std::size_t i = 0; i < src.size() && at + i < dst.size(); ++i) dst[at + i] += g * src[i];
}

Track build_track(double minutes, int keywords, const std::string& keyword,
                  const std::vector<std::string>& voices,
                  const std::vector<std::vector<float>>& noise_pool, std::mt19937_64& rng) {
  Track t;
  const std::size_t total = static_cast<std::size_t>(minutes * 60.0 * 16000.0);
  t.audio.assign(total, 0.0f);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::uniform_int_distribution<std::size_t> pick_voice(0, voices.size() - 1);
  // Continuous background: the noise pool's streams one after another at -50..-35 dBFS.
  for (std::size_t pos = 0; pos < total;) {
    const auto& n =
        noise_pool[std::uniform_int_distribution<std::size_t>(0, noise_pool.size() - 1)(rng)];
    const float level = db(-50.0f + 15.0f * u(rng)) / std::max(kws::rms(n), 1e-6f);
    for (std::size_t i = 0; i < n.size() && pos < total; ++i) t.audio[pos++] += level * n[i];
  }
  std::vector<std::string> sents = kws::sentences();
  sents.insert(sents.end(), eval_sentences().begin(), eval_sentences().end());
  std::uniform_int_distribution<std::size_t> pick_sent(0, sents.size() - 1);
  const std::string cap =
      static_cast<char>(std::toupper(static_cast<unsigned char>(keyword[0]))) + keyword.substr(1);
  const double spacing = static_cast<double>(total) / std::max(1, keywords);
  int placed = 0;
  std::size_t pos = 8000;
  while (pos < total) {
    const double next_kw = (placed + 0.3 + 0.4 * u(rng)) * spacing;
    const int rate = 120 + static_cast<int>(100 * u(rng));
    const int pitch = 25 + static_cast<int>(50 * u(rng));
    const std::string& voice = voices[pick_voice(rng)];
    const float level = -18.0f + 14.0f * u(rng);
    if (placed < keywords && static_cast<double>(pos) >= next_kw) {
      const std::vector<float> kw =
          kws::synthesize(u(rng) < 0.5f ? cap : keyword, voice, rate, pitch);
      if (pos + kw.size() >= total) break;
      mix_in(t.audio, pos, kw, level);
      t.keywords.push_back({static_cast<std::int64_t>(pos),
                            static_cast<std::int64_t>(pos + kw.size()), keyword, voice});
      pos += kw.size() + static_cast<std::size_t>(2400 + 4000 * u(rng));
      ++placed;
      if (u(rng) < 0.6f) {  // "Marvin, <command>"
        const std::string& text = sents[pick_sent(rng)];
        const std::vector<float> cmd = kws::synthesize(text, voice, rate, pitch);
        mix_in(t.audio, pos, cmd, level);
        t.sentences.push_back({static_cast<std::int64_t>(pos),
                               static_cast<std::int64_t>(pos + cmd.size()), text, voice});
        pos += cmd.size();
      }
    } else {
      const std::string& text = sents[pick_sent(rng)];
      const std::vector<float> s = kws::synthesize(text, voice, rate, pitch);
      mix_in(t.audio, pos, s, level);
      t.sentences.push_back(
          {static_cast<std::int64_t>(pos), static_cast<std::int64_t>(pos + s.size()), text, voice});
      pos += s.size();
    }
    pos += static_cast<std::size_t>(4800 + 40000 * u(rng));
  }
  for (float& v : t.audio) v = std::clamp(v, -1.0f, 1.0f);
  return t;
}

// Whether a detection ending at sample `end` is one for `keyword`: it ends between the
// keyword's start and 1.25 s after its end.
bool detects(const Segment& keyword, std::int64_t end) {
  return end >= keyword.begin && end <= keyword.end + 20000;
}

struct Score {
  int hits = 0, misses = 0, false_accepts = 0;
  std::vector<bool> found;  // per keyword of the track
  std::vector<std::int64_t> false_accept_ends;
  double miss_rate() const {
    return hits + misses > 0 ? static_cast<double>(misses) / (hits + misses) : 0.0;
  }
};

Score score(const std::vector<std::int64_t>& ends, const Track& track) {
  Score s;
  std::vector<bool> found(track.keywords.size(), false);
  for (std::int64_t e : ends) {
    bool matched = false;
    for (std::size_t k = 0; k < track.keywords.size(); ++k) {
      if (!found[k] && detects(track.keywords[k], e)) {
        found[k] = true;
        matched = true;
        break;
      }
    }
    if (!matched) {
      ++s.false_accepts;
      s.false_accept_ends.push_back(e);
    }
  }
  for (bool f : found) (f ? s.hits : s.misses)++;
  s.found = std::move(found);
  return s;
}

void print_accuracy(const char* name, const kws::Accuracy& a) {
  std::printf(
      "  %-6s overall %6.2f%%  keyword %6.2f%%  unknown %6.2f%%  silence %6.2f%%  noise %6.2f%%\n",
      name, 100.0 * a.overall, 100.0 * a.per_class(0), 100.0 * a.per_class(1),
      100.0 * a.per_class(2), 100.0 * a.per_class(3));
}

struct Trace {
  std::vector<float> posteriors;
  std::vector<std::int64_t> end_frames;
};

// Every window's keyword posterior of the int8 CNN spotter over `pcm`, streamed in 100 ms
// chunks as the microphone delivers them.
Trace cnn_trace(const kws::KwsModel& model, const std::vector<std::int16_t>& pcm) {
  kws::NeuralWakeWord detector(model, 0.5f, kws::Precision::int8);
  Trace trace;
  detector.spotter().set_window_observer(
      [](void* ctx, std::int64_t end_frame, float posterior, float) {
        auto* t = static_cast<Trace*>(ctx);
        t->posteriors.push_back(posterior);
        t->end_frames.push_back(end_frame);
      },
      &trace);
  std::vector<perception::WakeWordDetection> ignored;
  const std::span<const std::int16_t> all(pcm);
  for (std::size_t i = 0; i < pcm.size(); i += 1600) {
    detector.process(all.subspan(i, std::min<std::size_t>(1600, pcm.size() - i)), ignored);
  }
  return trace;
}

// Sample just past the last one of the window that ended at `end_frame` (exclusive).
std::int64_t end_sample(std::int64_t end_frame) { return (end_frame - 1) * 160 + 400; }

// Replays the decision (smoothing, threshold, refractory period) over the posterior trace.
std::vector<std::int64_t> detection_ends(const Trace& trace, int smoothing, float threshold,
                                         int refractory) {
  kws::DetectionDecider decider(smoothing, threshold, refractory);
  std::vector<std::int64_t> ends;
  for (std::size_t w = 0; w < trace.posteriors.size(); ++w) {
    if (decider.push(trace.posteriors[w])) ends.push_back(end_sample(trace.end_frames[w]));
  }
  return ends;
}

std::string base_of(const std::string& voice) { return voice.substr(0, voice.find('+')); }
std::string variant_of(const std::string& voice) {
  const std::size_t plus = voice.find('+');
  return plus == std::string::npos ? "(none)" : voice.substr(plus + 1);
}

// The scores a detector gave over a track, one per step: (end sample, score). The cnn spotter
// gives one per 10 ms window, the embedding wake word one every 80 ms.
using ScoreLog = std::vector<std::pair<std::int64_t, float>>;

ScoreLog score_log(const Trace& trace) {
  ScoreLog log;
  for (std::size_t w = 0; w < trace.posteriors.size(); ++w)
    log.emplace_back(end_sample(trace.end_frames[w]), trace.posteriors[w]);
  return log;
}

// --details / --embedding-details: where one operating point goes wrong. Miss rate per voice
// base and variant (on the real track: per folder), the distribution of each keyword's highest
// score, each missed keyword with its highest score, and every false accept with what was
// being said in the window that fired.
void print_details(const Score& s, const Track& track, const ScoreLog& log,
                   const std::string& setting) {
  std::printf("\ndetails at %s:\n", setting.c_str());
  std::map<std::string, std::pair<int, int>> by_base, by_variant;  // misses, keywords
  for (std::size_t k = 0; k < track.keywords.size(); ++k) {
    for (auto* m : {&by_base, &by_variant}) {
      auto& [misses, total] = (*m)[m == &by_base ? base_of(track.keywords[k].voice)
                                                 : variant_of(track.keywords[k].voice)];
      misses += s.found[k] ? 0 : 1;
      ++total;
    }
  }
  for (const auto* m : {&by_base, &by_variant}) {
    std::printf("  miss rate by voice %s:\n", m == &by_base ? "base" : "variant");
    for (const auto& [name, mt] : *m) {
      std::printf("    %-18s %3d / %3d  %6.2f%%\n", name.c_str(), mt.first, mt.second,
                  100.0 * mt.first / std::max(1, mt.second));
    }
  }
  // Highest score of a step ending inside each keyword's hit range.
  const float edges[] = {0.5f, 0.9f, 0.97f, 0.99f};
  int buckets[5] = {};
  std::vector<float> peaks;
  for (const Segment& kw : track.keywords) {
    float peak = 0.0f;
    for (const auto& [end, score] : log) {
      if (detects(kw, end)) peak = std::max(peak, score);
    }
    int i = 0;
    while (i < 4 && peak >= edges[i]) ++i;
    ++buckets[i];
    peaks.push_back(peak);
  }
  std::printf(
      "  keywords by highest score: <0.5 %d, 0.5-0.9 %d, 0.9-0.97 %d, 0.97-0.99 %d, >=0.99 %d\n",
      buckets[0], buckets[1], buckets[2], buckets[3], buckets[4]);
  std::printf("  missed keywords (time, highest score, who said what):\n");
  for (std::size_t k = 0; k < track.keywords.size(); ++k) {
    if (s.found[k]) continue;
    const Segment& kw = track.keywords[k];
    std::printf("    %7.1f s  %.3f  [%s] \"%s\"\n", static_cast<double>(kw.begin) / 16000.0,
                static_cast<double>(peaks[k]), kw.voice.c_str(), kw.text.c_str());
  }
  std::printf("  false accepts (time, then what was said in the 1 s before):\n");
  for (std::int64_t e : s.false_accept_ends) {
    std::string said;
    for (const auto* list : {&track.keywords, &track.sentences}) {
      for (const Segment& g : *list) {
        if (g.end > e - kws::kWindowSamples && g.begin < e)
          said += " [" + g.voice + "] \"" + g.text + "\"";
      }
    }
    std::printf("    %7.1f s%s\n", static_cast<double>(e) / 16000.0,
                said.empty() ? " (noise only)" : said.c_str());
  }
}

}  // namespace

ScoreLog embedding_scores(const kws::EmbeddingHead& head, const std::vector<std::int16_t>& pcm,
                          double* cpu_seconds) {
  kws::EmbeddingWakeWord detector(kws::EmbeddingModels::load(), head, 0.5f);
  ScoreLog log;
  detector.set_score_log(&log);
  std::vector<perception::WakeWordDetection> ignored;
  // This thread's CPU time (pocketsphinx may be running on others).
  auto cpu_now = [] {
    timespec t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) + static_cast<double>(t.tv_nsec) * 1e-9;
  };
  const double start = cpu_now();
  for (std::size_t i = 0; i < pcm.size(); i += 1600) {
    detector.process(
        std::span<const std::int16_t>(pcm).subspan(i, std::min<std::size_t>(1600, pcm.size() - i)),
        ignored);
  }
  *cpu_seconds = cpu_now() - start;
  return log;
}

// Replays threshold, the number of consecutive 80 ms scores that must reach it (or with
// `mean`, the number of scores whose mean must reach it: a dip in one step does not reset a
// mean as it resets a run), and the refractory period over the score log.
std::vector<std::int64_t> embedding_ends(const ScoreLog& log, float threshold, float refractory_s,
                                         int steps, bool mean = false) {
  std::vector<std::int64_t> ends;
  const auto refractory = static_cast<std::int64_t>(refractory_s * 16000.0f);
  const auto n = static_cast<std::size_t>(steps);
  int run = 0;
  float sum = 0.0f;  // of the last `steps` scores
  for (std::size_t i = 0; i < log.size(); ++i) {
    const auto& [end, score] = log[i];
    run = score >= threshold ? run + 1 : 0;
    sum += score - (i >= n ? log[i - n].second : 0.0f);
    const bool fires =
        mean ? i + 1 >= n && sum >= threshold * static_cast<float>(steps) : run >= steps;
    if (fires && (ends.empty() || end - ends.back() >= refractory)) ends.push_back(end);
  }
  return ends;
}

// --embedding-mean-steps: also replay thresholds on the mean of this many scores.
std::vector<int> g_embedding_mean_steps;

// --embedding-consecutive: the step counts to replay (1 = every score on its own).
std::vector<int> g_embedding_consecutive = {1};
// --embedding-details: the threshold to show the first head's misses and false accepts at
// (with the first --embedding-consecutive step count); negative: none.
float g_embedding_details = -1.0f;
// --dump-scores: where to write every head's score log and the track's segments, for trying
// decision rules offline (empty: not written).
std::string g_dump_scores;

// PREFIX.scores.tsv: "head end_sample score" per line; PREFIX.track.tsv: "keyword|sentence
// begin end voice text" per line (samples at 16 kHz).
void dump_scores(const std::string& prefix, const std::vector<ScoreLog>& logs, const Track& track) {
  std::ofstream scores(prefix + ".scores.tsv"), segments(prefix + ".track.tsv");
  for (std::size_t h = 0; h < logs.size(); ++h) {
    for (const auto& [end, score] : logs[h]) scores << h << '\t' << end << '\t' << score << '\n';
  }
  for (const auto* kind : {&track.keywords, &track.sentences}) {
    for (const Segment& seg : *kind) {
      segments << (kind == &track.keywords ? "keyword" : "sentence") << '\t' << seg.begin << '\t'
               << seg.end << '\t' << seg.voice << '\t' << seg.text << '\n';
    }
  }
  if (!scores.flush() || !segments.flush())
    throw std::runtime_error("--dump-scores: cannot write \"" + prefix + ".*.tsv\"");
}

// PREFIX.cnn.tsv: "end_sample posterior" for every window of the cnn spotter, so rules that
// combine it with a head (one confirming the other) can be replayed offline too.
void dump_cnn_trace(const std::string& prefix, const Trace& trace) {
  std::ofstream out(prefix + ".cnn.tsv");
  for (std::size_t w = 0; w < trace.posteriors.size(); ++w)
    out << end_sample(trace.end_frames[w]) << '\t' << trace.posteriors[w] << '\n';
  if (!out.flush()) throw std::runtime_error("--dump-scores: cannot write \"" + prefix + ".cnn.tsv\"");
}

struct EvalRow {
  double miss, fah;
  float setting;
  int consecutive = 1;  // steps in a row over the threshold, or with `mean`, steps averaged
  bool mean = false;
};

void print_embedding_rows(const ScoreLog& log, const Track& track,
                          const std::vector<float>& thresholds, float refractory_s, double hours,
                          std::vector<EvalRow>& rows) {
  std::vector<std::pair<int, bool>> rules;  // (steps, mean)
  for (int n : g_embedding_consecutive) rules.emplace_back(n, false);
  for (int n : g_embedding_mean_steps) rules.emplace_back(n, true);
  for (const auto& [n, mean] : rules) {
    char name[64];
    if (mean) {
      std::snprintf(name, sizeof name, "embedding head mean %d", n);
    } else if (n == 1) {
      std::snprintf(name, sizeof name, "embedding head");
    } else {
      std::snprintf(name, sizeof name, "embedding head %d steps", n);
    }
    for (float th : thresholds) {
      const Score s = score(embedding_ends(log, th, refractory_s, n, mean), track);
      std::printf("%-28s %9.3f %7.2f%% %6d %8.2f\n", name, static_cast<double>(th),
                  100.0 * s.miss_rate(), s.false_accepts, s.false_accepts / hours);
      rows.push_back({s.miss_rate(), s.false_accepts / hours, th, n, mean});
    }
  }
}

// pocketsphinx keyphrase spotting for `keyword` over the track at each sensitivity, each in the
// background (std::async) while the other detectors run; get() gives the detections' ends.
std::vector<std::future<std::vector<std::int64_t>>> start_pocketsphinx(
    const std::vector<std::int16_t>& pcm, const std::vector<float>& sensitivities, const std::string& keyword) {
  std::vector<std::future<std::vector<std::int64_t>>> runs;
  for (float s : sensitivities) {
    runs.push_back(std::async(std::launch::async, [&pcm, s, keyword] {
      perception::PocketsphinxWakeWordOptions o;
      o.keyword = keyword;
      o.sensitivity = s;
      perception::PocketsphinxWakeWord ps(o);
      std::vector<perception::WakeWordDetection> det;
      for (std::size_t i = 0; i < pcm.size(); i += 1600) {
        ps.process(std::span<const std::int16_t>(pcm).subspan(i, std::min<std::size_t>(1600, pcm.size() - i)), det);
      }
      std::vector<std::int64_t> ends;
      for (const auto& d : det) ends.push_back(d.end_sample);
      return ends;
    }));
  }
  return runs;
}

void print_best(const char* name, const std::vector<EvalRow>& rows) {
  const EvalRow* best = nullptr;
  for (const EvalRow& r : rows) {
    if (r.fah < 1.0 && (!best || r.miss < best->miss)) best = &r;
  }
  if (best) {
    std::printf("  %-13s setting %.3f, %d %s: miss %.2f%%, %.2f FA/h\n", name,
                static_cast<double>(best->setting), best->consecutive,
                best->mean ? "scores' mean" : "consecutive", 100.0 * best->miss, best->fah);
  } else {
    std::printf("  %-13s none of the settings stays under 1 FA/h\n", name);
  }
}

// Every --embedding-head on one track: the embeddings are computed once (they do not depend
// on the head), each head scores every 80 ms as EmbeddingWakeWord does.
std::vector<std::vector<EvalRow>> all_embedding_rows(const std::vector<std::string>& paths,
                                                     const std::vector<std::int16_t>& pcm,
                                                     const Track& track,
                                                     const std::vector<float>& thresholds,
                                                     double hours) {
  std::vector<std::vector<EvalRow>> rows(paths.size());
  if (paths.empty()) return rows;
  std::vector<kws::EmbeddingHead> heads;
  for (const auto& p : paths) heads.push_back(kws::load_head(p));
  double cpu = 0.0;
  // The first head through the detector itself (the listening cost figure) ...
  const ScoreLog first = embedding_scores(heads.front(), pcm, &cpu);
  std::vector<ScoreLog> logs(heads.size());
  logs[0] = first;
  if (heads.size() > 1) {
    // ... the others over the same embeddings.
    kws::EmbeddingStream stream(kws::EmbeddingModels::load());
    std::vector<kws::Embedding> all, fresh;
    std::vector<std::int64_t> ends;
    std::vector<float> scaled;
    for (std::size_t i = 0; i < pcm.size(); i += 1600) {
      const std::size_t n = std::min<std::size_t>(1600, pcm.size() - i);
      scaled.assign(pcm.begin() + static_cast<std::ptrdiff_t>(i),
                    pcm.begin() + static_cast<std::ptrdiff_t>(i + n));
      fresh.clear();
      stream.push(scaled, fresh);
      const std::int64_t last_end = stream.samples_seen();
      for (std::size_t k = 0; k < fresh.size(); ++k) {
        all.push_back(fresh[k]);
        ends.push_back(last_end -
                       static_cast<std::int64_t>(fresh.size() - 1 - k) * kws::kEmbeddingHop);
      }
    }
    std::vector<float> in(kws::kHeadInputs);
    for (std::size_t e = kws::kHeadEmbeddings - 1; e < all.size(); ++e) {
      for (std::size_t j = 0; j < static_cast<std::size_t>(kws::kHeadEmbeddings); ++j) {
        const auto& emb = all[e + 1 - kws::kHeadEmbeddings + j];
        std::copy(emb.begin(), emb.end(),
                  in.begin() + static_cast<std::ptrdiff_t>(j * kws::kEmbeddingSize));
      }
      for (std::size_t h = 1; h < heads.size(); ++h)
        logs[h].emplace_back(ends[e], heads[h].score(in));
    }
  }
  if (!g_dump_scores.empty()) dump_scores(g_dump_scores, logs, track);
  for (std::size_t h = 0; h < heads.size(); ++h) {
    std::printf("-- embedding head %s (\"%s\", refractory %.1f s)\n", paths[h].c_str(),
                heads[h].keyword.c_str(), static_cast<double>(heads[h].refractory_seconds));
    print_embedding_rows(logs[h], track, thresholds, heads[h].refractory_seconds, hours, rows[h]);
  }
  if (g_embedding_details >= 0.0f) {
    const int steps = g_embedding_consecutive.front();
    const Score s = score(
        embedding_ends(logs[0], g_embedding_details, heads[0].refractory_seconds, steps), track);
    print_details(s, track, logs[0],
                  paths[0] + " threshold " + std::to_string(g_embedding_details) + ", " +
                      std::to_string(steps) + " steps");
  }
  std::printf(
      "(embedding wake word \"%s\": %.1f s of CPU for %.1f s of audio, %.2f%% of one core)\n",
      heads.front().keyword.c_str(), cpu, hours * 3600.0, 100.0 * cpu / (hours * 3600.0));
  return rows;
}

void print_all_best(const std::vector<std::string>& paths,
                    const std::vector<std::vector<EvalRow>>& rows) {
  for (std::size_t h = 0; h < paths.size(); ++h) {
    std::printf("  embedding %s:\n", paths[h].c_str());
    print_best("", rows[h]);
  }
}

// The real track's background, one piece after another: the --noise recordings in turn, else
// 10 s of noise made afresh each time (white, pink, brown, or the babble of four held-out
// voices). Fresh, because a short noise clip played over and over makes one chance pattern in
// it that the detector takes for the keyword into dozens of false accepts.
class Background {
 public:
  Background(std::vector<std::vector<float>> recordings, std::mt19937_64& rng)
      : recordings_(std::move(recordings)), voices_(kws::heldout_voices()), rng_(rng) {}

  std::vector<float> next() {
    if (!recordings_.empty())
      return recordings_[std::uniform_int_distribution<std::size_t>(0,
                                                                    recordings_.size() - 1)(rng_)];
    constexpr std::size_t ten_s = 160000;
    switch (std::uniform_int_distribution<int>(0, 3)(rng_)) {
      case 0:
        return kws::make_noise(kws::NoiseColour::white, ten_s, 0.1f, rng_);
      case 1:
        return kws::make_noise(kws::NoiseColour::pink, ten_s, 0.1f, rng_);
      case 2:
        return kws::make_noise(kws::NoiseColour::brown, ten_s, 0.1f, rng_);
      default:
        return babble(ten_s);
    }
  }

 private:
  std::vector<float> babble(std::size_t samples) {
    std::vector<float> out(samples, 0.0f);
    for (int stream = 0; stream < 4; ++stream) {
      for (std::size_t pos = std::uniform_int_distribution<std::size_t>(0, 16000)(rng_);
           pos < samples;) {
        const auto& text = kws::sentences()[std::uniform_int_distribution<std::size_t>(
            0, kws::sentences().size() - 1)(rng_)];
        const auto& voice =
            voices_[std::uniform_int_distribution<std::size_t>(0, voices_.size() - 1)(rng_)];
        const std::vector<float> s = kws::synthesize(text, voice, 170, 50);
        for (std::size_t i = 0; i < s.size() && pos < samples; ++i) out[pos++] += s[i];
        pos += 1600;
      }
    }
    return out;
  }

  std::vector<std::vector<float>> recordings_;
  std::vector<std::string> voices_;  // for the babble
  std::mt19937_64& rng_;
};

// A real recording on the track: its samples, file name and folder.
struct Recording {
  std::vector<float> audio;
  std::string name, folder;
};

std::vector<Recording> read_recordings(const std::filesystem::path& folder) {
  std::vector<Recording> out;
  for (const auto& file : sound_folder_files(folder, 0))
    out.push_back({read_recording(file), file.filename().string(), folder.filename().string()});
  return out;
}

// Real recordings: every file of the negative folders and the positive folder, shuffled, one
// after another with 0.3..2.5 s pauses (2.8..5 s between two keywords), over continuous
// background noise (Background) at -50..-35 dBFS; each utterance at -18..-4 dBFS peak.
Track build_real_track(const std::vector<Recording>& positives,
                       const std::vector<Recording>& negatives, Background& background,
                       std::mt19937_64& rng) {
  std::vector<std::pair<const Recording*, bool>> items;
  for (const auto& p : positives) items.emplace_back(&p, true);
  for (const auto& n : negatives) items.emplace_back(&n, false);
  std::shuffle(items.begin(), items.end(), rng);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::size_t total = 16000;
  std::vector<std::size_t> gaps;
  for (std::size_t k = 0; k < items.size(); ++k) {
    float pause = 0.3f + 2.2f * u(rng);
    // Two keywords in a row are a new wake-up, not the same one said twice: at least 2.5 s
    // apart, beyond the detectors' refractory period (2 s), in which a second detection
    // would be suppressed and counted as a miss.
    if (k > 0 && items[k].second && items[k - 1].second) pause += 2.5f;
    gaps.push_back(static_cast<std::size_t>(pause * 16000.0f));
    total += gaps.back() + items[k].first->audio.size();
  }
  Track t;
  t.audio.assign(total + 16000, 0.0f);
  for (std::size_t pos = 0; pos < t.audio.size();) {
    const std::vector<float> n = background.next();
    const float level = db(-50.0f + 15.0f * u(rng)) / std::max(kws::rms(n), 1e-6f);
    for (std::size_t i = 0; i < n.size() && pos < t.audio.size(); ++i)
      t.audio[pos++] += level * n[i];
  }
  std::size_t pos = 16000;
  for (std::size_t k = 0; k < items.size(); ++k) {
    pos += gaps[k];
    const Recording& r = *items[k].first;
    const auto& x = r.audio;
    mix_in(t.audio, pos, x, -18.0f + 14.0f * u(rng));
    Segment seg{static_cast<std::int64_t>(pos), static_cast<std::int64_t>(pos + x.size()), r.name,
                r.folder};
    (items[k].second ? t.keywords : t.sentences).push_back(seg);
    pos += x.size();
  }
  for (float& v : t.audio) v = std::clamp(v, -1.0f, 1.0f);
  return t;
}

int main(int argc, char** argv) {
  CLI::App app{"Evaluate Marvin's keyword spotter on held-out voices, against pocketsphinx"};
  std::string model_path = kws::default_model_path().string(), float_model_path, save_track;
  std::uint64_t seed = 1001;
  int clips = 200, keywords = 120, threads = 2;
  double minutes = 30.0;
  std::vector<float> thresholds = {0.3f, 0.4f, 0.5f, 0.6f, 0.7f, 0.8f, 0.9f, 0.95f};
  std::vector<float> ps_sensitivities = {0.3f, 0.5f, 0.7f};
  bool no_pocketsphinx = false;
  std::vector<int> smoothings;
  float refractory_s = -1.0f;
  float details_threshold = -1.0f;
  app.add_option("--model", model_path, "int8 model")->capture_default_str();
  app.add_option("--float-model", float_model_path, "float model, for float vs int8 accuracy");
  app.add_option("--seed", seed)->capture_default_str();
  app.add_option("--clips", clips, "held-out keyword clips (other classes in proportion)")
      ->capture_default_str();
  app.add_option("--minutes", minutes, "length of the streaming track")->capture_default_str();
  app.add_option("--keywords", keywords, "keywords inside the streaming track")
      ->capture_default_str();
  app.add_option("--thresholds", thresholds, "neural thresholds to report")->capture_default_str();
  app.add_option("--ps-sensitivities", ps_sensitivities, "pocketsphinx sensitivities")
      ->capture_default_str();
  app.add_flag("--no-pocketsphinx", no_pocketsphinx);
  app.add_option("--smoothing", smoothings,
                 "smoothing windows to replay the trace with (default: the model's); several "
                 "values give a table for each");
  app.add_option("--refractory", refractory_s, "override the model's refractory period (s)");
  app.add_option("--threads", threads)->capture_default_str();
  app.add_option("--save-track", save_track, "write the streaming track to this WAV");
  app.add_option("--details", details_threshold,
                 "at this threshold (first --smoothing): miss rate per voice, keyword posterior "
                 "peaks, and each false accept with what was said");
  std::vector<std::string> head_paths;
  std::string positives_dir, noise_dir, ps_keyword_option;
  std::vector<std::string> negative_dirs;
  std::vector<float> embedding_thresholds = {0.3f,  0.5f,  0.7f,  0.8f,  0.9f,
                                             0.95f, 0.98f, 0.99f, 0.995f};
  app.add_option("--embedding-head", head_paths,
                 "also evaluate the embedding wake word with this head (on the same track)");
  app.add_option("--embedding-thresholds", embedding_thresholds)->capture_default_str();
  app.add_option("--embedding-consecutive", g_embedding_consecutive,
                 "embedding head: scores over the threshold in N consecutive 80 ms steps for a "
                 "detection; several values replay the one score log with each")
      ->capture_default_str();
  app.add_option("--embedding-mean-steps", g_embedding_mean_steps,
                 "also replay each threshold on the mean of this many consecutive scores")
      ->check(CLI::Range(1, 10));
  app.add_option("--dump-scores", g_dump_scores,
                 "write every head's scores, the cnn spotter's posteriors and the track's segments to "
                 "PREFIX.scores.tsv, PREFIX.cnn.tsv and PREFIX.track.tsv (for trying decision "
                 "rules offline)");
  app.add_option("--embedding-details", g_embedding_details,
                 "at this threshold (first --embedding-consecutive, first head): miss rate per "
                 "voice (real track: per folder), each missed keyword and each false accept");
  app.add_option("--positives", positives_dir,
                 "real recordings of the keyword (WAV/FLAC folder): evaluate on a track of real "
                 "recordings instead of held-out synthetic voices");
  app.add_option("--negatives", negative_dirs, "real recordings of other words (folders)");
  app.add_option("--noise", noise_dir, "background noise recordings for the real track");
  app.add_option("--ps-keyword", ps_keyword_option,
                 "the words pocketsphinx listens for on the real track (default: the embedding "
                 "head's keyword, else the model's)");
  CLI11_PARSE(app, argc, argv);

  if (!positives_dir.empty()) {
    try {
      std::mt19937_64 rng(seed);
      const auto positives = read_recordings(positives_dir);
      std::vector<Recording> negatives;
      for (const auto& d : negative_dirs) {
        auto n = read_recordings(d);
        negatives.insert(negatives.end(), std::make_move_iterator(n.begin()),
                         std::make_move_iterator(n.end()));
      }
      std::vector<std::vector<float>> noise_recordings;
      if (!noise_dir.empty())
        noise_recordings = kws::make_noise_pool(noise_dir, kws::heldout_voices(), rng);
      Background background(std::move(noise_recordings), rng);
      const Track track = build_real_track(positives, negatives, background, rng);
      const std::vector<std::int16_t> pcm = marvin::audio::to_pcm16(track.audio);
      const double hours = static_cast<double>(pcm.size()) / 16000.0 / 3600.0;
      std::printf("real track: %.1f min, %zu keyword recordings (%s), %zu other recordings\n",
                  hours * 60.0, track.keywords.size(), positives_dir.c_str(),
                  track.sentences.size());
      if (!save_track.empty()) marvin::audio::write_speech_file(save_track, pcm);
      std::printf("\n%-28s %9s %8s %6s %8s\n", "detector", "setting", "miss", "FA", "FA/h");
      std::vector<EvalRow> cnn_rows, ps_rows;
      const kws::KwsModel model = kws::load_model(model_path);
      // pocketsphinx listens for the keyword of the recordings: --ps-keyword, else the (first)
      // head's, else the model's.
      const std::string ps_keyword = !ps_keyword_option.empty() ? ps_keyword_option
                                     : head_paths.empty()
                                         ? model.keyword
                                         : kws::load_head(head_paths.front()).keyword;
      std::vector<std::future<std::vector<std::int64_t>>> ps_runs;
      if (!no_pocketsphinx) ps_runs = start_pocketsphinx(pcm, ps_sensitivities, ps_keyword);
      std::vector<std::vector<EvalRow>> head_rows =
          all_embedding_rows(head_paths, pcm, track, embedding_thresholds, hours);
      {
        const Trace trace = cnn_trace(model, pcm);
        if (!g_dump_scores.empty()) dump_cnn_trace(g_dump_scores, trace);
        for (float th : thresholds) {
          const Score s = score(detection_ends(trace, model.detection.smoothing_windows, th,
                                               kws::refractory_windows(model)),
                                track);
          std::printf("%-28s %9.3f %7.2f%% %6d %8.2f\n", ("cnn \"" + model.keyword + "\"").c_str(),
                      static_cast<double>(th), 100.0 * s.miss_rate(), s.false_accepts,
                      s.false_accepts / hours);
          cnn_rows.push_back({s.miss_rate(), s.false_accepts / hours, th});
        }
      }
      for (std::size_t i = 0; i < ps_runs.size(); ++i) {
        const float sens = ps_sensitivities[i];
        try {
          const Score s = score(ps_runs[i].get(), track);
          std::printf("%-28s %9.2f %7.2f%% %6d %8.2f\n", ("pocketsphinx \"" + ps_keyword + "\"").c_str(),
                      static_cast<double>(sens), 100.0 * s.miss_rate(), s.false_accepts, s.false_accepts / hours);
          ps_rows.push_back({s.miss_rate(), s.false_accepts / hours, sens});
        } catch (const std::exception& e) {  // e.g. a keyword word missing from its dictionary
          std::printf("pocketsphinx \"%s\" %.2f: %s\n", ps_keyword.c_str(), static_cast<double>(sens), e.what());
        }
      }
      std::printf("\noperating point (lowest miss rate with under 1 false accept per hour):\n");
      print_all_best(head_paths, head_rows);
      print_best("cnn", cnn_rows);
      if (!ps_rows.empty()) print_best("pocketsphinx", ps_rows);
      std::printf("(%.2f h of audio: one false accept is %.2f FA/h)\n", hours, 1.0 / hours);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "marvin-kws-eval: %s\n", e.what());
      return 1;
    }
    return 0;
  }

  try {
    const auto start = Clock::now();
    auto elapsed = [&] { return std::chrono::duration<double>(Clock::now() - start).count(); };
    kws::KwsModel model = kws::load_model(model_path);
    for (int sm : smoothings) {
      if (sm < 1)
        throw std::runtime_error("--smoothing " + std::to_string(sm) +
                                 ": expected 1 or more windows");
    }
    if (smoothings.empty()) smoothings.push_back(model.detection.smoothing_windows);
    if (refractory_s >= 0.0f) model.detection.refractory_seconds = refractory_s;
    const std::vector<std::string> voices = kws::heldout_voices();
    std::printf(
        "model %s: keyword \"%s\", threshold %.2f, smoothing %d windows, refractory %.2f s\n",
        model_path.c_str(), model.keyword.c_str(), static_cast<double>(model.detection.threshold),
        model.detection.smoothing_windows, static_cast<double>(model.detection.refractory_seconds));
    std::printf("held-out voices: %zu (none used in training)\n", voices.size());

    // 1. Clips.
    kws::DatasetOptions dopt;
    dopt.seed = seed;
    dopt.keyword = model.keyword;
    dopt.voices = voices;
    dopt.keyword_clips = clips;
    dopt.unknown_clips = clips;
    dopt.silence_clips = clips / 4;
    dopt.noise_clips = clips / 4;
    dopt.augmented_copies = 1;
    kws::SplitClips split = kws::synthesize_dataset(dopt);
    std::vector<kws::AudioClip> all = std::move(split.train);
    all.insert(all.end(), split.test.begin(), split.test.end());
    all.insert(all.end(), split.eval.begin(), split.eval.end());
    kws::TrainingSet set = kws::clips_to_inputs(all, threads);
    kws::normalise(set, model.normalisation);
    std::printf("\nper-class accuracy on %zu held-out clips (%.0f s):\n", set.size(), elapsed());
    const kws::Accuracy ia = kws::evaluate_int8(model.int8_network(), set);
    if (!float_model_path.empty()) {
      const kws::KwsModel fm = kws::load_model(float_model_path);
      const kws::Accuracy fa = kws::evaluate_float(fm.network, set);
      print_accuracy("float", fa);
      print_accuracy("int8", ia);
      std::printf("  int8 - float: %+.2f points\n", 100.0 * (ia.overall - fa.overall));
    } else {
      print_accuracy("int8", ia);
    }

    // 2. Streaming.
    std::mt19937_64 rng(seed * 7919 + 17);
    const Track track =
        build_track(minutes, keywords, model.keyword, voices, split.noise_pool, rng);
    const std::vector<std::int16_t> pcm = marvin::audio::to_pcm16(track.audio);
    const double hours = static_cast<double>(pcm.size()) / 16000.0 / 3600.0;
    std::printf("\nstreaming track: %.1f min, %zu keywords (%.0f s)\n", hours * 60.0,
                track.keywords.size(), elapsed());
    if (!save_track.empty()) marvin::audio::write_speech_file(save_track, pcm);

    // pocketsphinx in the background while the neural detector runs.
    std::vector<std::future<std::vector<std::int64_t>>> ps_runs;
    if (!no_pocketsphinx) ps_runs = start_pocketsphinx(pcm, ps_sensitivities, model.keyword);

    const auto neural_start = Clock::now();
    const Trace trace = cnn_trace(model, pcm);
    const double neural_s = std::chrono::duration<double>(Clock::now() - neural_start).count();
    std::printf("neural int8: %zu windows in %.1f s wall clock\n", trace.posteriors.size(),
                neural_s);
    if (!g_dump_scores.empty()) dump_cnn_trace(g_dump_scores, trace);

    std::printf("\n%-28s %9s %8s %6s %8s\n", "detector", "setting", "miss", "FA", "FA/h");
    const int refractory = kws::refractory_windows(model);
    struct Row {
      double miss, fah;
      float setting;
      int smoothing;
    };
    std::vector<Row> neural_rows, ps_rows;
    for (int sm : smoothings) {
      for (float th : thresholds) {
        const Score s = score(detection_ends(trace, sm, th, refractory), track);
        char name[64];
        std::snprintf(name, sizeof name, "neural int8 smoothing %d", sm);
        std::printf("%-28s %9.3f %7.2f%% %6d %8.2f\n", name, static_cast<double>(th),
                    100.0 * s.miss_rate(), s.false_accepts, s.false_accepts / hours);
        neural_rows.push_back({s.miss_rate(), s.false_accepts / hours, th, sm});
      }
    }
    const std::vector<std::vector<EvalRow>> head_rows =
        all_embedding_rows(head_paths, pcm, track, embedding_thresholds, hours);
    if (details_threshold >= 0.0f) {
      const Score s =
          score(detection_ends(trace, smoothings.front(), details_threshold, refractory), track);
      print_details(s, track, score_log(trace),
                    "threshold " + std::to_string(details_threshold) + ", smoothing " +
                        std::to_string(smoothings.front()));
    }
    for (std::size_t i = 0; i < ps_runs.size(); ++i) {
      const Score s = score(ps_runs[i].get(), track);
      std::printf("%-28s %9.2f %7.2f%% %6d %8.2f\n", "pocketsphinx keyphrase",
                  static_cast<double>(ps_sensitivities[i]), 100.0 * s.miss_rate(), s.false_accepts,
                  s.false_accepts / hours);
      ps_rows.push_back({s.miss_rate(), s.false_accepts / hours, ps_sensitivities[i], 0});
    }
    auto best_under = [](const std::vector<Row>& rows, double fah_limit) {
      const Row* best = nullptr;
      for (const Row& r : rows) {
        if (r.fah < fah_limit && (!best || r.miss < best->miss)) best = &r;
      }
      return best;
    };
    std::printf("\noperating point (lowest miss rate with under 1 false accept per hour):\n");
    if (const Row* r = best_under(neural_rows, 1.0)) {
      std::printf("  neural        threshold %.3f, smoothing %d: miss %.2f%%, %.2f FA/h\n",
                  static_cast<double>(r->setting), r->smoothing, 100.0 * r->miss, r->fah);
    } else {
      std::printf("  neural        none of the thresholds stays under 1 FA/h\n");
    }
    if (!ps_rows.empty()) {
      if (const Row* r = best_under(ps_rows, 1.0)) {
        std::printf("  pocketsphinx  sensitivity %.2f: miss %.2f%%, %.2f FA/h\n",
                    static_cast<double>(r->setting), 100.0 * r->miss, r->fah);
      } else {
        std::printf("  pocketsphinx  none of the sensitivities stays under 1 FA/h\n");
      }
    }
    print_all_best(head_paths, head_rows);
    std::printf("(%.1f h of audio: one false accept is %.2f FA/h; total %.0f s)\n", hours,
                1.0 / hours, elapsed());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "marvin-kws-eval: %s\n", e.what());
    return 1;
  }
  return 0;
}
