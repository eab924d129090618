#include "graph/aggregator.h"

#include <algorithm>
#include <cstring>
#include <stdexcept>

namespace marvin::graph {

SlidingWindow::SlidingWindow(std::size_t window_samples, std::size_t hop_samples)
    : window_(window_samples), hop_(hop_samples), ring_(window_samples), next_emit_(window_samples),
      out_(window_samples) {
  if (window_ == 0 || hop_ == 0) throw std::invalid_argument("window and hop must be at least one sample");
}

void SlidingWindow::write(const int16_t* samples, std::size_t n) {
  // Only the last window_ samples of a long run matter.
  if (n > window_) {
    samples += n - window_;
    write_pos_ = (write_pos_ + (n - window_)) % window_;
    n = window_;
  }
  const std::size_t first = std::min(n, window_ - write_pos_);
  std::memcpy(ring_.data() + write_pos_, samples, first * sizeof(int16_t));
  std::memcpy(ring_.data(), samples + first, (n - first) * sizeof(int16_t));
  write_pos_ = (write_pos_ + n) % window_;
}

void SlidingWindow::linearize() {
  // Oldest sample is at write_pos_ once the ring is full.
  const std::size_t tail = window_ - write_pos_;
  std::memcpy(out_.data(), ring_.data() + write_pos_, tail * sizeof(int16_t));
  std::memcpy(out_.data() + tail, ring_.data(), write_pos_ * sizeof(int16_t));
}

void SlidingWindow::reset() {
  seen_before_reset_ += total_;
  total_ = 0;
  write_pos_ = 0;
  next_emit_ = window_;
}

void Aggregator::declare(Contract& c) {
  const int64_t window = c.option_int("window_ms", 1000, 1, 60000);
  c.option_int("hop_ms", 250, 1, window);
  c.add_input<AudioChunk>("in");
  c.add_output<AudioChunk>("out");
}

void Aggregator::open(Context& ctx) {
  window_ms_ = ctx.options().get_int("window_ms");
  hop_ms_ = ctx.options().get_int("hop_ms");
}

void Aggregator::process(Context& ctx) {
  const Packet& in = ctx.input(0);
  const AudioChunk& chunk = in.get<AudioChunk>();
  if (chunk.sample_rate <= 0) throw std::runtime_error("chunk has sample rate " + std::to_string(chunk.sample_rate));
  if (window_.empty() || chunk.sample_rate != rate_) {
    const int64_t r = chunk.sample_rate;
    if ((window_ms_ * r) % 1000 != 0 || (hop_ms_ * r) % 1000 != 0) {
      throw std::runtime_error("window_ms " + std::to_string(window_ms_) + " / hop_ms " +
                               std::to_string(hop_ms_) + " are not whole numbers of samples at " +
                               std::to_string(r) + " Hz");
    }
    window_.clear();
    window_.emplace_back(static_cast<std::size_t>(window_ms_ * r / 1000),
                         static_cast<std::size_t>(hop_ms_ * r / 1000));
    restarted_ = rate_ != 0;
    rate_ = chunk.sample_rate;
  } else if (in.discontinuous()) {
    window_.front().reset();
    restarted_ = true;
  }
  const Timestamp start = in.timestamp();
  window_.front().add(chunk.samples.data(), chunk.samples.size(),
                      [&](const std::vector<int16_t>& samples, std::size_t last) {
                        AudioChunk out;
                        out.sample_rate = rate_;
                        out.samples = samples;
                        Packet p = Packet::make<AudioChunk>(std::move(out))
                                       .at(sample_timestamp(start, static_cast<int64_t>(last), rate_));
                        p.set_discontinuous(restarted_);
                        restarted_ = false;
                        ctx.emit(0, std::move(p));
                      });
}

}  // namespace marvin::graph
