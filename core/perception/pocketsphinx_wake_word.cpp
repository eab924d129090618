#include "perception/pocketsphinx_wake_word.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "perception/sphinx_decoder.h"

namespace marvin::perception {
namespace {

constexpr const char* kSearch = "wake_word";
constexpr int kFrameSamples = 160;  // pocketsphinx's 10 ms frame at 16 kHz
// Long utterances make pocketsphinx keep growing state; the stream is cut into utterances
// of this length (a keyword straddling a cut can be missed once a minute at most).
constexpr std::int64_t kRestartSamples = 60 * 16000;

}  // namespace

struct PocketsphinxWakeWord::Impl {
  PocketsphinxWakeWordOptions options;
  detail::Decoder decoder;
  std::int64_t samples = 0;          // fed since reset
  std::int64_t utterance_start = 0;  // sample where the current pocketsphinx utterance began
  bool in_utterance = false;

  void configure() {
    cmd_ln_set_float_r(ps_get_config(decoder.get()), "-kws_threshold",
                       threshold_for(options.sensitivity));
    if (ps_set_keyphrase(decoder.get(), kSearch, options.keyword.c_str()) < 0 ||
        ps_set_search(decoder.get(), kSearch) < 0) {
      throw std::runtime_error("wake word \"" + options.keyword +
                               "\": pocketsphinx cannot spot it (is every word in " +
                               options.model.dictionary.string() + "?)");
    }
  }

  void restart() {
    if (in_utterance) ps_end_utt(decoder.get());
    ps_start_utt(decoder.get());
    in_utterance = true;
    utterance_start = samples;
  }
};

PocketsphinxWakeWord::PocketsphinxWakeWord(const PocketsphinxWakeWordOptions& options)
    : impl_(std::make_unique<Impl>()) {
  impl_->options = options;
  impl_->options.sensitivity = std::clamp(options.sensitivity, 0.0f, 1.0f);
  for (char& c : impl_->options.keyword) {
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  }
  impl_->decoder = detail::make_decoder(options.model);
  for (std::size_t pos = 0; pos < impl_->options.keyword.size();) {
    const std::size_t end = std::min(impl_->options.keyword.find(' ', pos), impl_->options.keyword.size());
    const std::string word = impl_->options.keyword.substr(pos, end - pos);
    if (!word.empty() && ps_lookup_word(impl_->decoder.get(), word.c_str()) == nullptr) {
      throw std::runtime_error("wake word \"" + impl_->options.keyword + "\": \"" + word +
                               "\" is not in the dictionary " + options.model.dictionary.string());
    }
    pos = end + 1;
  }
  impl_->configure();
  impl_->restart();
}

PocketsphinxWakeWord::~PocketsphinxWakeWord() {
  if (impl_->in_utterance) ps_end_utt(impl_->decoder.get());
}

const std::string& PocketsphinxWakeWord::keyword() const { return impl_->options.keyword; }

double PocketsphinxWakeWord::threshold_for(float sensitivity) {
  return std::pow(10.0, -60.0 * std::clamp(static_cast<double>(sensitivity), 0.0, 1.0));
}

void PocketsphinxWakeWord::set_sensitivity(float sensitivity) {
  impl_->options.sensitivity = std::clamp(sensitivity, 0.0f, 1.0f);
  if (impl_->in_utterance) ps_end_utt(impl_->decoder.get());
  impl_->in_utterance = false;
  impl_->configure();
  impl_->restart();
}

float PocketsphinxWakeWord::sensitivity() const { return impl_->options.sensitivity; }

std::size_t PocketsphinxWakeWord::process(std::span<const std::int16_t> samples,
                                          std::vector<WakeWordDetection>& detections) {
  std::size_t found = 0;
  ps_decoder_t* ps = impl_->decoder.get();
  // Frame-sized steps so a detection is placed within 10 ms.
  for (std::size_t offset = 0; offset < samples.size(); offset += kFrameSamples) {
    const std::size_t n = std::min<std::size_t>(kFrameSamples, samples.size() - offset);
    if (ps_process_raw(ps, samples.data() + offset, n, FALSE, FALSE) < 0) {
      throw std::runtime_error("pocketsphinx: wake-word decoding failed");
    }
    impl_->samples += static_cast<std::int64_t>(n);
    int32 score = 0;
    if (ps_get_hyp(ps, &score) != nullptr) {
      WakeWordDetection detection;
      detection.end_sample = impl_->samples;
      detection.begin_sample = impl_->samples;
      if (ps_seg_t* seg = ps_seg_iter(ps)) {
        int first = 0, last = 0;
        ps_seg_frames(seg, &first, &last);
        detection.begin_sample = impl_->utterance_start + std::int64_t{first} * kFrameSamples;
        ps_seg_free(seg);
      }
      // Pocketsphinx scores are log probabilities scaled to a log base of 1.0001.
      detection.score = static_cast<float>(score) * 1e-4f;
      detections.push_back(detection);
      ++found;
      impl_->restart();
    } else if (impl_->samples - impl_->utterance_start >= kRestartSamples) {
      impl_->restart();
    }
  }
  return found;
}

void PocketsphinxWakeWord::reset() {
  impl_->samples = 0;
  impl_->restart();
}

}  // namespace marvin::perception
