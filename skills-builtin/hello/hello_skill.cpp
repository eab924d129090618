// Built-in skill "hello": answers a greeting, and says who Marvin is and what it can do
// ("hello" -> "Hello! What can I do for you?"; "who are you" -> a short introduction).
#include <marvin/skill.hpp>
#include <string>

namespace {

class HelloSkill : public marvin::Skill {
 public:
  using marvin::Skill::Skill;

  void handle(const marvin::Request& request) override {
    if (request.intent == "hello") {
      robot().say("Hello! What can I do for you?");
    } else if (request.intent == "about") {
      robot().say(
          "I'm Marvin, your home robot. I can tell you the time and the date, set reminders, "
          "alarms and timers, and read you your schedule. Just ask.");
    } else {
      throw marvin::Error(MARVIN_ERR_INVALID, "unknown intent '" + request.intent + "'");
    }
  }
};

}  // namespace

MARVIN_SKILL(HelloSkill, "hello")
