#include "perception/endpointer.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace marvin::perception {

const char* to_string(EndpointState state) {
  switch (state) {
    case EndpointState::kWaitingForSpeech: return "waiting";
    case EndpointState::kInSpeech: return "in speech";
    case EndpointState::kEnded: return "ended";
    case EndpointState::kTimedOut: return "timed out";
  }
  return "?";
}

Endpointer::Endpointer(const EndpointerOptions& options)
    : options_(options), frame_samples_(options.sample_rate / 100) {
  if (frame_samples_ <= 0 || frame_samples_ > static_cast<int>(frame_.size())) {
    throw std::invalid_argument("EndpointerOptions: sample_rate must be in 100..48000");
  }
  reset();
}

void Endpointer::reset() {
  filled_ = 0;
  state_ = EndpointState::kWaitingForSpeech;
  samples_seen_ = speech_begin_ = speech_end_ = 0;
  noise_db_ = options_.min_speech_db - options_.margin_db;
  speech_run_ = silence_run_ = frames_total_ = frames_in_speech_ = 0;
}

EndpointState Endpointer::push(std::span<const std::int16_t> samples) {
  for (std::int16_t s : samples) {
    if (state_ == EndpointState::kEnded || state_ == EndpointState::kTimedOut) break;
    ++samples_seen_;
    frame_[filled_++] = s;
    if (filled_ == frame_samples_) {
      double sum = 0.0;
      for (int i = 0; i < frame_samples_; ++i) {
        const double v = frame_[i] / 32768.0;
        sum += v * v;
      }
      filled_ = 0;
      on_frame(static_cast<float>(10.0 * std::log10(sum / frame_samples_ + 1e-12)));
    }
  }
  return state_;
}

void Endpointer::on_frame(float energy_db) {
  ++frames_total_;
  const bool speech = energy_db > std::max(options_.min_speech_db, noise_db_ + options_.margin_db);
  if (!speech) {
    // The floor follows the background slowly, and never from speech frames.
    noise_db_ = 0.95f * noise_db_ + 0.05f * std::max(energy_db, -90.0f);
  }
  const int start_frames = std::max(1, options_.speech_start_ms / 10);
  const int end_frames = std::max(1, options_.trailing_silence_ms / 10);
  switch (state_) {
    case EndpointState::kWaitingForSpeech:
      speech_run_ = speech ? speech_run_ + 1 : 0;
      if (speech_run_ >= start_frames) {
        state_ = EndpointState::kInSpeech;
        speech_begin_ = samples_seen_ - static_cast<std::int64_t>(speech_run_) * frame_samples_;
        speech_end_ = samples_seen_;
        frames_in_speech_ = speech_run_;
        silence_run_ = 0;
      } else if (frames_total_ * 10 >= options_.no_speech_timeout_ms) {
        state_ = EndpointState::kTimedOut;
      }
      break;
    case EndpointState::kInSpeech:
      ++frames_in_speech_;
      if (speech) {
        silence_run_ = 0;
        speech_end_ = samples_seen_;
      } else if (++silence_run_ >= end_frames) {
        state_ = EndpointState::kEnded;
      }
      if (frames_in_speech_ * 10 >= options_.max_speech_ms) state_ = EndpointState::kEnded;
      break;
    case EndpointState::kEnded:
    case EndpointState::kTimedOut:
      break;
  }
}

}  // namespace marvin::perception
