// The host loop: the user's utterances arrive here one by one (typed lines in
// `marvin run --sim`, recognised speech later) and go to the skill manager, or to the
// question a skill is waiting on.
//
// post() may be called from any thread (the console reader); run() is the loop and owns
// the thread that calls Manager::handle(). Utterances are taken in order; each one goes:
//   - "stop": to the manager at once (it cancels whatever runs);
//   - a request of an "urgent" intent (a call for help) while a task runs or asks: the task
//     is stopped as by "stop", then the request is handled;
//   - while a long task runs: held until the task asks a question (the utterance is the
//     answer) or ends (the utterance starts the next conversation). A "stop" queued behind
//     a held utterance is taken first: stop always wins;
//   - otherwise: Manager::handle().
// Questions asked on the loop thread itself (slot filling, a short skill's ask) take the
// next utterance directly; "stop" there cancels through Manager::stop() and the question
// returns no answer. After a "stop", every further question of that conversation returns
// no answer at once, until the next conversation starts.
//
// HostLoop is the User of the manager: say() hands sentences to `speak` (serialised), ask()
// says the question and waits as described. At end of input (close()), pending and later
// questions return no answer and run() returns once the running task has finished.
// shut_down() (SIGINT, SIGTERM) is the end of input without waiting: utterances not yet
// taken are dropped, the running task is stopped as by "stop", and run() returns once it
// has ended.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "interpret/interpreter.h"
#include "skills/manager.h"
#include "skills/user.h"

namespace marvin::skills {

class HostLoop : public User {
 public:
  // `speak` receives each sentence; it is never called on two threads at once.
  explicit HostLoop(std::function<void(std::string_view)> speak);

  // Connects the loop to the manager it feeds (the manager's User must be this loop).
  void attach(Manager& manager, const interpret::Interpreter& interpreter);
  // Called on the loop thread with each utterance as it is taken (the console echoes
  // piped input with it). Set before run().
  void on_heard(std::function<void(std::string_view)> heard) { heard_ = std::move(heard); }
  // Called when the loop starts waiting for the user with no utterance queued, so a voice
  // front end knows whether to listen with the wake word: kCommand (the next conversation;
  // a long task may be running), kAnswer (a question waits for the answer: the loop's own
  // ask(), or a task's), kHeld (an utterance is held until the running task asks or ends).
  // Called on the loop thread or a task's thread, never with the loop's lock held; may
  // repeat. Set before run().
  enum class Waiting { kCommand, kAnswer, kHeld };
  void on_waiting(std::function<void(Waiting)> waiting) { waiting_ = std::move(waiting); }

  // Skill timers (marvin.after). Between utterances, run() asks `next` when the next timer
  // is due (host clock, Unix ms; nullopt: none, e.g. while a long task runs) and calls
  // `run(now)` once `now()` has reached it. Timers due when an utterance arrives, or at
  // end of input, run first; later ones are dropped at end of input. Set before run().
  struct Timers {
    std::function<std::optional<std::int64_t>()> next;
    std::function<void(std::int64_t)> run;
    std::function<std::int64_t()> now;
  };
  void set_timers(Timers timers) { timers_ = std::move(timers); }

  void post(std::string utterance);  // any thread
  void close();                      // end of input; any thread
  void shut_down();                  // stop now (see above); any thread
  // Makes a loop waiting between utterances ask Timers::next again now (any thread): how
  // the host gets work onto the loop thread, e.g. a skills reload (core/app/host.h).
  void wake();
  void run();                        // the host loop; returns after close() and the last task

  void say(std::string_view text) override;
  std::optional<std::string> ask(std::string_view question) override;
  void interrupt() override;
  void task_finished() override;

 private:
  // Waits for an utterance; nullopt at end of input. With `run_timers` (the loop's own
  // wait, not a question's), due skill timers run while it waits.
  std::optional<std::string> pop(bool run_timers = false);
  void run_due_timers();  // mutex_ not held
  void route(std::string line);
  // Stops the running task (stop(), or leave_task() with `leaving`), waits for it to end and
  // handles `line`. Called with `lock` held; route() returns right after.
  void take_over(std::unique_lock<std::mutex>& lock, const std::string& line, bool leaving);
  bool stop_queued() const;  // mutex_ held
  bool is_stop(const std::string& utterance) const;

  std::function<void(std::string_view)> speak_;
  std::function<void(std::string_view)> heard_;
  std::function<void(Waiting)> waiting_;
  void notify_waiting(std::unique_lock<std::mutex>& lock, Waiting what);  // unlocks meanwhile
  Timers timers_;
  std::mutex speak_mutex_;
  Manager* manager_ = nullptr;
  const interpret::Interpreter* interpreter_ = nullptr;
  std::thread::id loop_thread_;

  std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<std::string> input_;      // guarded by mutex_
  bool closed_ = false;                // guarded by mutex_
  bool shutting_down_ = false;         // guarded by mutex_: shut_down() was called
  bool interrupted_ = false;           // guarded by mutex_
  bool question_pending_ = false;      // guarded by mutex_: a worker waits in ask()
  bool holding_ = false;               // guarded by mutex_: the loop holds an utterance
  std::string question_;               // guarded by mutex_: what the pending question asks
  std::optional<std::string> answer_;  // guarded by mutex_
  // Guarded by mutex_: said to a question a task asked on the loop thread, taken as a new
  // request; run() routes it before the next line.
  std::optional<std::string> taken_next_;
  std::uint64_t events_ = 0;           // guarded by mutex_: bumped by every notification
};

}  // namespace marvin::skills
