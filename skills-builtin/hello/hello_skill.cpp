// Built-in skill "hello": the courtesies, and who Marvin is and what it can do.
// "hello" -> "Hello! What can I do for you?"; "thank you" -> "You're welcome."; "goodbye" and
// "good night" get a goodbye; "who are you" or "what can you do" -> a short introduction
// naming what the built-in skills do.
#include <marvin/skill.hpp>
#include <string>

namespace {

class HelloSkill : public marvin::Skill {
 public:
  using marvin::Skill::Skill;

  void handle(const marvin::Request& request) override {
    if (request.intent == "hello") {
      robot().say(asks_how_i_am(request.utterance) ? "I'm fine, thank you. What can I do for you?"
                  : asks_if_i_hear(request.utterance) ? "Yes, I'm here. What can I do for you?"
                                                      : "Hello! What can I do for you?");
    } else if (request.intent == "thanks") {
      robot().say("You're welcome.");
    } else if (request.intent == "goodbye") {
      const bool night = request.utterance.find("night") != std::string::npos ||
                         request.utterance.find("sleep") != std::string::npos;
      robot().say(night ? "Good night. Sleep well."
                        : "Goodbye. Just say my name when you need me.");
    } else if (request.intent == "about") {
      robot().say(
          "I'm Marvin, your home robot. I can tell you the time, keep your reminders, timers "
          "and schedule, recognise the people you introduce to me, find people and things, "
          "keep watch while you're out, guide you through the house, switch lights and "
          "devices, and make phone calls. Just ask.");
    } else {
      throw marvin::Error(MARVIN_ERR_INVALID, "unknown intent '" + request.intent + "'");
    }
  }

 private:
  // "can you hear me", "are you there", "are you listening".
  static bool asks_if_i_hear(const std::string& utterance) {
    for (const char* question :
         {"hear me", "are you there", "are you listening", "are you awake"}) {
      if (utterance.find(question) != std::string::npos) return true;
    }
    return false;
  }

  // "how are you", "how's it going", "how have you been", "are you doing well".
  static bool asks_how_i_am(const std::string& utterance) {
    for (const char* question : {"how are", "how is it", "how's it", "how have you",
                                 "how do you do", "are you doing", "are you well", "are you ok"}) {
      if (utterance.find(question) != std::string::npos) return true;
    }
    return false;
  }
};

}  // namespace

MARVIN_SKILL(HelloSkill, "hello")
