// The skill manager: turns what the user said into a skill's action, one conversation at
// a time.
//
// For each utterance handle():
//   1. "stop"/"cancel" always wins: it cancels the running task (its pending question, its
//      motion, its is_cancelled() flag) and answers "OK.". "repeat" says the last sentence
//      again. "Speak slower", "louder" change the voice (on_voice_style).
//   2. While a long task runs, anything else is answered "I'm still busy ..." (one
//      conversation at a time). The host loop delivers answers to a task's question before
//      calling handle(), see HostLoop.
//   3. The interpreter matches the utterance. No match is answered with a helpful
//      sentence naming something the robot can do, never with a guess.
//   4. Each required slot the user did not say is asked for with the manifest's question
//      and parsed with the slot's type; a bad answer is asked again once, then the manager
//      gives up politely.
//   5. Intents marked "confirm" ask their confirmation question; only "yes" goes ahead.
//   6. The skill runs: "short" intents on the calling thread (the host loop), "long" ones
//      on a worker thread with the intent's time limit, cancellable by "stop".
//   7. A failure or exception of the skill is logged (and recorded as an event) and
//      answered with an apology; the host keeps running.
//
// The manager is also the User its skills talk to (install it as HostServices::user): it
// forwards to the real User and remembers the last sentence for "repeat".
//
// Threading: handle() is called by one thread (the host loop). stop(), busy() and
// wait_idle() may be called from any thread. Status lights go to HostServices::body when
// there is one: executing while a skill acts, awaiting otherwise.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "interpret/voice_change.h"
#include "skills/registry.h"
#include "skills/user.h"

namespace marvin::skills {

struct ManagerOptions {
  // Run "long" intents on the calling thread too: the SkillHarness uses this so tests
  // have no threads to wait for. Time limits then do not apply.
  bool run_long_inline = false;
};

class Manager : public User {
 public:
  // `registry` and `user` must outlive the manager.
  Manager(Registry& registry, User& user, ManagerOptions options = {});
  ~Manager() override;  // cancels a running task and waits for it
  Manager(const Manager&) = delete;
  Manager& operator=(const Manager&) = delete;

  // Acts on one utterance. The host loop's thread only.
  void handle(std::string_view utterance);
  // Cancels the running task or dialogue and answers "OK.". Any thread.
  void stop();
  // What "stop" also ends (a phone call): the hook gets the id of the skill whose task runs
  // ("" when none), ends what it stands for and returns what to say instead of "OK."
  // ("" when there was nothing to end; ignored while a task runs: "OK, I stopped.").
  // Set before use.
  void on_stop(std::function<std::string(const std::string& running_skill)> hook) {
    stop_hook_ = std::move(hook);
  }
  // How Marvin speaks, changed by "speak slower", "louder", "I can't hear you"
  // (interpret/voice_change.h): steps away from the host's own rate and volume, each within
  // [-kVoiceSteps, kVoiceSteps]. The hook applies them (the voice host: on its next turn);
  // without one (typed text) there is no voice to change, and the manager says so. The hook
  // is called on the host loop's thread. Set before use.
  struct VoiceStyle {
    int rate_steps = 0;
    int volume_steps = 0;
    bool operator==(const VoiceStyle&) const = default;
  };
  static constexpr int kVoiceSteps = 3;
  void on_voice_style(std::function<void(VoiceStyle)> hook) { voice_hook_ = std::move(hook); }
  VoiceStyle voice_style() const { return voice_style_; }  // the host loop's thread

  // What `utterance` is while a task runs, read once: kRequest when it is, word for word, a
  // request of some skill (a template at full confidence) and no word of the dialogue (yes,
  // no, stop); kLikely when the intent model alone is sure of one ("turn the heating up to
  // 21"); kUrgent when a word-for-word request's intent is marked "urgent" (a call for help)
  // and the task running, if any, is not one, so the host loop lets it stop that task. The
  // host loop's thread only.
  enum class Standing { kNone, kRequest, kLikely, kUrgent };
  Standing standing(std::string_view utterance) const;
  // The user answered the running task's yes-or-no question with a new request: the task is
  // stopped as by stop(), but Marvin says "OK, I'll leave that." (any thread).
  void leave_task();

  // True while a long task runs on the worker.
  bool busy() const;
  // Waits until no long task runs; false if `timeout` passed first.
  bool wait_idle(std::chrono::milliseconds timeout);
  // True when no long task runs, after joining the finished task's threads: from then on
  // nothing but the caller touches a LoadedSkill, so the registry may unload skills. The
  // host loop's thread only (like handle()).
  bool idle();

  // User, for the skills (forwarded to the real user).
  void say(std::string_view text) override;
  std::optional<std::string> ask(std::string_view question) override;
  void interrupt() override { user_.interrupt(); }
  void task_finished() override { user_.task_finished(); }

  // The interpreter's view of the world now: clock, time zone, contact names.
  interpret::Context context() const;

 private:
  std::function<std::string(const std::string&)> stop_hook_;
  std::function<void(VoiceStyle)> voice_hook_;
  VoiceStyle voice_style_;  // the host loop's thread
  void change_voice(interpret::VoiceChange change);
  void end_task(bool leaving);  // stop() and leave_task()
  bool fill_slots(const IntentDecl& intent, interpret::Match& match, std::string_view utterance);
  bool confirm(const IntentDecl& intent, const interpret::Match& match);
  // "Did you want a reminder or your schedule?": the chosen reading, or nullopt after "no",
  // "stop" or an answer naming neither.
  std::optional<interpret::Match> clarify(const std::vector<interpret::Match>& choices);
  // An answer to the manager's own question (a slot, yes or no, which of two) that does not
  // answer it but is a request word for word ("When should I remind you?" "What's on my
  // calendar this week?"): the question is dropped and handle() takes it next. True then.
  bool takes_as_request(const std::string& answer);
  void handle_next_request();               // handle() of it, if there is one
  std::optional<std::string> next_request_;  // the host loop's thread
  // How the user would name an intent: its "description", else skill name and intent.
  std::string describe(const interpret::Match& match) const;
  void run(LoadedSkill& skill, const IntentDecl& intent, const interpret::Match& match,
           std::string utterance);
  void execute(LoadedSkill& skill, const std::string& intent, const std::string& slots_json,
               const std::string& utterance, bool timed);
  void report(LoadedSkill& skill, const std::string& intent, marvin_status status,
              const std::string& error);
  void light(int which);
  void join_finished();
  // "Sorry, I don't know how to help with that." and a request the user could make instead,
  // from the next skill each time: the same example after every refusal teaches nothing.
  std::string no_match_sentence();

  Registry& registry_;
  User& user_;
  ManagerOptions options_;

  mutable std::mutex mutex_;
  std::condition_variable changed_;
  bool busy_ = false;               // guarded by mutex_
  bool timed_out_ = false;          // guarded by mutex_
  bool cancelled_ = false;          // guarded by mutex_: "stop" during this conversation
  LoadedSkill* running_ = nullptr;  // guarded by mutex_: the skill acting now
  std::string running_stopped_;     // guarded by mutex_: its intent's "stopped" sentence
  bool running_urgent_ = false;     // guarded by mutex_: its intent is "urgent"
  std::string last_said_;           // guarded by mutex_
  std::atomic<std::size_t> refusals_{0};  // refusals so far
  std::thread worker_;
  std::thread watchdog_;
};

}  // namespace marvin::skills
