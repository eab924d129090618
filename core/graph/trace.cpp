#include "graph/trace.h"

#include <algorithm>
#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>
#include <stdexcept>

namespace marvin::graph {

TraceRecorder::TraceRecorder(int workers, std::size_t max_spans_per_worker)
    : capacity_(max_spans_per_worker), buffers_(static_cast<std::size_t>(std::max(workers, 1))) {
  for (Buffer& b : buffers_) b.spans.reserve(capacity_);
}

void TraceRecorder::record(int worker, int node, int64_t start_ns, int64_t duration_ns) {
  if (worker < 0 || static_cast<std::size_t>(worker) >= buffers_.size()) return;
  Buffer& b = buffers_[static_cast<std::size_t>(worker)];
  if (b.spans.size() == capacity_) {
    ++b.lost;
    return;
  }
  b.spans.push_back({node, start_ns, duration_ns});
}

std::size_t TraceRecorder::spans() const {
  std::size_t n = 0;
  for (const Buffer& b : buffers_) n += b.spans.size();
  return n;
}

std::size_t TraceRecorder::lost_spans() const {
  std::size_t n = 0;
  for (const Buffer& b : buffers_) n += b.lost;
  return n;
}

void TraceRecorder::write_chrome_trace(const std::string& path,
                                       const std::vector<std::string>& node_names) const {
  std::unique_ptr<FILE, int (*)(FILE*)> f(std::fopen(path.c_str(), "w"), &std::fclose);
  if (!f) throw std::runtime_error(path + ": cannot write the trace file");
  // Timestamps in the format are microseconds; start at the first span for readability.
  int64_t origin = INT64_MAX;
  for (const Buffer& b : buffers_) {
    for (const Span& s : b.spans) origin = std::min(origin, s.start_ns);
  }
  std::fputs("{\"displayTimeUnit\":\"ns\",\"traceEvents\":[\n", f.get());
  bool first = true;
  for (std::size_t w = 0; w < buffers_.size(); ++w) {
    std::fprintf(f.get(),
                 "%s{\"name\":\"thread_name\",\"ph\":\"M\",\"pid\":1,\"tid\":%zu,"
                 "\"args\":{\"name\":\"graph worker %zu\"}}",
                 first ? "" : ",\n", w, w);
    first = false;
  }
  for (std::size_t w = 0; w < buffers_.size(); ++w) {
    for (const Span& s : buffers_[w].spans) {
      const std::string name =
          s.node >= 0 && static_cast<std::size_t>(s.node) < node_names.size()
              ? nlohmann::json(node_names[static_cast<std::size_t>(s.node)]).dump()
              : "\"?\"";
      std::fprintf(f.get(),
                   ",\n{\"name\":%s,\"cat\":\"process\",\"ph\":\"X\",\"pid\":1,\"tid\":%zu,"
                   "\"ts\":%.3f,\"dur\":%.3f}",
                   name.c_str(), w, static_cast<double>(s.start_ns - origin) / 1e3,
                   static_cast<double>(s.duration_ns) / 1e3);
    }
  }
  std::fputs("\n]}\n", f.get());
  if (std::ferror(f.get())) throw std::runtime_error(path + ": error writing the trace file");
}

}  // namespace marvin::graph
