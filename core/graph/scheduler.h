// Scheduler: the bounded pool of worker threads that runs a graph's nodes.
//
// A task (a node) is submitted when it may have work; a worker takes it from a FIFO run
// queue and calls run(). The graph guarantees a task is queued at most once at a time, so
// the queue is a fixed ring of `max_tasks` slots and submitting never allocates. Tasks can
// also ask to be woken at a point in (real, steady-clock) time; workers sleep until the
// earliest such timer when the queue is empty.
//
// Thread-safe. stop() joins the workers; queued tasks that did not run are forgotten.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <mutex>
#include <queue>
#include <thread>
#include <vector>

namespace marvin::graph {

class Task {
 public:
  // Called by a worker for a submitted task.
  virtual void run() = 0;
  // Called by a worker when a timer set with wake_at() expires.
  virtual void wake() = 0;

 protected:
  virtual ~Task() = default;
};

class Scheduler {
 public:
  // `threads` workers (at least 1); at most `max_tasks` tasks queued at once.
  Scheduler(int threads, std::size_t max_tasks);
  ~Scheduler();
  Scheduler(const Scheduler&) = delete;
  Scheduler& operator=(const Scheduler&) = delete;

  void start();
  void stop();
  void submit(Task* task);
  // Calls task->wake() at steady-clock time `when_ns` (or soon after).
  void wake_at(Task* task, int64_t when_ns);

  int threads() const { return threads_; }
  // 0-based index of the calling worker thread, -1 on other threads.
  static int worker_index();

 private:
  void work(int index);

  const int threads_;
  std::mutex mutex_;
  std::condition_variable ready_;
  std::vector<Task*> ring_;
  std::size_t head_ = 0, count_ = 0;
  struct Timer {
    int64_t when_ns;
    Task* task;
    bool operator>(const Timer& o) const { return when_ns > o.when_ns; }
  };
  std::priority_queue<Timer, std::vector<Timer>, std::greater<>> timers_;
  int sleeping_ = 0;
  bool stopping_ = false;
  std::vector<std::thread> workers_;
};

}  // namespace marvin::graph
