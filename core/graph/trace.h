// TraceRecorder: node spans for the Chrome trace viewer (chrome://tracing, Perfetto).
//
// When a graph runs with tracing on, every process() call is recorded as a span (node,
// worker thread, start, duration) into a buffer per worker, preallocated so recording never
// allocates. When a buffer is full further spans are counted, not kept. write_chrome_trace()
// produces the "Trace Event Format" JSON: one complete ("ph":"X") event per span, one row per
// worker thread.
//
// record() may be called concurrently for different workers (each worker owns its buffer);
// write_chrome_trace() must not run concurrently with record().
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace marvin::graph {

class TraceRecorder {
 public:
  TraceRecorder(int workers, std::size_t max_spans_per_worker);

  // `worker` out of range (a non-worker thread) is ignored.
  void record(int worker, int node, int64_t start_ns, int64_t duration_ns);

  // Writes the trace; `node_names[i]` names node i. Throws std::runtime_error if the file
  // cannot be written.
  void write_chrome_trace(const std::string& path, const std::vector<std::string>& node_names) const;

  std::size_t spans() const;
  std::size_t lost_spans() const;

 private:
  struct Span {
    int node;
    int64_t start_ns;
    int64_t duration_ns;
  };
  struct Buffer {
    std::vector<Span> spans;
    std::size_t lost = 0;
  };
  std::size_t capacity_;
  std::vector<Buffer> buffers_;
};

}  // namespace marvin::graph
