// Latch: a boolean control input opens and closes the flow of one or more data streams
// (the wake-word spotter opens the speech recognizer's input).
//
// Type name "Latch". Ports:
//   control        bool; true opens, false closes, as of the packet's timestamp
//   in0..in<N-1>   any type; data
//   out0..out<N-1> same type as the matching input; data passed while open
// Options:
//   channels    (int, 1..16, default 1)   number of gated data streams
//   start_open  (bool, default false)     state before the first control packet
//
// With the default synchronized input policy, data at timestamp t is gated by the last
// control packet at or before t (control is applied first at equal timestamps). While closed
// nothing is emitted but the outputs' bounds still advance (see node.h), so a node that
// joins a gated stream with another one keeps running. The first packet passed on each
// channel after the latch reopens is flagged discontinuous, so windowing nodes downstream
// (Aggregator) restart cleanly.
#pragma once

#include <vector>

#include "graph/node.h"

namespace marvin::graph {

class Latch : public Node {
 public:
  static constexpr int kControl = 0;  // input index; data input i is port i + 1
  static void declare(Contract& c);
  void open(Context& ctx) override;
  void process(Context& ctx) override;
  bool is_open() const { return open_; }

 private:
  bool open_ = false;
  std::vector<bool> reopened_;  // per channel: flag the next packet discontinuous
};

}  // namespace marvin::graph
