#include "graph/latch.h"

namespace marvin::graph {

void Latch::declare(Contract& c) {
  const int64_t channels = c.option_int("channels", 1, 1, 16);
  c.option_bool("start_open", false);
  c.add_input<bool>("control");
  for (int64_t i = 0; i < channels; ++i) {
    const std::string n = std::to_string(i);
    c.add_input("in" + n, "any");
    c.add_output("out" + n, "same_as:in" + n);
  }
}

void Latch::open(Context& ctx) {
  open_ = ctx.options().get_bool("start_open");
  reopened_.assign(static_cast<std::size_t>(ctx.options().get_int("channels")), false);
}

void Latch::process(Context& ctx) {
  if (ctx.has_input(kControl)) {
    const bool now_open = ctx.input(kControl).get<bool>();
    if (now_open && !open_) reopened_.assign(reopened_.size(), true);
    open_ = now_open;
  }
  if (!open_) return;  // nothing passes; the framework still advances our bounds
  for (std::size_t ch = 0; ch < reopened_.size(); ++ch) {
    const int in = static_cast<int>(ch) + 1;
    if (!ctx.has_input(in)) continue;
    Packet p = ctx.take_input(in);
    if (reopened_[ch]) {
      p.set_discontinuous(true);
      reopened_[ch] = false;
    }
    ctx.emit(static_cast<int>(ch), std::move(p));
  }
}

}  // namespace marvin::graph
