// The person the robot talks to, as the skill manager and the skills reach them.
//
// The host implements it with its console or its voice loop (see HostLoop), the SDK's
// MockRobot with a transcript and a queue of scripted answers.
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace marvin::skills {

class User {
 public:
  virtual ~User() = default;
  // Speaks `text`. Returns once the sentence is queued for speaking.
  virtual void say(std::string_view text) = 0;
  // Speaks `question` and waits for the answer. nullopt when the user said "stop", the
  // task was cancelled, or no answer can come (end of input).
  virtual std::optional<std::string> ask(std::string_view question) = 0;
  // Wakes a pending ask() on any thread, which then returns nullopt. Called on "stop".
  virtual void interrupt() {}
  // A long task has finished (the host loop may go on with held input). Any thread.
  virtual void task_finished() {}
};

}  // namespace marvin::skills
