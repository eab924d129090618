#include "graph/watchdog.h"

#include <cstdio>

namespace marvin::graph {

const char* to_string(WatchdogEventKind kind) {
  switch (kind) {
    case WatchdogEventKind::kDeadline: return "deadline";
    case WatchdogEventKind::kLatency: return "latency";
    case WatchdogEventKind::kRateLow: return "rate_low";
    case WatchdogEventKind::kRateHigh: return "rate_high";
    case WatchdogEventKind::kDrops: return "drops";
  }
  return "?";
}

namespace {

std::string ms(int64_t ns) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f ms", static_cast<double>(ns) / 1e6);
  return buf;
}

}  // namespace

Watchdog::Watchdog(const Clock& clock, EventSink sink) : clock_(clock), sink_(std::move(sink)) {}

Watchdog::~Watchdog() { stop(); }

void Watchdog::watch(std::string subject, const WatchSpec& spec, WatchPoint* point) {
  point->max_latency_ns = spec.max_latency_ns;
  Watched w;
  w.subject = std::move(subject);
  w.spec = spec;
  w.point = point;
  watched_.push_back(std::move(w));
}

void Watchdog::arm() {
  std::lock_guard lock(check_mutex_);
  const int64_t now = clock_.now_ns();
  for (Watched& w : watched_) {
    w.quiet_since_ns = now;
    w.window_start_ns = now;
    w.window_start_activity = w.point->activity.load(std::memory_order_relaxed);
  }
}

void Watchdog::emit(WatchdogEventKind kind, const Watched& w, int64_t now, uint64_t total,
                    uint64_t since_last, std::string message) {
  WatchdogEvent e;
  e.kind = kind;
  e.subject = w.subject;
  e.time_ns = now;
  e.total = total;
  e.count_since_last = since_last;
  e.message = w.subject + ": " + std::move(message) + " (" + std::to_string(since_last) +
              " since last event, " + std::to_string(total) + " in total)";
  events_.fetch_add(1, std::memory_order_relaxed);
  if (sink_) sink_(e);
}

void Watchdog::check() {
  std::lock_guard lock(check_mutex_);
  const int64_t now = clock_.now_ns();
  for (Watched& w : watched_) {
    WatchPoint& p = *w.point;
    const bool finished = p.finished.load(std::memory_order_acquire);

    // Deadline: one event per full deadline of silence.
    const int64_t last = p.last_activity_ns.load(std::memory_order_relaxed);
    if (last > w.quiet_since_ns) w.quiet_since_ns = last;
    if (w.spec.deadline_ns > 0 && !finished && now - w.quiet_since_ns > w.spec.deadline_ns) {
      ++w.deadline_total;
      emit(WatchdogEventKind::kDeadline, w, now, w.deadline_total, 1,
           "no activity for " + ms(now - w.quiet_since_ns) + " (deadline " +
               ms(w.spec.deadline_ns) + ")");
      w.quiet_since_ns = now;
    }

    // Latency and drop violations are counted on the hot path; report the new ones.
    const uint64_t late = p.latency_violations.load(std::memory_order_relaxed);
    if (late > w.latency_reported) {
      emit(WatchdogEventKind::kLatency, w, now, late, late - w.latency_reported,
           "latency above " + ms(w.spec.max_latency_ns));
      w.latency_reported = late;
    }
    const uint64_t drops = p.drop_violations.load(std::memory_order_relaxed);
    if (drops > w.drops_reported) {
      emit(WatchdogEventKind::kDrops, w, now, drops, drops - w.drops_reported,
           "too many consecutive drops");
      w.drops_reported = drops;
    }

    // Rate over each complete window.
    if ((w.spec.min_rate_hz > 0 || w.spec.max_rate_hz > 0) && w.spec.rate_window_ns > 0 &&
        now - w.window_start_ns >= w.spec.rate_window_ns) {
      const uint64_t count = p.activity.load(std::memory_order_relaxed);
      const double seconds = static_cast<double>(now - w.window_start_ns) / 1e9;
      const double rate = static_cast<double>(count - w.window_start_activity) / seconds;
      char figures[96];
      if (w.spec.min_rate_hz > 0 && rate < w.spec.min_rate_hz && !finished) {
        ++w.rate_low_total;
        std::snprintf(figures, sizeof figures, "rate %.1f/s below minimum %.1f/s", rate,
                      w.spec.min_rate_hz);
        emit(WatchdogEventKind::kRateLow, w, now, w.rate_low_total, 1, figures);
      }
      if (w.spec.max_rate_hz > 0 && rate > w.spec.max_rate_hz) {
        ++w.rate_high_total;
        std::snprintf(figures, sizeof figures, "rate %.1f/s above maximum %.1f/s", rate,
                      w.spec.max_rate_hz);
        emit(WatchdogEventKind::kRateHigh, w, now, w.rate_high_total, 1, figures);
      }
      w.window_start_ns = now;
      w.window_start_activity = count;
    }
  }
}

void Watchdog::start(std::chrono::milliseconds interval) {
  stop();
  {
    std::lock_guard lock(thread_mutex_);
    stopping_ = false;
  }
  thread_ = std::thread([this, interval] {
    std::unique_lock lock(thread_mutex_);
    while (!stopping_) {
      if (wake_.wait_for(lock, interval, [this] { return stopping_; })) break;
      lock.unlock();
      check();
      lock.lock();
    }
  });
}

void Watchdog::stop() {
  {
    std::lock_guard lock(thread_mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

}  // namespace marvin::graph
