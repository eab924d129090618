// Aggregator: a sliding window over audio chunks of any size.
//
// Type name "Aggregator". Ports: in (AudioChunk) -> out (AudioChunk).
// Options:
//   window_ms  (int, 1..60000, default 1000)  window length
//   hop_ms     (int, 1..window_ms, default 250)  distance between window starts
//
// At sample rate r the window holds window_ms * r / 1000 samples and one is emitted every
// hop_ms * r / 1000 samples once the first window is full (the voice path uses 1000/250 ms at
// 16 kHz: 16000-sample windows every 4000 samples). Accounting is exact whatever the chunk
// sizes: a chunk may complete several windows or none, and every sample lands in exactly
// the windows that cover it. Each window is stamped with the timestamp of its *last* sample.
//
// A discontinuous input chunk (drops upstream, a reopened latch) or a change of sample rate
// restarts the window from that chunk; the first window after a restart is flagged
// discontinuous. window_ms and hop_ms must give whole numbers of samples at the rate seen;
// otherwise process() fails naming the rate.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "graph/audio_chunk.h"
#include "graph/node.h"

namespace marvin::graph {

// The windowing arithmetic on its own (no graph), so it can be tested exhaustively.
class SlidingWindow {
 public:
  SlidingWindow(std::size_t window_samples, std::size_t hop_samples);

  // Adds `n` samples. For each window completed, calls on_window(window, last_index) where
  // `window` holds the window's samples oldest first (valid during the call) and
  // `last_index` is the index, within these n samples, of the window's last sample.
  template <typename OnWindow>
  void add(const int16_t* samples, std::size_t n, OnWindow&& on_window) {
    std::size_t pos = 0;
    while (pos < n) {
      const std::size_t take = std::min<std::size_t>(n - pos, static_cast<std::size_t>(next_emit_ - total_));
      write(samples + pos, take);
      pos += take;
      total_ += take;
      if (total_ == next_emit_) {
        linearize();
        on_window(static_cast<const std::vector<int16_t>&>(out_), pos - 1);
        ++windows_;
        next_emit_ += hop_;
      }
    }
  }

  // Forgets every sample (a discontinuity).
  void reset();

  std::size_t window_samples() const { return window_; }
  std::size_t hop_samples() const { return hop_; }
  uint64_t samples_seen() const { return seen_before_reset_ + total_; }
  uint64_t windows_emitted() const { return windows_; }

 private:
  void write(const int16_t* samples, std::size_t n);
  void linearize();

  std::size_t window_, hop_;
  std::vector<int16_t> ring_;  // the last `window_` samples
  std::size_t write_pos_ = 0;
  uint64_t total_ = 0;      // samples since the last reset
  uint64_t next_emit_ = 0;  // value of total_ at which the next window completes
  uint64_t windows_ = 0, seen_before_reset_ = 0;
  std::vector<int16_t> out_;
};

class Aggregator : public Node {
 public:
  static void declare(Contract& c);
  void open(Context& ctx) override;
  void process(Context& ctx) override;

 private:
  int64_t window_ms_ = 0, hop_ms_ = 0;
  int rate_ = 0;
  bool restarted_ = false;
  std::vector<SlidingWindow> window_;  // 0 or 1 element: built at the first chunk's rate
};

}  // namespace marvin::graph
