#include "graph/builtin_nodes.h"

#include <chrono>
#include <cmath>
#include <numbers>

#include "graph/aggregator.h"
#include "graph/audio_chunk.h"
#include "graph/latch.h"

namespace marvin::graph {
namespace {

int64_t steady_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

// Keeps a source's stream time in step with real time scaled by `pace`.
class Pacer {
 public:
  void configure(double pace) { pace_ = pace; }
  // Asks to be called again when stream time `next_us` is due; no-op when unpaced.
  void wait_for(Context& ctx, Timestamp next_us) {
    if (pace_ <= 0) return;
    if (start_ns_ == 0) start_ns_ = steady_ns();
    const auto due = start_ns_ + static_cast<int64_t>(static_cast<double>(next_us) * 1000.0 / pace_);
    const int64_t now = steady_ns();
    if (due > now) ctx.wake_after(std::chrono::nanoseconds(due - now));
  }

 private:
  double pace_ = 0;
  int64_t start_ns_ = 0;
};

class SyntheticAudioSource : public Node {
 public:
  static void declare(Contract& c) {
    c.option_int("sample_rate", 16000, 1000, 192000);
    c.option_int("chunk_samples", 320, 1, 1 << 20);
    c.option_int("duration_ms", 2000, 0, INT64_MAX / 1'000'000);
    c.option_double("pace", 1.0, 0, 1000);
    c.option_string("waveform", "sine", {"sine", "ramp"});
    c.option_double("frequency_hz", 440, 0, 96000);
    c.option_int("amplitude", 8000, 0, 32767);
    c.add_output<AudioChunk>("out");
  }
  void open(Context& ctx) override {
    const Options& o = ctx.options();
    rate_ = static_cast<int>(o.get_int("sample_rate"));
    chunk_ = o.get_int("chunk_samples");
    total_ = o.get_int("duration_ms") * rate_ / 1000;
    ramp_ = o.get_string("waveform") == "ramp";
    step_ = 2 * std::numbers::pi * o.get_double("frequency_hz") / rate_;
    amplitude_ = static_cast<double>(o.get_int("amplitude"));
    pacer_.configure(o.get_double("pace"));
  }
  void process(Context& ctx) override {
    if (total_ > 0 && next_ >= total_) {
      ctx.finish();
      return;
    }
    const int64_t n = total_ > 0 ? std::min(chunk_, total_ - next_) : chunk_;
    AudioChunk out;
    out.sample_rate = rate_;
    out.samples.resize(static_cast<std::size_t>(n));
    for (int64_t i = 0; i < n; ++i) {
      const int64_t k = next_ + i;
      out.samples[static_cast<std::size_t>(i)] =
          ramp_ ? static_cast<int16_t>(k % 32768)
                : static_cast<int16_t>(std::lround(amplitude_ * std::sin(step_ * static_cast<double>(k))));
    }
    ctx.emit(0, Packet::make<AudioChunk>(std::move(out)).at(sample_timestamp(0, next_, rate_)));
    next_ += n;
    pacer_.wait_for(ctx, sample_timestamp(0, next_, rate_));
  }

 private:
  int rate_ = 0;
  int64_t chunk_ = 0, total_ = 0, next_ = 0;
  bool ramp_ = false;
  double step_ = 0, amplitude_ = 0;
  Pacer pacer_;
};

class ToggleSource : public AttentionNode {
 public:
  static void declare(Contract& c) {
    c.option_int("period_ms", 500, 1, INT64_MAX / 1000);
    c.option_int("tick_ms", 50, 1, INT64_MAX / 1000);
    c.option_int("duration_ms", 2000, 0, INT64_MAX / 1000);
    c.option_double("pace", 1.0, 0, 1000);
    c.option_bool("start_open", true);
    add_state_output(c, "out");
  }
  void open(Context& ctx) override {
    const Options& o = ctx.options();
    period_us_ = o.get_int("period_ms") * 1000;
    tick_us_ = o.get_int("tick_ms") * 1000;
    duration_us_ = o.get_int("duration_ms") * 1000;
    start_open_ = o.get_bool("start_open");
    pacer_.configure(o.get_double("pace"));
  }
  void process(Context& ctx) override {
    if (duration_us_ > 0 && now_us_ >= duration_us_) {
      ctx.finish();
      return;
    }
    const bool flipped = (now_us_ / period_us_) % 2 == 1;
    set_state(ctx, 0, start_open_ != flipped, now_us_);
    now_us_ += tick_us_;
    pacer_.wait_for(ctx, now_us_);
  }

 private:
  int64_t period_us_ = 0, tick_us_ = 0, duration_us_ = 0, now_us_ = 0;
  bool start_open_ = true;
  Pacer pacer_;
};

class CounterSource : public Node {
 public:
  static void declare(Contract& c) {
    c.option_int("count", 0, 0);
    c.option_int("interval_us", 0, 0, INT64_MAX / 1'000'000);
    c.add_output<int64_t>("out");
  }
  void open(Context& ctx) override {
    count_ = ctx.options().get_int("count");
    interval_us_ = ctx.options().get_int("interval_us");
    pacer_.configure(interval_us_ > 0 ? 1.0 : 0.0);
  }
  void process(Context& ctx) override {
    if (count_ > 0 && next_ >= count_) {
      ctx.finish();
      return;
    }
    ctx.emit(0, Packet::make<int64_t>(next_).at(next_));
    ++next_;
    pacer_.wait_for(ctx, next_ * interval_us_);
  }

 private:
  int64_t count_ = 0, interval_us_ = 0, next_ = 0;
  Pacer pacer_;
};

class PassThrough : public Node {
 public:
  static void declare(Contract& c) {
    c.add_input("in", "any");
    c.add_output("out", "same_as:in");
  }
  void process(Context& ctx) override { ctx.emit(0, ctx.take_input(0)); }
};

class Sink : public Node {
 public:
  static void declare(Contract& c) { c.add_input("in", "any"); }
  void process(Context& ctx) override { (void)ctx; }
};

}  // namespace

void GraphInputNode::declare(Contract& c) {
  c.add_output("out", c.option_string("type", "any"));
}

void GraphInputNode::enqueue(Packet packet) {
  std::lock_guard lock(mutex_);
  queue_.push_back(std::move(packet));
}

void GraphInputNode::close_input() {
  std::lock_guard lock(mutex_);
  closed_ = true;
}

void GraphInputNode::process(Context& ctx) {
  Packet p;
  {
    std::lock_guard lock(mutex_);
    if (queue_.empty()) {
      if (closed_) {
        ctx.finish();
      } else {
        ctx.sleep_until_woken();
      }
      return;
    }
    p = std::move(queue_.front());
    queue_.pop_front();
  }
  ctx.emit(0, std::move(p));
}

void WatchdogEventsNode::declare(Contract& c) {
  c.add_output<WatchdogEvent>("events");
  c.set_daemon();
}

void WatchdogEventsNode::enqueue(const WatchdogEvent& event) {
  std::lock_guard lock(mutex_);
  queue_.push_back(event);
}

void WatchdogEventsNode::process(Context& ctx) {
  WatchdogEvent e;
  {
    std::lock_guard lock(mutex_);
    if (queue_.empty()) {
      ctx.sleep_until_woken();
      return;
    }
    e = std::move(queue_.front());
    queue_.pop_front();
  }
  // Stamped in microseconds of the graph clock, kept strictly increasing.
  last_ = std::max(last_ + 1, e.time_ns / 1000);
  ctx.emit(0, Packet::make<WatchdogEvent>(std::move(e)).at(last_));
}

namespace detail {

template <typename N>
void add(NodeRegistry& r, const char* name) {
  r.add({name, &N::declare, []() -> std::unique_ptr<Node> { return std::make_unique<N>(); }});
}

void register_builtin_nodes(NodeRegistry& r) {
  add<Aggregator>(r, "Aggregator");
  add<CounterSource>(r, "CounterSource");
  add<GraphInputNode>(r, "GraphInput");
  add<Latch>(r, "Latch");
  add<PassThrough>(r, "PassThrough");
  add<Sink>(r, "Sink");
  add<SyntheticAudioSource>(r, "SyntheticAudioSource");
  add<ToggleSource>(r, "ToggleSource");
  add<WatchdogEventsNode>(r, "WatchdogEvents");
}

}  // namespace detail
}  // namespace marvin::graph
