// AttentionNode: base for nodes whose outputs are state bits ("someone is speaking", "the
// wake word was heard", "a face is in view").
//
// A state output carries `bool` packets, and only when the state *changes* (plus once for the
// initial state): consumers such as a Latch see edges, not a flood of repeated values. When
// the state does not change, set_state() still advances the output's timestamp bound, so
// consumers synchronised on it know the state holds up to that time and never stall.
//
// Subclasses declare state outputs with add_state_output() in their declare() and call
// set_state() from process(). Same threading rules as any node (node.h).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "graph/node.h"

namespace marvin::graph {

class AttentionNode : public Node {
 public:
  // Last state set on `port`; false before the first set_state().
  bool state(int port) const {
    return static_cast<std::size_t>(port) < states_.size() && states_[static_cast<std::size_t>(port)] == 1;
  }

 protected:
  // Declares a boolean state output named `name`; returns its port index.
  static int add_state_output(Contract& c, std::string name) {
    return c.add_output<bool>(std::move(name));
  }

  // Sets state bit `port` as of timestamp `ts` (default: the input timestamp). Emits a packet
  // if the value differs from the last one emitted (or none was); otherwise advances the bound.
  void set_state(Context& ctx, int port, bool value, Timestamp ts = kTimestampUnset);

 private:
  std::vector<int8_t> states_;  // per port: -1 none yet, 0, 1
};

}  // namespace marvin::graph
