#include "graph/attention_node.h"

namespace marvin::graph {

void AttentionNode::set_state(Context& ctx, int port, bool value, Timestamp ts) {
  if (ts == kTimestampUnset) ts = ctx.input_timestamp();
  const auto index = static_cast<std::size_t>(port);
  if (states_.size() <= index) states_.resize(index + 1, -1);
  const int8_t next = value ? 1 : 0;
  if (states_[index] == next) {
    ctx.set_bound(port, ts + 1);
    return;
  }
  states_[index] = next;
  ctx.emit(port, Packet::make<bool>(value).at(ts));
}

}  // namespace marvin::graph
