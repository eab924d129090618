#include "skills/host_loop.h"

#include <cctype>
#include <chrono>
#include <set>

namespace marvin::skills {

namespace {

// Whether a question asks yes or no, or to pick one of a few ("Shall I look again?", "Call
// Anna?", "Fan, light or thermostat?"): its last sentence ends with '?' and does not start
// with a question word. An open question ("What should I remind you of?") may be answered
// with words that happen to be a request ("call Tom"), so it always gets its answer.
bool closed_question(std::string_view question) {
  while (!question.empty() && std::isspace(static_cast<unsigned char>(question.back()))) {
    question.remove_suffix(1);
  }
  if (question.empty() || question.back() != '?') return false;
  question.remove_suffix(1);
  const std::size_t end_of_previous = question.find_last_of(".!?");
  if (end_of_previous != std::string_view::npos) question.remove_prefix(end_of_previous + 1);
  std::string first;
  for (char c : question) {
    if (std::isalpha(static_cast<unsigned char>(c))) {
      first += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    } else if (!first.empty()) {
      break;
    }
  }
  static const std::set<std::string, std::less<>> kQuestionWords = {
      "what", "which", "who", "whom", "whose", "where", "when", "why", "how"};
  return !first.empty() && !kQuestionWords.contains(first);
}

// Whether `answer` says a word of `question` ("The bedroom thermostat or the living room
// thermostat?" "the bedroom one"): then it answers, however much it also reads as a request.
// Short words and articles say nothing of which option was picked.
bool shares_a_word(std::string_view answer, std::string_view question) {
  auto words = [](std::string_view text) {
    std::set<std::string, std::less<>> out;
    std::string word;
    for (std::size_t i = 0; i <= text.size(); ++i) {
      const char c = i < text.size() ? text[i] : ' ';
      if (std::isalnum(static_cast<unsigned char>(c))) {
        word += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
      } else if (!word.empty()) {
        if (word.size() >= 3 && word != "the" && word != "and" && word != "one" &&
            word != "you" && word != "your") {
          out.insert(word);
        }
        word.clear();
      }
    }
    return out;
  };
  const auto asked = words(question);
  for (const std::string& w : words(answer)) {
    if (asked.contains(w)) return true;
  }
  return false;
}

// Whether the user, asked `question`, moved on with `line` instead of answering: a request
// said word for word, or one the model is sure of that names nothing the question offered,
// to a yes-or-no or pick-one question.
bool moves_on(Manager::Standing standing, std::string_view line, std::string_view question) {
  if (!closed_question(question)) return false;
  return standing == Manager::Standing::kRequest ||
         (standing == Manager::Standing::kLikely && !shares_a_word(line, question));
}

}  // namespace

HostLoop::HostLoop(std::function<void(std::string_view)> speak) : speak_(std::move(speak)) {}

void HostLoop::attach(Manager& manager, const interpret::Interpreter& interpreter) {
  manager_ = &manager;
  interpreter_ = &interpreter;
}

void HostLoop::post(std::string utterance) {
  {
    std::lock_guard lock(mutex_);
    input_.push_back(std::move(utterance));
    ++events_;
  }
  changed_.notify_all();
}

void HostLoop::close() {
  {
    std::lock_guard lock(mutex_);
    closed_ = true;
    ++events_;
  }
  changed_.notify_all();
}

void HostLoop::shut_down() {
  {
    std::lock_guard lock(mutex_);
    input_.clear();
    closed_ = true;
    shutting_down_ = true;
    interrupted_ = true;  // a question pending or asked from now on gets no answer
    ++events_;
  }
  changed_.notify_all();
}

void HostLoop::wake() {
  {
    std::lock_guard lock(mutex_);
    ++events_;
  }
  changed_.notify_all();
}

void HostLoop::interrupt() {
  {
    std::lock_guard lock(mutex_);
    interrupted_ = true;
    ++events_;
  }
  changed_.notify_all();
}

void HostLoop::say(std::string_view text) {
  std::lock_guard lock(speak_mutex_);
  speak_(text);
}

bool HostLoop::is_stop(const std::string& utterance) const {
  return interpreter_ && interpreter_->builtin(utterance) == interpret::Builtin::kStop;
}

void HostLoop::run_due_timers() {
  if (!timers_.next || !timers_.run || !timers_.now) return;
  std::optional<std::int64_t> next = timers_.next();
  if (!next) return;
  std::int64_t now = timers_.now();
  if (*next <= now) timers_.run(now);
}

void HostLoop::notify_waiting(std::unique_lock<std::mutex>& lock, Waiting what) {
  if (!waiting_) return;
  lock.unlock();
  waiting_(what);
  lock.lock();
}

std::optional<std::string> HostLoop::pop(bool run_timers) {
  std::unique_lock lock(mutex_);
  if (run_timers && timers_.next && timers_.run && timers_.now) {
    for (;;) {
      // Due timers first (also when an utterance or the end of input is already here).
      const std::uint64_t seen = events_;
      lock.unlock();
      run_due_timers();
      std::optional<std::int64_t> next = timers_.next();
      std::int64_t now = timers_.now();
      lock.lock();
      if (!input_.empty() || closed_) break;
      // A post() while unlocked bumps events_, so the wait below returns at once.
      notify_waiting(lock, question_pending_ ? Waiting::kAnswer : Waiting::kCommand);
      auto woken = [&] { return events_ != seen; };
      if (next) {
        changed_.wait_for(lock, std::chrono::milliseconds(*next - now), woken);
      } else {
        changed_.wait(lock, woken);
      }
    }
  } else {
    if (input_.empty() && !closed_) {
      notify_waiting(lock, run_timers && !question_pending_ ? Waiting::kCommand : Waiting::kAnswer);
    }
    changed_.wait(lock, [&] { return !input_.empty() || closed_; });
  }
  if (input_.empty()) return std::nullopt;
  std::string line = std::move(input_.front());
  input_.pop_front();
  holding_ = true;
  lock.unlock();
  changed_.notify_all();
  if (heard_) heard_(line);
  return line;
}

std::optional<std::string> HostLoop::ask(std::string_view question) {
  {
    std::lock_guard lock(mutex_);
    if (interrupted_) return std::nullopt;
  }
  const bool on_loop = std::this_thread::get_id() == loop_thread_;
  if (!on_loop) {
    // Pending before it is said: an answer typed as soon as the question shows is never
    // taken for a "no" to the task (route()).
    std::lock_guard lock(mutex_);
    question_pending_ = true;
    question_ = question;
    answer_.reset();
  }
  say(question);
  if (on_loop) {
    // Nested on the loop thread: the next utterance is the answer.
    std::optional<std::string> line = pop();
    if (!line) return std::nullopt;
    {
      std::lock_guard lock(mutex_);
      holding_ = false;
    }
    if (is_stop(*line)) {
      if (manager_) manager_->stop();
      return std::nullopt;
    }
    // As route() does for a task on a worker: a call for help is no answer, and a request
    // said to a yes-or-no or pick-one question ("The bedroom thermostat or the living room
    // thermostat?" "Make it warmer.") leaves the task. The line is taken next.
    const Manager::Standing standing =
        manager_ ? manager_->standing(*line) : Manager::Standing::kNone;
    if (standing == Manager::Standing::kUrgent || moves_on(standing, *line, question)) {
      {
        std::lock_guard lock(mutex_);
        taken_next_ = std::move(*line);
      }
      if (standing == Manager::Standing::kUrgent) {
        manager_->stop();
      } else {
        manager_->leave_task();
      }
      return std::nullopt;
    }
    return line;
  }
  // On a worker: the loop delivers the answer (or "stop" interrupts).
  std::unique_lock lock(mutex_);
  changed_.notify_all();  // a held utterance may be the answer
  if (input_.empty() && !holding_ && !closed_) notify_waiting(lock, Waiting::kAnswer);
  changed_.wait(lock, [&] {
    return answer_.has_value() || interrupted_ || (closed_ && input_.empty() && !holding_);
  });
  question_pending_ = false;
  std::optional<std::string> answer = std::move(answer_);
  answer_.reset();
  return answer;
}

void HostLoop::task_finished() {
  {
    std::lock_guard lock(mutex_);
    ++events_;
  }
  changed_.notify_all();
}

bool HostLoop::stop_queued() const {
  for (const std::string& line : input_) {
    if (is_stop(line)) return true;
  }
  return false;
}

void HostLoop::take_over(std::unique_lock<std::mutex>& lock, const std::string& line,
                         bool leaving) {
  holding_ = false;
  lock.unlock();
  if (leaving) {
    manager_->leave_task();
  } else {
    manager_->stop();
  }
  while (!manager_->wait_idle(std::chrono::hours{1})) {
  }
  lock.lock();
  if (shutting_down_) return;
  interrupted_ = false;  // a new conversation starts
  lock.unlock();
  manager_->handle(line);
}

void HostLoop::route(std::string line) {
  // A call for help while a task runs or asks: the task is stopped, not waited for, and the
  // call is no answer to its question. Checked unlocked: the interpreter takes a while.
  // A request said in answer to a task's yes-or-no question ("Shall I look again?" "What
  // time is it?") declines it and is taken: the user has moved on.
  const Manager::Standing standing = manager_ && manager_->busy() ? manager_->standing(line)
                                                                  : Manager::Standing::kNone;
  const bool urgent = standing == Manager::Standing::kUrgent;
  std::unique_lock lock(mutex_);
  if (shutting_down_) {  // taken just before shut_down(): dropped with the rest
    holding_ = false;
    return;
  }
  if (urgent) return take_over(lock, line, false);
  if (!manager_ || is_stop(line)) {
    holding_ = false;
    lock.unlock();
    if (manager_) manager_->handle(line);
    return;
  }
  // "No" while a task runs and asks nothing ("find Anna" ... "no"): stop it, as "stop" does,
  // instead of holding it until the task ends to answer "I wasn't asking anything".
  if (!question_pending_ && manager_->busy() && interpreter_ &&
      interpreter_->builtin(line) == interpret::Builtin::kNo) {
    holding_ = false;
    lock.unlock();
    manager_->stop();
    return;
  }
  bool told_held = false;
  for (;;) {
    if (!told_held && !question_pending_ && manager_->busy() && !stop_queued()) {
      told_held = true;
      notify_waiting(lock, Waiting::kHeld);
    }
    changed_.wait(lock, [&] {
      return shutting_down_ || question_pending_ || !manager_->busy() || stop_queued();
    });
    // Also a request held from before the question: a task's yes or no is not given by
    // something the user said before hearing the question.
    if (question_pending_ && !shutting_down_ && moves_on(standing, line, question_)) {
      question_pending_ = false;
      return take_over(lock, line, true);
    }
    if (question_pending_ && !shutting_down_) {
      answer_ = std::move(line);
      // Answered: the next utterance is not an answer too, even when it comes before the
      // task has woken to take this one (piped lines, quick speech).
      question_pending_ = false;
      holding_ = false;
      lock.unlock();
      changed_.notify_all();
      return;
    }
    if (!manager_->busy() || shutting_down_) break;
    // A "stop" behind the held utterance goes first.
    for (auto it = input_.begin(); it != input_.end(); ++it) {
      if (is_stop(*it)) {
        std::string stop = std::move(*it);
        input_.erase(it);
        lock.unlock();
        if (heard_) heard_(stop);
        manager_->handle(stop);
        lock.lock();
        break;
      }
    }
  }
  holding_ = false;
  if (shutting_down_) return;  // the held utterance goes with the rest
  interrupted_ = false;        // a new conversation starts
  lock.unlock();
  manager_->handle(line);
}

void HostLoop::run() {
  loop_thread_ = std::this_thread::get_id();
  for (;;) {
    std::optional<std::string> line;
    {
      std::lock_guard lock(mutex_);
      if (taken_next_) {  // said to a question asked on this thread, and taken as a request
        line = std::move(taken_next_);
        taken_next_.reset();
        holding_ = true;
      }
    }
    if (!line) line = pop(true);
    if (!line) break;
    route(std::move(*line));
  }
  // End of input: a running task finishes (its questions get no answer). After
  // shut_down() it is stopped; no task starts after the loop above has ended, so one
  // that is not busy here will not be.
  bool stop = false;
  {
    std::lock_guard lock(mutex_);
    stop = shutting_down_;
  }
  if (manager_ && stop && manager_->busy()) manager_->stop();
  if (manager_) {
    while (!manager_->wait_idle(std::chrono::hours{1})) {
    }
  }
}

}  // namespace marvin::skills
