#include "graph/stream.h"

#include <bit>
#include <utility>

namespace marvin::graph {

const char* to_string(StreamPolicy policy) {
  switch (policy) {
    case StreamPolicy::kLossless: return "lossless";
    case StreamPolicy::kDropOldest: return "drop_oldest";
    case StreamPolicy::kDropNewest: return "drop_newest";
  }
  return "?";
}

Stream::Stream(std::string name, StreamOptions options, const Clock& clock)
    : name_(std::move(name)), options_(options), clock_(clock) {
  if (options_.capacity == 0) throw std::invalid_argument("stream " + name_ + ": capacity must be at least 1");
  ring_.resize(std::bit_ceil(options_.capacity + 1));
}

void Stream::connect(Wakeable* producer, Wakeable* consumer) {
  producer_ = producer;
  consumer_ = consumer;
}

void Stream::grow() {
  std::vector<Entry> bigger(ring_.size() * 2);
  for (std::size_t i = 0; i < count_; ++i) {
    bigger[i] = std::move(ring_[(head_ + i) & (ring_.size() - 1)]);
  }
  ring_ = std::move(bigger);
  head_ = 0;
}

bool Stream::push(Packet packet, int64_t now) {
  watch_.record_activity(now);
  pushed_.add();
  bool accepted = true;
  Packet dropped;  // released outside the lock
  {
    std::lock_guard lock(mutex_);
    const std::size_t mask = ring_.size() - 1;
    const Timestamp ts = packet.timestamp();
    if (options_.policy != StreamPolicy::kLossless && count_ >= options_.capacity) {
      dropped_.add();
      ++consecutive_drops_;
      if (options_.max_consecutive_drops > 0 &&
          consecutive_drops_ == options_.max_consecutive_drops + 1) {
        watch_.drop_violations.fetch_add(1, std::memory_order_relaxed);
      }
      if (options_.policy == StreamPolicy::kDropNewest) {
        flag_next_push_ = true;
        accepted = false;
        dropped = std::move(packet);
      } else {
        dropped = std::move(ring_[head_].packet);
        head_ = (head_ + 1) & mask;
        --count_;
        // The gap lies between what the consumer saw last and the new front.
        if (count_ > 0) {
          ring_[head_].packet.set_discontinuous(true);
        } else {
          packet.set_discontinuous(true);
        }
      }
    }
    if (accepted) {
      if (count_ == ring_.size() - 1) grow();
      if (flag_next_push_) {
        packet.set_discontinuous(true);
        flag_next_push_ = false;
      }
      Entry& e = ring_[(head_ + count_) & (ring_.size() - 1)];
      e.packet = std::move(packet);
      e.queued_ns = now;
      ++count_;
      size_.store(count_, std::memory_order_release);
      high_water_.raise_to(count_);
    }
    if (ts != kTimestampUnset && ts + 1 > bound_) bound_ = ts + 1;
  }
  if (consumer_) consumer_->wake();
  return accepted;
}

void Stream::advance_bound(Timestamp next) {
  {
    std::lock_guard lock(mutex_);
    if (next <= bound_) return;
    bound_ = next;
  }
  if (consumer_) consumer_->wake();
}

Stream::Head Stream::head() const {
  Head h;
  std::lock_guard lock(mutex_);
  h.bound = bound_;
  if (count_ > 0) {
    h.has_packet = true;
    h.front = ring_[head_].packet.timestamp();
  }
  return h;
}

void Stream::pop_locked(Packet& out, int64_t& queued_ns, bool& was_full) {
  was_full = count_ >= options_.capacity;
  Entry& e = ring_[head_];
  out = std::move(e.packet);
  queued_ns = e.queued_ns;
  head_ = (head_ + 1) & (ring_.size() - 1);
  --count_;
  consecutive_drops_ = 0;
  size_.store(count_, std::memory_order_release);
}

void Stream::account_take(int64_t now_ns, int64_t queued_ns, bool was_full) {
  const int64_t latency = now_ns - queued_ns;
  latency_.record(latency);
  watch_.record_latency(latency);
  delivered_.add();
  if (was_full && producer_ && options_.policy == StreamPolicy::kLossless) producer_->wake();
}

Packet Stream::take(int64_t now_ns) {
  Packet out;
  bool was_full = false;
  int64_t queued_ns = 0;
  {
    std::lock_guard lock(mutex_);
    if (count_ == 0) return out;
    pop_locked(out, queued_ns, was_full);
  }
  account_take(now_ns, queued_ns, was_full);
  return out;
}

Stream::Head Stream::poll(Packet& out, int64_t now_ns) {
  Head h;
  bool was_full = false;
  int64_t queued_ns = 0;
  {
    std::lock_guard lock(mutex_);
    h.bound = bound_;
    if (count_ == 0) return h;
    h.has_packet = true;
    h.front = ring_[head_].packet.timestamp();
    pop_locked(out, queued_ns, was_full);
  }
  account_take(now_ns, queued_ns, was_full);
  return h;
}

void Stream::clear() {
  std::lock_guard lock(mutex_);
  while (count_ > 0) {
    ring_[head_].packet = Packet();
    head_ = (head_ + 1) & (ring_.size() - 1);
    --count_;
  }
  size_.store(0, std::memory_order_release);
}

StreamStats Stream::stats() const {
  StreamStats s;
  s.name = name_;
  s.policy = to_string(options_.policy);
  s.capacity = options_.capacity;
  s.pushed = pushed_.get();
  s.delivered = delivered_.get();
  s.dropped = dropped_.get();
  s.high_water = high_water_.get();
  s.latency_p50_ns = latency_.quantile(0.50);
  s.latency_p99_ns = latency_.quantile(0.99);
  return s;
}

}  // namespace marvin::graph
