#include "graph/stats.h"

#include <cstdio>

namespace marvin::graph {

uint64_t LatencyHistogram::upper_edge(std::size_t index) {
  if (index < 8) return index;
  const std::size_t e = (index - 8) / 8 + 3;
  const uint64_t sub = (index - 8) % 8;
  return ((8 + sub + 1) << (e - 3)) - 1;
}

uint64_t LatencyHistogram::count() const {
  uint64_t total = 0;
  for (const auto& bin : bins_) total += bin.load(std::memory_order_relaxed);
  return total;
}

int64_t LatencyHistogram::quantile(double q) const {
  const uint64_t total = count();
  if (total == 0) return 0;
  // Rank of the wanted sample, 1-based: ceil(q * total), at least 1.
  auto rank = static_cast<uint64_t>(q * static_cast<double>(total));
  if (static_cast<double>(rank) < q * static_cast<double>(total)) ++rank;
  if (rank == 0) rank = 1;
  uint64_t seen = 0;
  for (std::size_t i = 0; i < kBins; ++i) {
    seen += bins_[i].load(std::memory_order_relaxed);
    if (seen >= rank) return static_cast<int64_t>(upper_edge(i));
  }
  return static_cast<int64_t>(upper_edge(kBins - 1));
}

namespace {

std::string duration(int64_t ns) {
  char buf[32];
  if (ns < 10'000) {
    std::snprintf(buf, sizeof buf, "%lld ns", static_cast<long long>(ns));
  } else if (ns < 10'000'000) {
    std::snprintf(buf, sizeof buf, "%.1f us", static_cast<double>(ns) / 1e3);
  } else {
    std::snprintf(buf, sizeof buf, "%.1f ms", static_cast<double>(ns) / 1e6);
  }
  return buf;
}

}  // namespace

std::string GraphStats::to_text() const {
  std::string out;
  char line[512];
  std::snprintf(line, sizeof line, "%-24s %-22s %10s %10s %11s %11s\n", "node", "type", "calls",
                "emitted", "proc p50", "proc p99");
  out += line;
  for (const NodeStats& n : nodes) {
    std::snprintf(line, sizeof line, "%-24s %-22s %10llu %10llu %11s %11s\n", n.name.c_str(),
                  n.type.c_str(), static_cast<unsigned long long>(n.process_calls),
                  static_cast<unsigned long long>(n.emitted), duration(n.process_p50_ns).c_str(),
                  duration(n.process_p99_ns).c_str());
    out += line;
  }
  out += "\n";
  std::snprintf(line, sizeof line, "%-40s %-12s %5s %10s %10s %8s %5s %11s %11s\n", "stream",
                "policy", "cap", "pushed", "delivered", "dropped", "hwm", "queue p50",
                "queue p99");
  out += line;
  for (const StreamStats& s : streams) {
    std::snprintf(line, sizeof line, "%-40s %-12s %5llu %10llu %10llu %8llu %5llu %11s %11s\n",
                  s.name.c_str(), s.policy.c_str(), static_cast<unsigned long long>(s.capacity),
                  static_cast<unsigned long long>(s.pushed),
                  static_cast<unsigned long long>(s.delivered),
                  static_cast<unsigned long long>(s.dropped),
                  static_cast<unsigned long long>(s.high_water),
                  duration(s.latency_p50_ns).c_str(), duration(s.latency_p99_ns).c_str());
    out += line;
  }
  std::snprintf(line, sizeof line, "\nwatchdog events: %llu\n",
                static_cast<unsigned long long>(watchdog_events));
  out += line;
  return out;
}

}  // namespace marvin::graph
