#include "graph/scheduler.h"

#include <chrono>
#include <stdexcept>

namespace marvin::graph {
namespace {

thread_local int t_worker_index = -1;

int64_t steady_now_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

}  // namespace

Scheduler::Scheduler(int threads, std::size_t max_tasks)
    : threads_(threads < 1 ? 1 : threads), ring_(max_tasks < 1 ? 1 : max_tasks) {}

Scheduler::~Scheduler() { stop(); }

int Scheduler::worker_index() { return t_worker_index; }

void Scheduler::start() {
  std::lock_guard lock(mutex_);
  if (!workers_.empty()) return;
  stopping_ = false;
  for (int i = 0; i < threads_; ++i) workers_.emplace_back([this, i] { work(i); });
}

void Scheduler::stop() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  ready_.notify_all();
  for (std::thread& t : workers_) t.join();
  workers_.clear();
  std::lock_guard lock(mutex_);
  head_ = count_ = 0;
  timers_ = {};
}

void Scheduler::submit(Task* task) {
  bool notify = false;
  {
    std::lock_guard lock(mutex_);
    if (count_ == ring_.size()) throw std::logic_error("scheduler: run queue overflow");
    ring_[(head_ + count_) % ring_.size()] = task;
    ++count_;
    notify = sleeping_ > 0;
  }
  if (notify) ready_.notify_one();
}

void Scheduler::wake_at(Task* task, int64_t when_ns) {
  {
    std::lock_guard lock(mutex_);
    timers_.push({when_ns, task});
  }
  // A sleeping worker may be waiting for a later timer; let one re-evaluate.
  ready_.notify_one();
}

void Scheduler::work(int index) {
  t_worker_index = index;
  std::unique_lock lock(mutex_);
  while (!stopping_) {
    if (!timers_.empty() && timers_.top().when_ns <= steady_now_ns()) {
      Task* t = timers_.top().task;
      timers_.pop();
      lock.unlock();
      t->wake();
      lock.lock();
      continue;
    }
    if (count_ > 0) {
      Task* t = ring_[head_];
      head_ = (head_ + 1) % ring_.size();
      --count_;
      lock.unlock();
      t->run();
      lock.lock();
      continue;
    }
    ++sleeping_;
    if (timers_.empty()) {
      ready_.wait(lock);
    } else {
      const auto when = std::chrono::steady_clock::time_point(
          std::chrono::nanoseconds(timers_.top().when_ns));
      ready_.wait_until(lock, when);
    }
    --sleeping_;
  }
}

}  // namespace marvin::graph
