// Built-in skill "hello": the courtesies, and who Marvin is and what it can do.
// "hello" -> "Hello! What can I do for you?"; "thank you" -> "You're welcome."; "goodbye" and
// "good night" get a goodbye; "who are you" or "what can you do" -> a short introduction
// naming what the built-in skills do. "Good morning" is answered with the greeting of the
// owner's time of day ("Good afternoon!" at 3 PM): someone who has lost track of the day hears
// it gently.
#include <date/tz.h>

#include <cctype>
#include <chrono>
#include <marvin/skill.hpp>
#include <string>

namespace {

class HelloSkill : public marvin::Skill {
 public:
  using marvin::Skill::Skill;

  void handle(const marvin::Request& request) override {
    if (request.intent == "hello") {
      const std::string greeting = says_good_time_of_day(request.utterance)
                                       ? greeting_for_now() + "! What can I do for you?"
                                       : "Hello! What can I do for you?";
      robot().say(asks_how_i_am(request.utterance) ? "I'm fine, thank you. What can I do for you?"
                  : asks_if_i_hear(request.utterance) ? "Yes, I'm here. What can I do for you?"
                                                      : greeting);
    } else if (request.intent == "thanks") {
      robot().say("You're welcome.");
    } else if (request.intent == "goodbye") {
      const bool night = request.utterance.find("night") != std::string::npos ||
                         request.utterance.find("sleep") != std::string::npos ||
                         request.utterance.find("bed") != std::string::npos;
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
  // "good morning", "Good afternoon, Marvin", "good evening".
  static bool says_good_time_of_day(const std::string& utterance) {
    std::string u;
    for (char c : utterance) u += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    for (const char* greeting : {"good morning", "good afternoon", "good evening"}) {
      if (u.find(greeting) != std::string::npos) return true;
    }
    return false;
  }

  // "Good morning" 5-12, "Good afternoon" 12-18, else "Good evening", in the owner's zone
  // (UTC when the zone is unknown).
  std::string greeting_for_now() {
    const date::time_zone* zone = nullptr;
    try {
      zone = date::locate_zone(robot().time_zone());
    } catch (const std::exception&) {
      zone = date::locate_zone("UTC");
    }
    const auto now =
        date::sys_time<std::chrono::milliseconds>{std::chrono::milliseconds{robot().now_ms()}};
    const auto local = zone->to_local(now);
    const auto hour =
        std::chrono::duration_cast<std::chrono::hours>(local - date::floor<date::days>(local))
            .count();
    if (hour >= 5 && hour < 12) return "Good morning";
    if (hour >= 12 && hour < 18) return "Good afternoon";
    return "Good evening";
  }

  // "can you hear me", "are you there", "are you listening".
  static bool asks_if_i_hear(const std::string& utterance) {
    // Only the name ("Marvin?", "OK Marvin"): someone wants my attention.
    std::string letters;
    for (char c : utterance) {
      if (std::isalpha(static_cast<unsigned char>(c)) || c == ' ') {
        letters += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
      }
    }
    while (!letters.empty() && letters.back() == ' ') letters.pop_back();
    for (const char* name : {"marvin", "ok marvin", "okay marvin"}) {
      if (letters == name) return true;
    }
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
